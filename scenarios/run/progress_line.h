#pragma once

namespace pavilion::scenarios {

// CPU seconds this process has used: beside wall time, a figure that holds
// on a machine shared with other work.
double ProcessCpuSeconds();

// Shows "sim 12.3/60.0 s  RTF 41.2x  ETA 1.2 s" on one updating line.
class ProgressLine {
 public:
  ProgressLine(bool enabled, double total_s) : enabled_(enabled), total_s_(total_s) {}
  // Rewrites the line (at most every kPeriodS of wall time).
  void Update(double sim_s, double wall_s);
  // Clears the line.
  void Done();

 private:
  static constexpr double kPeriodS = 0.25;  // wall seconds between updates

  bool enabled_;
  double total_s_;
  double last_wall_s_ = 0.0;
};

}  // namespace pavilion::scenarios
