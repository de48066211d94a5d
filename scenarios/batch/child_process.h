#pragma once

// Child processes for the batch commands (`pavilion sweep`, `pavilion test`): a
// list of command lines run as separate processes, a few at a time, each with
// its stdout and stderr in files, stopped cleanly on Ctrl-C. POSIX (Linux).

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace pavilion::scenarios {

// One process to run. argv[0] is a path, or a name looked up in PATH. An empty
// stdout_path / stderr_path sends that stream to /dev/null; the files are
// created or truncated (their folder must exist). stdin is /dev/null.
struct ChildJob {
  std::vector<std::string> argv;
  std::string stdout_path;
  std::string stderr_path;
};

// How a child ended. exit_code is -1 unless it exited (then signal is 0);
// signal is the number that killed it, else 0. 127: it could not be started
// (the reason is in its stderr file). interrupted: this call was stopped by a
// signal while the job ran (it was sent SIGTERM) or before it started (then it
// never ran: exit_code -1, signal 0, wall_s 0).
struct ChildResult {
  int exit_code = -1;
  int signal = 0;
  double wall_s = 0.0;
  bool interrupted = false;
};

// Seconds a child has to exit after SIGTERM before it gets SIGKILL.
inline constexpr double kChildTerminateGraceS = 5.0;

// Runs the jobs with at most `jobs` at a time (values < 1 count as 1), started
// in order of index; on_done(index, result) is called on the calling thread as
// each finishes (completion order), exactly once per job. Each child runs in
// its own process group (a terminal's Ctrl-C reaches this process only) and,
// on Linux, gets SIGTERM should this process die.
// On SIGINT/SIGTERM to this process (handlers installed for the duration of the
// call, restored after), running children get SIGTERM (SIGKILL after
// kChildTerminateGraceS, or at a second signal), pending jobs are not started,
// their results are {interrupted = true}, and the function returns the signal
// number that stopped it (0 when all ran). Not reentrant: one call at a time
// per process. Throws std::runtime_error when a job's output file cannot be
// created or a process cannot be forked (running children are killed first).
int RunChildren(const std::vector<ChildJob>& jobs_list, int jobs,
                const std::function<void(std::size_t, const ChildResult&)>& on_done);

// The last `max_lines` lines of a text file (for crash reports), each ending in
// '\n'; empty if unreadable. Reads at most the file's last 64 KiB.
std::string TailOfFile(const std::string& path, int max_lines = 20);

// The path of the running executable (/proc/self/exe), to run `pavilion run`
// children. Throws std::runtime_error when it cannot be read.
std::string SelfExecutable();

}  // namespace pavilion::scenarios
