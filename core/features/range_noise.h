#pragma once

#include <span>
#include <vector>

#include "core/features/line_fit.h"

namespace pavilion::core {

// Range noise read off a scan itself — an extension of §3.2. The extraction
// weighs every reading with the sensor's nominal sigma_rho (eq. 3.11), a
// "distance-only" model; the thesis saw black velvet's readings scatter far
// more than that model predicts (§3.2.4, fig. 3.6) and the AccuRange's
// variance grow on low-reflectance targets (§2.2.1.6, "C"), and called for a
// physically grounded model. A SICK LMS 200 reports no amplitude, so the
// extraction estimates the local noise from the readings:
//
// - The pseudo-residual of reading i is its range minus the range at which its
//   beam meets the chord of its valid neighbours i-1 and i+1. On a surface
//   (plane, or a curve much larger than the reading spacing) it is
//   n_i - (a n_{i-1} + b n_{i+1}) for the range errors n, a + b = 1 the
//   neighbours' interpolation weights along the chord, hence of variance
//   sigma^2 (1 + a^2 + b^2); it is normalized by that factor. A corner or a
//   depth edge gives a few large pseudo-residuals, a curve of radius R at
//   reading spacing s a deterministic s^2 / (2R) (1.4 mm for a 0.25 m column
//   at 3 m), so the estimate is local and robust, not a fit.
// - A reading lies in a noisy region when more than half of the normalized
//   pseudo-residuals in the window of `window_readings` valid readings around
//   it exceed detection_factor x nominal sigma, i.e. when their median does:
//   a running count, O(n). With nominal noise the chance is a binomial tail
//   (1e-7 for 15 readings at factor 2); noise of 3x nominal or more is
//   detected with probability 1/2 or more.
// - Each maximal run of such readings, widened by a quarter window at both
//   ends (the majority sits inside the region by about that much), is given
//   the robust sigma 1.4826 median |normalized pseudo-residual| of its
//   readings — unless that exceeds max_factor x nominal: readings jumping
//   between legs, bodies and the background are clutter, not a surface, and
//   keep the nominal sigma (so no line is fitted through a crowd).
struct RangeNoiseOptions {
  // Valid readings in the detection window; odd, >= 5.
  int window_readings = 15;
  // The median |pseudo-residual| / nominal sigma above which a window is
  // noisy; > 0.
  double detection_factor = 2.0;
  // Estimated sigmas above max_factor x nominal are clutter, not a surface;
  // >= 1. Eight covers dark surfaces (the simulated LMS 200 gives them 5x)
  // with margin for the estimate's scatter.
  double max_factor = 8.0;

  // Throws std::invalid_argument naming the first invalid field.
  void Validate() const;
};

// One noisy region found by EstimateRangeSigmas.
struct NoisyRegion {
  int first = 0;  // indices into the points, inclusive
  int last = 0;
  double sigma_m = 0.0;  // robust estimate of its range sigma
  bool clutter = false;  // above max_factor x nominal: left at the nominal sigma
};

// The range sigma of each of `points` (the valid readings of one scan in
// order, as the extraction prepares them; weights are ignored) into `sigmas`:
// nominal_sigma_m, or the estimate of the noisy region the reading lies in —
// or `sigmas` left empty when every reading keeps the nominal sigma (most
// scans). Returns the regions found, cut at depth edges: the pieces of
// surface, and the clutter. O(n) plus a median per region.
std::vector<NoisyRegion> EstimateRangeSigmas(std::span<const FitPoint> points,
                                             double nominal_sigma_m,
                                             const RangeNoiseOptions& options,
                                             std::vector<double>& sigmas);

}  // namespace pavilion::core
