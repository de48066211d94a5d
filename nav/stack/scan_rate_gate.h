#pragma once

// Which scans a localization cycle takes: each listed laser's at most
// `rate_hz` times per second (the thesis localized at 2 Hz, §4.5.2).

#include <string>
#include <vector>

#include "core/types/sensor_data.h"

namespace pavilion::nav {

class ScanRateGate {
 public:
  ScanRateGate(std::vector<std::string> lasers, double rate_hz);
  // True when `scan` is due (and records it); false for unlisted lasers.
  bool Admit(const core::LaserScan& scan);

 private:
  std::vector<std::string> lasers_;
  double rate_hz_;
  std::vector<double> next_due_s_;  // per entry of lasers_
};

}  // namespace pavilion::nav
