#include "sim/runtime/schedule.h"

#include <cmath>
#include <stdexcept>

namespace pavilion::sim {

std::int64_t PeriodTicks(double physics_rate_hz, double task_rate_hz, const std::string& what) {
  if (!(task_rate_hz > 0.0) || !std::isfinite(task_rate_hz)) {
    throw std::invalid_argument(what + ": rate must be a positive number of Hz");
  }
  const double ratio = physics_rate_hz / task_rate_hz;
  const double rounded = std::round(ratio);
  if (rounded < 1.0 || std::abs(ratio - rounded) > 1e-9 * ratio) {
    throw std::invalid_argument(what + ": rate " + std::to_string(task_rate_hz) +
                                " Hz is not the physics rate " + std::to_string(physics_rate_hz) +
                                " Hz divided by a whole number");
  }
  return static_cast<std::int64_t>(rounded);
}

PeriodicSchedule::PeriodicSchedule(double physics_rate_hz) : physics_rate_hz_(physics_rate_hz) {}

int PeriodicSchedule::Add(const std::string& name, double rate_hz, std::int64_t phase_ticks) {
  tasks_.push_back({name, PeriodTicks(physics_rate_hz_, rate_hz, name), phase_ticks});
  return static_cast<int>(tasks_.size()) - 1;
}

std::vector<int> PeriodicSchedule::Due(std::int64_t tick) const {
  std::vector<int> due;
  for (int i = 0; i < static_cast<int>(tasks_.size()); ++i) {
    if (IsDue(i, tick)) due.push_back(i);
  }
  return due;
}

}  // namespace pavilion::sim
