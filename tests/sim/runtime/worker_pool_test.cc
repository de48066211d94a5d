// The worker pool of per-robot tick work: every index exactly once, results
// independent of the thread count, exceptions reported by lowest index.
#include "sim/runtime/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/random/random_stream.h"

namespace pavilion::sim {
namespace {

// Item i draws from its own stream and writes its own slot: the pattern the
// scenario runner uses, so results cannot depend on scheduling.
std::vector<double> Work(WorkerPool& pool, std::size_t n) {
  std::vector<double> out(n, 0.0);
  pool.ParallelFor(n, [&](std::size_t i) {
    core::RandomStream stream(7, static_cast<std::uint64_t>(i));
    double sum = 0.0;
    for (int k = 0; k < 1000 + static_cast<int>(i % 7) * 500; ++k) sum += stream.Normal(0.0, 1.0);
    out[i] = sum;
  });
  return out;
}

TEST(WorkerPoolTest, SameResultsForOneTwoAndEightThreads) {
  WorkerPool one(1), two(2), eight(8);
  EXPECT_EQ(one.threads(), 1);
  EXPECT_EQ(eight.threads(), 8);
  for (std::size_t n : {0u, 1u, 3u, 37u, 200u}) {
    const std::vector<double> a = Work(one, n);
    EXPECT_EQ(Work(two, n), a) << n;
    EXPECT_EQ(Work(eight, n), a) << n;
  }
}

TEST(WorkerPoolTest, RunsEveryIndexExactlyOnceAcrossManyJobs) {
  WorkerPool pool(4);
  for (int job = 0; job < 300; ++job) {
    const std::size_t n = static_cast<std::size_t>(job % 17);
    std::vector<std::atomic<int>> calls(n);
    pool.ParallelFor(n, [&](std::size_t i) { calls[i].fetch_add(1); });
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(calls[i].load(), 1) << job << " " << i;
  }
}

// Two threads on this machine kind spin between jobs before sleeping: jobs
// back to back (caught while spinning) and jobs after pauses longer than the
// spin (caught after sleeping) both run every index once, and ParallelFor
// returns only when every call has finished.
TEST(WorkerPoolTest, SpinningAndSleepingWorkersBothFinishEveryJob) {
  WorkerPool pool(2);
  for (int job = 0; job < 4000; ++job) {
    const std::size_t n = 2 + static_cast<std::size_t>(job % 5);
    std::vector<std::atomic<int>> calls(n);
    std::atomic<int> finished{0};
    pool.ParallelFor(n, [&](std::size_t i) {
      calls[i].fetch_add(1);
      finished.fetch_add(1);
    });
    ASSERT_EQ(finished.load(), static_cast<int>(n)) << job;
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(calls[i].load(), 1) << job << " " << i;
    if (job % 50 == 49) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

TEST(WorkerPoolTest, RethrowsTheLowestIndexFailureAfterAllFinish) {
  for (int threads : {1, 3}) {
    WorkerPool pool(threads);
    std::atomic<int> done{0};
    try {
      pool.ParallelFor(50, [&](std::size_t i) {
        done.fetch_add(1);
        if (i == 11 || i == 40) throw std::runtime_error("item " + std::to_string(i));
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "item 11") << threads;
    }
    if (threads > 1) {
      EXPECT_EQ(done.load(), 50);  // all calls made before the rethrow
    }
    // The pool is usable afterwards.
    EXPECT_EQ(Work(pool, 9), Work(pool, 9));
  }
  EXPECT_THROW(WorkerPool(0), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::sim
