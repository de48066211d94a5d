#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace pavilion::sim {

// A fixed set of worker threads for the per-robot work of a tick (scans,
// localization, later navigation). ParallelFor(n, fn) calls fn(0) ... fn(n-1),
// each exactly once, spread over the workers and the calling thread, and
// returns when all are done. Determinism is the caller's part and is cheap to
// keep: fn(i) reads only what no call writes (the tick's immutable snapshot)
// and writes only its own slot i, and every random draw comes from a stream
// owned by item i; results are then merged in index order. Which thread runs
// which index never matters.
class WorkerPool {
 public:
  // `threads` >= 1 in total, the calling thread included (1: no workers, every
  // call runs inline). Throws std::invalid_argument for threads < 1.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // Runs fn(i) for i in [0, n). If calls throw, the exception of the lowest
  // index is rethrown after all calls have finished (the others are dropped),
  // so failures are reported the same way for any thread count (one thread
  // stops at the first failure instead of making the later calls). Not
  // reentrant: fn must not call ParallelFor on the same pool.
  void ParallelFor(std::size_t n, const std::function<void(std::size_t)>& fn);

  // The number of hardware threads (at least 1): the default of --threads.
  static int HardwareThreads();

 private:
  void WorkerLoop();
  // Takes indices of the current job until none is left.
  void Drain();
  // Waits up to spin_s_ without sleeping for `ready` to hold (true when it does).
  template <typename Ready>
  bool Spin(Ready ready) const;
  // Sets published_done_ from the job's counts (under mutex_).
  void PublishDone();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable work_done_;
  bool stopping_ = false;
  std::size_t generation_ = 0;  // incremented per job, so workers see each job once
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t count_ = 0;
  std::size_t next_ = 0;      // next index to hand out
  std::size_t finished_ = 0;  // indices completed
  std::size_t busy_workers_ = 0;
  std::size_t error_index_ = 0;
  std::exception_ptr error_;
  // Copies of generation_, stopping_ and (finished_ == count_ && no busy
  // worker), written under mutex_, read without it while spinning.
  std::atomic<std::size_t> published_generation_{0};
  std::atomic<bool> published_stopping_{false};
  std::atomic<bool> published_done_{false};
  // How long a thread spins for the next job or the job's end before it
  // sleeps on a condition variable: a tick's serial part is a few hundred
  // microseconds, and waking a sleeping thread costs tens. 0 (always sleep)
  // when there are more threads than the hardware runs at once.
  double spin_s_ = 0.0;
};

}  // namespace pavilion::sim
