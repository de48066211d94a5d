#include "scenarios/batch/child_process.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace pavilion::scenarios {
namespace {

using Clock = std::chrono::steady_clock;

// How long the wait loop sleeps at most between checks of the kill deadline.
constexpr int kPollIntervalMs = 100;
// The part of a file TailOfFile reads.
constexpr std::streamoff kTailBytes = 64 * 1024;
constexpr int kExitCannotStart = 127;

// Set by the signal handlers; read by the wait loop.
volatile std::sig_atomic_t g_stop_signal = 0;   // the first SIGINT/SIGTERM received
volatile std::sig_atomic_t g_stop_signals = 0;  // how many were received
int g_wake_fd = -1;                             // write end of the self-pipe

void WakeWaitLoop() {
  const int saved_errno = errno;
  if (g_wake_fd >= 0) {
    const char byte = 0;
    const ssize_t written = ::write(g_wake_fd, &byte, 1);
    (void)written;  // a full pipe already wakes the loop
  }
  errno = saved_errno;
}

void OnStopSignal(int signal_number) {
  if (g_stop_signal == 0) g_stop_signal = signal_number;
  g_stop_signals = g_stop_signals + 1;
  WakeWaitLoop();
}

void OnChildSignal(int) { WakeWaitLoop(); }

// Installs the handlers of SIGINT, SIGTERM and SIGCHLD and a self-pipe that
// wakes Wait(); restores the previous handlers when it goes.
class SignalScope {
 public:
  SignalScope() {
    if (::pipe2(pipe_, O_CLOEXEC | O_NONBLOCK) != 0) {
      throw std::runtime_error(std::string("cannot create a pipe: ") + std::strerror(errno));
    }
    g_stop_signal = 0;
    g_stop_signals = 0;
    g_wake_fd = pipe_[1];
    Install(SIGINT, OnStopSignal, &old_int_);
    Install(SIGTERM, OnStopSignal, &old_term_);
    Install(SIGCHLD, OnChildSignal, &old_chld_);
  }
  ~SignalScope() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
    ::sigaction(SIGCHLD, &old_chld_, nullptr);
    g_wake_fd = -1;
    ::close(pipe_[0]);
    ::close(pipe_[1]);
  }
  SignalScope(const SignalScope&) = delete;
  SignalScope& operator=(const SignalScope&) = delete;

  // Sleeps until a signal arrives or timeout_ms pass.
  void Wait(int timeout_ms) {
    pollfd p{pipe_[0], POLLIN, 0};
    ::poll(&p, 1, timeout_ms);
    char buffer[64];
    while (::read(pipe_[0], buffer, sizeof buffer) > 0) {
    }
  }

 private:
  static void Install(int signal_number, void (*handler)(int), struct sigaction* old) {
    struct sigaction action {};
    action.sa_handler = handler;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART | (signal_number == SIGCHLD ? SA_NOCLDSTOP : 0);
    ::sigaction(signal_number, &action, old);
  }

  int pipe_[2] = {-1, -1};
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
  struct sigaction old_chld_ {};
};

// A file descriptor closed when it goes.
class Fd {
 public:
  explicit Fd(int fd = -1) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

int OpenOutput(const std::string& path) {
  const char* name = path.empty() ? "/dev/null" : path.c_str();
  const int fd = ::open(name, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    throw std::runtime_error("cannot create " + std::string(name) + ": " + std::strerror(errno));
  }
  return fd;
}

// In the forked child: only async-signal-safe calls until exec.
[[noreturn]] void ExecChild(char* const* argv, int in_fd, int out_fd, int err_fd, pid_t parent) {
  ::setpgid(0, 0);
#ifdef __linux__
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(kExitCannotStart);
#else
  (void)parent;
#endif
  if (::dup2(in_fd, 0) < 0 || ::dup2(out_fd, 1) < 0 || ::dup2(err_fd, 2) < 0) {
    ::_exit(kExitCannotStart);
  }
  ::signal(SIGINT, SIG_DFL);
  ::signal(SIGTERM, SIG_DFL);
  ::signal(SIGCHLD, SIG_DFL);
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  ::execvp(argv[0], argv);
  const char* message = "cannot start the program: ";
  const char* reason = std::strerror(errno);
  ssize_t w = ::write(2, message, std::strlen(message));
  w = ::write(2, reason, std::strlen(reason));
  w = ::write(2, "\n", 1);
  (void)w;
  ::_exit(kExitCannotStart);
}

// Forks and execs one job; its pid.
pid_t StartChild(const ChildJob& job) {
  if (job.argv.empty()) throw std::runtime_error("a child job has an empty command line");
  std::vector<char*> argv;
  for (const std::string& a : job.argv) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const Fd in(::open("/dev/null", O_RDONLY | O_CLOEXEC));
  const Fd out(OpenOutput(job.stdout_path));
  const Fd err_own(job.stderr_path == job.stdout_path && !job.stdout_path.empty()
                       ? -1
                       : OpenOutput(job.stderr_path));
  const int err_fd = err_own.get() >= 0 ? err_own.get() : out.get();
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(std::string("cannot fork: ") + std::strerror(errno));
  if (pid == 0) ExecChild(argv.data(), in.get(), out.get(), err_fd, parent);
  ::setpgid(pid, pid);  // also here, so that the group exists before any kill
  return pid;
}

// Sends a signal to a child's process group (to the child alone if that fails).
void SignalChild(pid_t pid, int signal_number) {
  if (::kill(-pid, signal_number) != 0) ::kill(pid, signal_number);
}

ChildResult ResultOf(int status, Clock::time_point start, bool interrupted) {
  ChildResult r;
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  r.interrupted = interrupted;
  return r;
}

struct RunningChild {
  pid_t pid;
  std::size_t index;
  Clock::time_point start;
};

// The children started and not yet reaped; killed and reaped when it goes
// early (an exception from on_done or from starting a child).
class RunningSet {
 public:
  ~RunningSet() {
    for (const RunningChild& c : children_) {
      SignalChild(c.pid, SIGKILL);
      int status = 0;
      while (::waitpid(c.pid, &status, 0) < 0 && errno == EINTR) {
      }
    }
  }
  std::vector<RunningChild>& children() { return children_; }

