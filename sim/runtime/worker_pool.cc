#include "sim/runtime/worker_pool.h"

#include <chrono>
#include <stdexcept>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace pavilion::sim {
namespace {

// Spin budget per wait (s); measured on the 2-core machine kind (expo_day,
// docs/benchmarks.md): ticks run a few hundred microseconds apart at ~17x.
constexpr double kSpinS = 300e-6;
// Pauses between clock reads while spinning.
constexpr int kPausesPerClockRead = 64;

void Pause() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace

template <typename Ready>
bool WorkerPool::Spin(Ready ready) const {
  if (spin_s_ <= 0.0) return ready();
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(spin_s_);
  while (true) {
    for (int k = 0; k < kPausesPerClockRead; ++k) {
      if (ready()) return true;
      Pause();
    }
    if (std::chrono::steady_clock::now() >= until) return ready();
  }
}

WorkerPool::WorkerPool(int threads) {
  if (threads < 1) throw std::invalid_argument("WorkerPool: threads must be >= 1");
  spin_s_ = threads <= HardwareThreads() ? kSpinS : 0.0;
  workers_.reserve(static_cast<std::size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) workers_.emplace_back([this] { WorkerLoop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    published_stopping_.store(true, std::memory_order_release);
  }
  work_ready_.notify_all();
  for (std::thread& t : workers_) t.join();
}

int WorkerPool::HardwareThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

void WorkerPool::ParallelFor(std::size_t n, const std::function<void(std::size_t)>& fn) {
  if (n == 0) return;
  if (workers_.empty() || n == 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &fn;
    count_ = n;
    next_ = 0;
    finished_ = 0;
    error_ = nullptr;
    ++generation_;
    published_done_.store(false, std::memory_order_relaxed);
    published_generation_.store(generation_, std::memory_order_release);
  }
  work_ready_.notify_all();
  Drain();
  Spin([this] { return published_done_.load(std::memory_order_acquire); });
  std::unique_lock<std::mutex> lock(mutex_);
  // Every index finished and no worker still inside the job (it may be about
  // to read job_), then the job is over.
  work_done_.wait(lock, [this] { return finished_ == count_ && busy_workers_ == 0; });
  job_ = nullptr;
  if (error_) {
    std::exception_ptr e = error_;
    error_ = nullptr;
    std::rethrow_exception(e);
  }
}

void WorkerPool::PublishDone() {
  published_done_.store(finished_ == count_ && busy_workers_ == 0, std::memory_order_release);
}

void WorkerPool::Drain() {
  while (true) {
    std::size_t i;
    const std::function<void(std::size_t)>* job;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (next_ >= count_) return;
      i = next_++;
      job = job_;
    }
    std::exception_ptr failure;
    try {
      (*job)(i);
    } catch (...) {
      failure = std::current_exception();
    }
    bool all_done;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (failure && (!error_ || i < error_index_)) {
        error_ = failure;
        error_index_ = i;
      }
      all_done = ++finished_ == count_;
      PublishDone();
    }
    if (all_done) work_done_.notify_all();
  }
}

void WorkerPool::WorkerLoop() {
  std::size_t seen = 0;
  while (true) {
    Spin([&] {
      return published_stopping_.load(std::memory_order_acquire) ||
             published_generation_.load(std::memory_order_acquire) != seen;
    });
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_ready_.wait(lock, [&] { return stopping_ || generation_ != seen; });
      if (stopping_) return;
      seen = generation_;
      ++busy_workers_;
    }
    Drain();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_workers_;
      PublishDone();
    }
    work_done_.notify_all();
  }
}

}  // namespace pavilion::sim
