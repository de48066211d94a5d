#include "scenarios/run/progress_line.h"

#include <cstdio>
#include <ctime>

namespace pavilion::scenarios {

double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void ProgressLine::Update(double sim_s, double wall_s) {
  if (!enabled_ || wall_s - last_wall_s_ < kPeriodS) return;
  last_wall_s_ = wall_s;
  const double rtf = wall_s > 0 ? sim_s / wall_s : 0.0;
  const double eta = rtf > 0 ? (total_s_ - sim_s) / rtf : 0.0;
  std::fprintf(stderr, "\r  sim %.1f/%.1f s  RTF %.1fx  ETA %.1f s   ", sim_s, total_s_, rtf, eta);
  std::fflush(stderr);
}

void ProgressLine::Done() {
  if (enabled_ && last_wall_s_ > 0.0) std::fprintf(stderr, "\r%60s\r", "");
}

}  // namespace pavilion::scenarios
