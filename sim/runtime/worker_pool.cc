#include "sim/runtime/worker_pool.h"

#include <stdexcept>

namespace pavilion::sim {

WorkerPool::WorkerPool(int threads) {
  if (threads < 1) throw std::invalid_argument("WorkerPool: threads must be >= 1");
  workers_.reserve(static_cast<std::size_t>(threads - 1));
  for (int k = 1; k < threads; ++k) workers_.emplace_back([this] { WorkerLoop(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
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
  }
  work_ready_.notify_all();
  Drain();
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
    }
    if (all_done) work_done_.notify_all();
  }
}

void WorkerPool::WorkerLoop() {
  std::size_t seen = 0;
  while (true) {
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
    }
    work_done_.notify_all();
  }
}

}  // namespace pavilion::sim
