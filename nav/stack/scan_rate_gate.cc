#include "nav/stack/scan_rate_gate.h"

#include <algorithm>
#include <utility>

namespace pavilion::nav {
namespace {
// Scan stamps are compared with a laser's due time up to this rounding (s).
constexpr double kDueToleranceS = 1e-9;
}  // namespace

ScanRateGate::ScanRateGate(std::vector<std::string> lasers, double rate_hz)
    : lasers_(std::move(lasers)), rate_hz_(rate_hz), next_due_s_(lasers_.size(), 0.0) {}

bool ScanRateGate::Admit(const core::LaserScan& scan) {
  const auto it = std::find(lasers_.begin(), lasers_.end(), scan.sensor_id);
  if (it == lasers_.end()) return false;
  double& next = next_due_s_[static_cast<std::size_t>(it - lasers_.begin())];
  if (scan.stamp_s + kDueToleranceS < next) return false;
  next = std::max(next + 1.0 / rate_hz_, scan.stamp_s);
  return true;
}

}  // namespace pavilion::nav
