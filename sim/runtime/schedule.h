#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pavilion::sim {

// Number of physics ticks between runs of a task at `task_rate_hz` when physics
// steps at `physics_rate_hz`. Every task runs on integer multiples of the physics
// step (architecture.md), so the ratio must be a whole number: throws
// std::invalid_argument naming `what` otherwise.
std::int64_t PeriodTicks(double physics_rate_hz, double task_rate_hz, const std::string& what);

// Integer-tick scheduling of periodic tasks. A task with period p and phase f is
// due at every tick t >= f with (t - f) % p == 0. Tasks are reported in the order
// they were added, which keeps the run order deterministic.
class PeriodicSchedule {
 public:
  explicit PeriodicSchedule(double physics_rate_hz);

  // Adds a task; returns its id (0, 1, ...).
  int Add(const std::string& name, double rate_hz, std::int64_t phase_ticks = 0);
  // Ids of the tasks due at `tick`, in the order added.
  std::vector<int> Due(std::int64_t tick) const;
  bool IsDue(int task, std::int64_t tick) const {  // inline: robots ask every tick
    const Task& t = tasks_.at(task);
    if (t.period == 1) return tick >= t.phase;  // every tick: no division
    return tick >= t.phase && (tick - t.phase) % t.period == 0;
  }
  std::int64_t period_ticks(int task) const { return tasks_.at(task).period; }
  const std::string& name(int task) const { return tasks_.at(task).name; }

 private:
  struct Task {
    std::string name;
    std::int64_t period;
    std::int64_t phase;
  };
  double physics_rate_hz_;
  std::vector<Task> tasks_;
};

}  // namespace pavilion::sim
