#pragma once

// Vertical edges in a grey-level image (thesis §3.4, after Tomatis 2001): the
// bearings of the image's vertical lines with their variances, from the
// distorted camera image and the camera model of §2.4 (camera_model.h).

#include <vector>

#include "core/features/camera_model.h"
#include "core/types/image.h"

namespace pavilion::core {

// One vertical edge, in the camera frame.
struct VerticalEdge {
  double bearing_rad = 0.0;    // phi = atan((c_u - column_px) / f), positive left (§3.4)
  double variance_rad2 = 0.0;  // sigma_phi^2 (§3.4), rad^2
  double column_px = 0.0;      // undistorted column: weighted mean of the corrected edge pixels
  int pixels = 0;              // edge pixels in the fit (one per row)
  int first_row = 0;           // image rows spanned (distorted image, pixel index)
  int last_row = 0;
  int polarity = 0;       // +1 dark to bright from left to right, -1 bright to dark
  double contrast = 0.0;  // mean grey-level step across the edge, grey levels
};

// How an edge pixel's sub-pixel column is estimated from the Sobel responses
// g around its maximum u (§3.4, step 2).
enum class SubpixelMethod {
  // The centroid of g at u - 2 .. u + 2: where the grey-level step's area
  // balances, unbiased for any edge profile the window holds (blur,
  // DistortImage's resampling: < 0.005 px per line). Noise: sigma about
  // 1.44 sigma_n / step per pixel; its second-order bias, up to 0.2
  // (sigma_n / step)^2 px, a tenth of the parabola's. Another edge within
  // 4 px shares the window and shifts it.
  kCentroid,
  // The vertex of the parabola through g at u - 1, u, u + 1: exact for an
  // edge spanning one pixel (area coverage) and the least noisy (0.75
  // sigma_n / step), but biased on wider, asymmetric profiles (0.06 px per
  // line, 0.1 px per pixel on DistortImage's bilinear resampling) and by the
  // noise itself (E[N / 2D] != E[N] / 2E[D]: up to 2 (sigma_n / step)^2 px).
  // Neither bias averages out along a line; the calibration floor covers them.
  kParabola,
};

// Options of ExtractVerticalEdges. Defaults: the Pulnix TM-9701 of §2.4 at 640 x 480.
struct VerticalEdgeOptions {
  SubpixelMethod subpixel = SubpixelMethod::kCentroid;
  // sigma_n of the camera electronics' grey-level noise, grey levels; finite, >= 0.
  // The 8-bit quantization's 1/12 grey^2 is added to its square.
  double image_noise_sigma_grey = 2.0;
  // True: sigma_n is estimated from the image instead (robust sigma of the
  // Sobel response, see noise_threshold_factor, over sqrt(12)); texture makes
  // it an overestimate.
  bool estimate_image_noise = false;
  // Absolute threshold of the dynamic threshold: an edge pixel's grey-level
  // step (Sobel response / 4) is at least this, grey levels; finite, >= 0.
  double min_contrast_grey = 10.0;
  // Relative threshold: the Sobel response of an edge pixel is at least this
  // many robust sigmas (median |gx| / 0.6745, the noise and texture level of
  // the image) of the image's Sobel responses; finite, >= 0.
  double noise_threshold_factor = 5.0;
  // Width of the window of undistorted columns whose edge pixels of one
  // polarity form one line, px; finite, > 0. A straight edge's corrected
  // pixels scatter by their noise (a few hundredths to a few tenths of a px).
  double column_window_px = 2.0;
  // A line needs at least this many edge pixels (rows); >= 2. 60 of 480 rows:
  // an edge spanning an eighth of the image.
  int min_pixels = 60;
  // ... and its pixels must fill at least this fraction of the rows it spans;
  // in (0, 1]. Rejects texture pixels that happen to share a column.
  double min_fill = 0.5;
  // Standard deviation added in quadrature to a line's column, px; finite,
  // >= 0: the calibration's and the lens model's error, which all pixels of
  // a line share and which averaging does not reduce (§2.4, §3.4). 0 leaves
  // the image noise alone.
  double calibration_sigma_px = 0.1;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// What one extraction found, for diagnostics and benchmarks.
struct VerticalEdgeStats {
  double gradient_threshold = 0.0;  // Sobel response an edge pixel needed
  double noise_sigma_grey = 0.0;    // sigma_n used, quantization included
  int edge_pixels = 0;              // after non-maxima suppression
};

// The four steps of §3.4 on the distorted image of `camera`:
//  1. horizontal Sobel gx ([-1 0 1; -2 0 2; -1 0 1]);
//  2. non-maxima suppression along each row (|gx| greater than its left and
//     at least its right neighbour's) with the dynamic threshold
//     max(4 min_contrast_grey, noise_threshold_factor robust_sigma(gx)), and
//     the sub-pixel column (SubpixelMethod);
//  3. calibration of each edge pixel (not of the image) by eq. 3.23;
//  4. line fitting: the pixels of one polarity whose corrected columns fall in
//     the densest column_window_px window (repeatedly, each pixel used once)
//     form a line if they are enough and fill their rows; its column is the
//     mean of their corrected columns weighted by 1 / sigma_i^2.
// Uncertainty is modelled on the uncalibrated edge image (sigma_n per grey
// level) and propagated to first order through the sub-pixel estimator, eq. 3.23 and the
// weighted mean, including the correlation that the Sobel kernel's rows
// create between adjacent rows; then through phi: sigma_phi = f / (f^2 + (c_u
// - x)^2) sigma_x. Edges are ordered by column ascending (bearing descending).
// Throws std::invalid_argument if the image is not the camera's size or the
// options or the camera are invalid.
std::vector<VerticalEdge> ExtractVerticalEdges(const GrayImage& image,
                                               const CameraIntrinsics& camera,
                                               const VerticalEdgeOptions& options,
                                               VerticalEdgeStats* stats = nullptr);

}  // namespace pavilion::core
