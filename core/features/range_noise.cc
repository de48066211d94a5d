#include "core/features/range_noise.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace pavilion::core {
namespace {

// sigma = 1.4826 x the median absolute deviation of a zero-mean normal
// (1 / Phi^-1(3/4)).
constexpr double kMadToSigma = 1.482602218505602;
// A beam meeting the chord of its neighbours at a sine below this (relative to
// the chord's length) has no pseudo-residual: the chord runs along the beam (a
// depth edge), which counts as a large one.
constexpr double kMinChordSine = 1e-9;
// A region is widened into neighbouring readings whose pseudo-residual is
// within this many of its sigmas.
constexpr double kExplainedSigmas = 3.0;
constexpr double kEdgeSigmas = 4.0;

void Require(bool ok, const char* field, const std::string& expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("RangeNoiseOptions.") + field + ": expected " +
                                expected);
  }
}

// The pieces of reading i's pseudo-residual (see the header), i interior:
// e = numerator / chord_sine with chord_sine = d x u (d the chord, u the beam),
// and 1 + a^2 + b^2 = weight_sum / step_sum^2 for the bearing steps before
// and after it. chord_sine is 0 where the chord runs along the beam.
struct PseudoResidualParts {
  double numerator = 0.0;
  double chord_sine = 0.0;
  double step_sum = 1.0;
  double weight_sum = 1.5;
};

[[gnu::always_inline]] inline PseudoResidualParts Parts(std::span<const FitPoint> p, int i) {
  const FitPoint& prev = p[i - 1];
  const FitPoint& next = p[i + 1];
  const double ax = prev.range_m * prev.cos_bearing;
  const double ay = prev.range_m * prev.sin_bearing;
  const double dx = next.range_m * next.cos_bearing - ax;
  const double dy = next.range_m * next.sin_bearing - ay;
  PseudoResidualParts parts;
  parts.chord_sine = dx * p[i].sin_bearing - dy * p[i].cos_bearing;
  if (!(parts.chord_sine * parts.chord_sine >
        kMinChordSine * kMinChordSine * (dx * dx + dy * dy))) {
    parts.chord_sine = 0.0;
    return parts;
  }
  // rho_i minus the range at which beam i meets the chord, (d x A) / (d x u).
  parts.numerator = p[i].range_m * parts.chord_sine - (dx * ay - dy * ax);
  // Interpolation weights a (for i - 1) and b (for i + 1) from the bearing
  // steps (sines of the differences; the steps are small): a = after / sum.
  const double before = prev.cos_bearing * p[i].sin_bearing - prev.sin_bearing * p[i].cos_bearing;
  const double after = p[i].cos_bearing * next.sin_bearing - p[i].sin_bearing * next.cos_bearing;
  if (before > 0.0 && after > 0.0) {
    parts.step_sum = before + after;
    parts.weight_sum = parts.step_sum * parts.step_sum + before * before + after * after;
  }
  return parts;
}

// The normalized pseudo-residual |e_i| / sqrt(1 + a^2 + b^2): NaN at both
// ends, +inf where the chord runs along the beam.
double PseudoResidual(std::span<const FitPoint> p, int i) {
  if (i <= 0 || i + 1 >= static_cast<int>(p.size()))
    return std::numeric_limits<double>::quiet_NaN();
  const PseudoResidualParts q = Parts(p, i);
  if (q.chord_sine == 0.0) return std::numeric_limits<double>::infinity();
  return std::abs(q.numerator / q.chord_sine) * q.step_sum / std::sqrt(q.weight_sum);
}

// Whether the normalized pseudo-residual of interior reading i exceeds
// `threshold`, without a division or root (the test runs on every reading).
bool Exceeds(std::span<const FitPoint> p, int i, double threshold) {
  const PseudoResidualParts q = Parts(p, i);
  if (q.chord_sine == 0.0) return true;
  const double lhs = q.numerator * q.step_sum;
  const double rhs = threshold * q.chord_sine;
  return lhs * lhs > rhs * rhs * q.weight_sum;
}

}  // namespace

void RangeNoiseOptions::Validate() const {
  Require(window_readings >= 5 && window_readings % 2 == 1, "window_readings",
          "an odd integer >= 5");
  Require(std::isfinite(detection_factor) && detection_factor > 0.0, "detection_factor",
          "a finite value > 0");
  Require(std::isfinite(max_factor) && max_factor >= 1.0, "max_factor", "a finite value >= 1");
}