 private:
  std::vector<RunningChild> children_;
};

// The scheduling loop of RunChildren.
class ChildRunner {
 public:
  ChildRunner(const std::vector<ChildJob>& jobs_list, int jobs,
              const std::function<void(std::size_t, const ChildResult&)>& on_done)
      : jobs_list_(jobs_list),
        max_running_(static_cast<std::size_t>(std::max(1, jobs))),
        on_done_(on_done) {}

  int Run() {
    SignalScope signals;
    while (true) {
      HandleSignals();
      while (!terminating_ && running_.children().size() < max_running_ &&
             next_ < jobs_list_.size()) {
        running_.children().push_back({StartChild(jobs_list_[next_]), next_, Clock::now()});
        ++next_;
      }
      if (ReapFinished()) continue;
      if (running_.children().empty() && (terminating_ || next_ == jobs_list_.size())) break;
      signals.Wait(kPollIntervalMs);
    }
    if (terminating_) {
      ChildResult never_started;
      never_started.interrupted = true;
      for (; next_ < jobs_list_.size(); ++next_) on_done_(next_, never_started);
    }
    return static_cast<int>(g_stop_signal);
  }

 private:
  // SIGTERM to every child at the first stop signal; SIGKILL after the grace
  // period or at a further signal.
  void HandleSignals() {
    if (g_stop_signal != 0 && !terminating_) {
      terminating_ = true;
      signals_seen_ = g_stop_signals;
      kill_at_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(kChildTerminateGraceS));
      for (const RunningChild& c : running_.children()) SignalChild(c.pid, SIGTERM);
    }
    if (terminating_ && !killed_ && (Clock::now() >= kill_at_ || g_stop_signals != signals_seen_)) {
      killed_ = true;
      for (const RunningChild& c : running_.children()) SignalChild(c.pid, SIGKILL);
    }
  }

  // Reaps the children that ended and reports them; whether any had.
  bool ReapFinished() {
    auto& children = running_.children();
    for (std::size_t k = 0; k < children.size(); ++k) {
      int status = 0;
      const pid_t got = ::waitpid(children[k].pid, &status, WNOHANG);
      if (got != children[k].pid) continue;
      const RunningChild done = children[k];
      children.erase(children.begin() + static_cast<std::ptrdiff_t>(k));
      on_done_(done.index, ResultOf(status, done.start, terminating_));
      return true;
    }
    return false;
  }

  const std::vector<ChildJob>& jobs_list_;
  const std::size_t max_running_;
  const std::function<void(std::size_t, const ChildResult&)>& on_done_;
  RunningSet running_;
  std::size_t next_ = 0;
  bool terminating_ = false;
  bool killed_ = false;
  std::sig_atomic_t signals_seen_ = 0;
  Clock::time_point kill_at_{};
};

}  // namespace

int RunChildren(const std::vector<ChildJob>& jobs_list, int jobs,
                const std::function<void(std::size_t, const ChildResult&)>& on_done) {
  ChildRunner runner(jobs_list, jobs, on_done);
  return runner.Run();
}

std::string TailOfFile(const std::string& path, int max_lines) {
  if (max_lines <= 0) return "";
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return "";
  const std::streamoff size = in.tellg();
  const std::streamoff from = std::max<std::streamoff>(0, size - kTailBytes);
  in.seekg(from);
  std::string text(static_cast<std::size_t>(size - from), '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (from > 0) {  // drop the partial first line
    const std::size_t first = text.find('\n');
    text = first == std::string::npos ? std::string() : text.substr(first + 1);
  }
  if (!text.empty() && text.back() != '\n') text += '\n';
  std::size_t begin = text.size();
  for (int lines = 0; begin > 0 && lines < max_lines; ++lines) {
    const std::size_t previous = text.rfind('\n', begin >= 2 ? begin - 2 : 0);
    begin = previous == std::string::npos || begin < 2 ? 0 : previous + 1;
  }
  return text.substr(begin);
}

std::string SelfExecutable() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot read /proc/self/exe: " + ec.message());
  return self.string();
}

}  // namespace pavilion::scenarios