namespace {

// Runs of centres c where the pseudo-residuals above `threshold` are the
// majority of the window [c - h, c + h] of m readings (a running count).
std::vector<NoisyRegion> MajorityRuns(std::span<const FitPoint> points, double threshold, int m) {
  const int n = static_cast<int>(points.size());
  std::vector<NoisyRegion> regions;
  thread_local std::vector<char> exceed;
  exceed.assign(n, 0);
  int total = 0;
  for (int i = 1; i + 1 < n; ++i) total += exceed[i] = Exceeds(points, i, threshold);
  if (2 * total <= m) return regions;  // no window can hold a majority
  const int h = m / 2;
  const auto exceeds = [&](int i) { return i >= 0 && i < n ? exceed[i] : 0; };
  int count = 0;
  for (int i = 0; i < h; ++i) count += exceeds(i);
  int run_first = -1;
  for (int c = 0; c < n; ++c) {
    count += exceeds(c + h) - exceeds(c - h - 1);
    const bool noisy = 2 * count > m;
    if (noisy && run_first < 0) run_first = c;
    if (run_first >= 0 && (!noisy || c == n - 1)) {
      regions.push_back({run_first, noisy ? c : c - 1, 0.0, false});
      run_first = -1;
    }
  }
  return regions;
}

// The region's sigma from its own readings (clutter when it has none or more
// than max_factor nominal); then the region is widened by up to `widen`
// readings at each end into readings its noise explains (|z| <= 3 sigma: not
// across a depth edge).
void EstimateRegion(std::span<const FitPoint> points, double nominal_sigma_m,
                    const RangeNoiseOptions& options, int widen, NoisyRegion& region) {
  const int n = static_cast<int>(points.size());
  const auto z = [&](int i) { return PseudoResidual(points, i); };
  thread_local std::vector<double> sample;
  sample.clear();
  for (int i = region.first; i <= region.last; ++i) {
    if (const double v = z(i); !std::isnan(v)) sample.push_back(v);
  }
  if (sample.empty()) {
    region.clutter = true;
    return;
  }
  const auto middle = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 2);
  std::nth_element(sample.begin(), middle, sample.end());
  // Once more without the depth edges the first estimate shows (the chord
  // across an edge at either end of the run).
  const double first_estimate = kMadToSigma * *middle;
  std::erase_if(sample, [&](double v) { return v > kEdgeSigmas * first_estimate; });
  const auto centre = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 2);
  std::nth_element(sample.begin(), centre, sample.end());
  region.sigma_m = std::max(kMadToSigma * *centre, nominal_sigma_m);
  region.clutter = !(region.sigma_m <= options.max_factor * nominal_sigma_m);
  if (region.clutter) return;
  const double explained = kExplainedSigmas * region.sigma_m;
  for (int k = 0; k < widen && region.first > 0 && !(z(region.first - 1) > explained); ++k) {
    --region.first;
  }
  for (int k = 0; k < widen && region.last + 1 < n && !(z(region.last + 1) > explained); ++k) {
    ++region.last;
  }
}

// Surface regions that touch are one surface: the larger sigma (the
// conservative weight).
std::vector<NoisyRegion> MergeTouching(const std::vector<NoisyRegion>& regions) {
  std::vector<NoisyRegion> merged;
  for (const NoisyRegion& region : regions) {
    if (!merged.empty() && !region.clutter && !merged.back().clutter &&
        region.first <= merged.back().last + 1) {
      merged.back().last = std::max(merged.back().last, region.last);
      merged.back().sigma_m = std::max(merged.back().sigma_m, region.sigma_m);
      continue;
    }
    merged.push_back(region);
  }
  return merged;
}

// A surface ends at a depth edge: a reading its neighbours' chord misses by
// more than kEdgeSigmas of the region's sigma (a chance of 6e-5 per reading
// on the surface) separates two surfaces — the velvet and a visitor in
// front of it. Such readings keep the region's sigma but belong to no piece.
// Sets the surfaces' readings' sigmas.
std::vector<NoisyRegion> SplitAtDepthEdges(std::span<const FitPoint> points,
                                           const std::vector<NoisyRegion>& merged,
                                           double nominal_sigma_m, std::vector<double>& sigmas) {
  const int n = static_cast<int>(points.size());
  std::vector<NoisyRegion> pieces;
  for (const NoisyRegion& region : merged) {
    if (region.clutter) {
      pieces.push_back(region);
      continue;
    }
    if (sigmas.empty()) sigmas.assign(n, nominal_sigma_m);
    std::fill(sigmas.begin() + region.first, sigmas.begin() + region.last + 1, region.sigma_m);
    const double edge = kEdgeSigmas * region.sigma_m;
    int first = region.first;
    for (int i = region.first; i <= region.last + 1; ++i) {
      if (i <= region.last && !(PseudoResidual(points, i) > edge)) continue;
      if (i > first) pieces.push_back({first, i - 1, region.sigma_m, false});
      first = i + 1;
    }
  }
  return pieces;
}

}  // namespace

std::vector<NoisyRegion> EstimateRangeSigmas(std::span<const FitPoint> points,
                                             double nominal_sigma_m,
                                             const RangeNoiseOptions& options,
                                             std::vector<double>& sigmas) {
  const int n = static_cast<int>(points.size());
  sigmas.clear();
  const int m = options.window_readings;
  if (n < m) return {};
  std::vector<NoisyRegion> regions =
      MajorityRuns(points, options.detection_factor * nominal_sigma_m, m);
  if (regions.empty()) return regions;
  const int widen = m / 4;
  for (NoisyRegion& region : regions) {
    EstimateRegion(points, nominal_sigma_m, options, widen, region);
  }
  return SplitAtDepthEdges(points, MergeTouching(regions), nominal_sigma_m, sigmas);
}

}  // namespace pavilion::core
