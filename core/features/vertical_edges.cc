#include "core/features/vertical_edges.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>

namespace pavilion::core {
namespace {

// Sobel response of a unit grey-level step: (1 + 2 + 1) rows x 1 (§3.4, step 1).
constexpr double kSobelGain = 4.0;
constexpr int kMaxAbsGradient = 4 * 255;
// sum_dv w(dv) w(dv + d) of the Sobel row weights w = (1, 2, 1) for row
// distances d = 0, 1, 2: how much of one Sobel response's noise the responses
// of the same column 0, 1 and 2 rows away share.
constexpr std::array<double, 3> kRowOverlap{6.0, 4.0, 1.0};
// Phi^-1(3/4): median |x| / this is the sigma of a zero-mean Gaussian x.
constexpr double kMedianAbsToSigma = 0.6744897501960817;
// Var(gx) = 12 sigma_n^2 for independent pixels ((1 + 4 + 1) x 2 columns).
constexpr double kSobelNoiseGain = 12.0;
// 8-bit grey levels: rounding adds a uniform error of variance 1/12.
constexpr double kQuantizationVariance = 1.0 / 12.0;
// A centroid farther than this from its maximum is not one edge's: an edge of
// the other polarity shares the window (the parabola's vertex is within 0.5).
constexpr double kMaxPeakOffsetPx = 1.0;
// Mean-shift steps that centre a line's column window on its pixels.
constexpr int kCentreIterations = 3;

void Require(bool ok, const char* field, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("VerticalEdgeOptions.") + field + ": expected " +
                                expected);
  }
}

// Columns of grey levels an edge pixel's sub-pixel column depends on: u - 3 ..
// u + 3 (the centroid's Sobel responses at u - 2 .. u + 2).
constexpr int kStencilHalf = 3;
constexpr int kStencilSize = 2 * kStencilHalf + 1;

// An edge pixel after non-maxima suppression and calibration (§3.4, steps 2-3).
struct EdgePixel {
  double column_px = 0.0;  // undistorted (eq. 3.23) sub-pixel column
  // d(column_px) / d(grey level of pixel (u - 3 + k, v + dv)) / w(dv), with
  // the Sobel row weights w = (1, 2, 1): the first-order error propagation
  // through the Sobel filter, the sub-pixel estimator and eq. 3.23.
  std::array<double, kStencilSize> stencil{};
  double unit_variance = 0.0;  // Var(column_px) per grey-level variance
  double step_grey = 0.0;      // grey-level step across the edge
  int u = 0, v = 0;            // integer pixel of the maximum
  int polarity = 0;
  int strength = 0;  // |gx|
};

// Horizontal Sobel response, zero on the border (§3.4, step 1).
std::vector<std::int16_t> SobelX(const GrayImage& image) {
  const int w = image.width, h = image.height;
  std::vector<std::int16_t> gx(static_cast<std::size_t>(w) * h, 0);
  for (int v = 1; v + 1 < h; ++v) {
    const std::uint8_t* up = image.pixels.data() + static_cast<std::size_t>(v - 1) * w;
    const std::uint8_t* mid = up + w;
    const std::uint8_t* down = mid + w;
    std::int16_t* out = gx.data() + static_cast<std::size_t>(v) * w;
    for (int u = 1; u + 1 < w; ++u) {
      out[u] = static_cast<std::int16_t>((up[u + 1] - up[u - 1]) + 2 * (mid[u + 1] - mid[u - 1]) +
                                         (down[u + 1] - down[u - 1]));
    }
  }
  return gx;
}

// Robust sigma of the interior Sobel responses: median |gx| / Phi^-1(3/4),
// from a histogram of the integer responses (linear within the median's bin).
double RobustGradientSigma(const std::vector<std::int16_t>& gx, int w, int h) {
  std::vector<std::int64_t> counts(kMaxAbsGradient + 1, 0);
  std::int64_t n = 0;
  for (int v = 1; v + 1 < h; ++v) {
    const std::int16_t* row = gx.data() + static_cast<std::size_t>(v) * w;
    for (int u = 1; u + 1 < w; ++u) ++counts[std::abs(row[u])];
    n += std::max(w - 2, 0);
  }
  if (n == 0) return 0.0;
  const double half = 0.5 * static_cast<double>(n);
  double below = 0.0;
  for (int a = 0; a <= kMaxAbsGradient; ++a) {
    const double c = static_cast<double>(counts[a]);
    if (below + c >= half) {
      // |gx| = a stands for [a - 0.5, a + 0.5); a = 0 for [0, 0.5).
      const double lo = a == 0 ? 0.0 : a - 0.5, width = a == 0 ? 0.5 : 1.0;
      return (lo + width * (half - below) / c) / kMedianAbsToSigma;
    }
    below += c;
  }
  return kMaxAbsGradient / kMedianAbsToSigma;
}

// A sub-pixel peak: the offset from the maximum's pixel, its derivatives
// with respect to g(u + m), m = -2..2 (zero outside the estimator's window),
// and the sum of g over the window.
struct Peak {
  double offset = 0.0;
  std::array<double, 5> d_offset_d_g{};
  double sum = 0.0;
};

// The parabola through (-1, g_m), (0, g_0), (1, g_p) peaks at delta = N / (2 D),
// N = g_m - g_p, D = g_m - 2 g_0 + g_p < 0, so d delta/d g_m = (D - N) / (2 D^2),
// d delta/d g_0 = N / D^2, d delta/d g_p = -(D + N) / (2 D^2).
Peak ParabolaPeak(const double* g) {
  const double n = g[-1] - g[1];
  const double d = g[-1] - 2.0 * g[0] + g[1];
  Peak p;
  p.offset = n / (2.0 * d);
  p.d_offset_d_g = {0.0, (d - n) / (2.0 * d * d), n / (d * d), -(d + n) / (2.0 * d * d), 0.0};
  p.sum = g[-1] + g[0] + g[1];
  return p;
}

// The centroid delta = sum m g_m / sum g_m over m = -2..2, so d delta/d g_m =
// (m - delta) / sum g. The central differences of a step telescope: delta is
// where the step's area balances, whatever its profile.
Peak CentroidPeak(const double* g) {
  Peak p;
  double moment = 0.0;
  for (int m = -2; m <= 2; ++m) {
    p.sum += g[m];
    moment += m * g[m];
  }
  p.offset = moment / p.sum;
  for (int m = -2; m <= 2; ++m) p.d_offset_d_g[m + 2] = (m - p.offset) / p.sum;
  return p;
}

// The edge pixel at the maximum (u, v), the responses signed by polarity.
//
// Uncertainty on the uncalibrated edge image (§3.4): each g(u') = sum_dv
// w(dv) (I(u' + 1, v + dv) - I(u' - 1, v + dv)) is linear in the grey levels
// I, so the offset's derivative with respect to I(u + c, v + dv) is w(dv) h_c,
// h_c = d_offset/d g(u + c - 1) - d_offset/d g(u + c + 1). For independent
// grey-level noise sigma_n, Var(offset) = 6 sigma_n^2 sum_c h_c^2 (an ideal
// step of height A centred on the pixel: g = 4A (1/2, 1, 1/2); the parabola
// gives sigma = 0.75 sigma_n / A, the centroid 1.44 sigma_n / A).
// Calibration (step 3) scales the error by J = dx/dx_d of eq. 3.23. Nothing
// if the peak lies off the pixel (kMaxPeakOffsetPx) or its variance is not
// positive and finite.
std::optional<EdgePixel> MakeEdgePixel(const std::int16_t* row_gx, int u, int v, int polarity,
                                       const CameraIntrinsics& camera, SubpixelMethod method) {
  double g[5];
  for (int m = -2; m <= 2; ++m) g[m + 2] = polarity * row_gx[u + m];
  const Peak peak = method == SubpixelMethod::kParabola ? ParabolaPeak(g + 2) : CentroidPeak(g + 2);
  if (!(std::abs(peak.offset) <= kMaxPeakOffsetPx)) return std::nullopt;
  const Eigen::Vector2d distorted(u + 0.5 + peak.offset, v + 0.5);
  const double j = UndistortPointJacobian(camera, distorted)(0, 0);
  EdgePixel p;
  p.column_px = UndistortPoint(camera, distorted).x();
  auto d_g = [&](int m) { return m >= -2 && m <= 2 ? peak.d_offset_d_g[m + 2] : 0.0; };
  double sum_sq = 0.0;
  for (int c = -kStencilHalf; c <= kStencilHalf; ++c) {
    const double h = j * (d_g(c - 1) - d_g(c + 1));
    p.stencil[c + kStencilHalf] = h;
    sum_sq += h * h;
  }
  p.unit_variance = kRowOverlap[0] * sum_sq;
  if (!(p.unit_variance > 0.0 && std::isfinite(p.unit_variance))) return std::nullopt;
  // The central differences of a step sum to twice its height.
  p.step_grey = peak.sum / (2.0 * kSobelGain);
  p.u = u;
  p.v = v;
  p.polarity = polarity;
  p.strength = std::abs(row_gx[u]);
  return p;
}

// Non-maxima suppression along each row with the threshold (§3.4, step 2),
// then calibration of each maximum (step 3). A maximum beats its left
// neighbour strictly and its right one or equals it, so of two equal
// neighbours the left is kept.
std::vector<EdgePixel> FindEdgePixels(const std::vector<std::int16_t>& gx, int w, int h,
                                      double threshold, const CameraIntrinsics& camera,
                                      SubpixelMethod method) {
  std::vector<EdgePixel> pixels;
  for (int v = 1; v + 1 < h; ++v) {
    const std::int16_t* row = gx.data() + static_cast<std::size_t>(v) * w;
    // Maxima whose estimator window reaches a border column (g = 0) are left out.
    for (int u = kStencilHalf; u + kStencilHalf < w; ++u) {
      const int a = std::abs(row[u]);
      if (a == 0 || a < threshold) continue;
      if (a <= std::abs(row[u - 1]) || a < std::abs(row[u + 1])) continue;
      const auto pixel = MakeEdgePixel(row, u, v, row[u] > 0 ? 1 : -1, camera, method);
      if (pixel) pixels.push_back(*pixel);
    }
  }
  return pixels;
}

// The members of a window of `sorted` (indices into `pixels`, ascending by
// column): the strongest pixel of each row, ordered by row.
std::vector<int> OnePerRow(const std::vector<EdgePixel>& pixels, const std::vector<int>& sorted,
                           std::size_t first, std::size_t last) {
  std::vector<int> members(sorted.begin() + first, sorted.begin() + last);
  std::sort(members.begin(), members.end(), [&](int a, int b) {
    const EdgePixel &pa = pixels[a], &pb = pixels[b];
    if (pa.v != pb.v) return pa.v < pb.v;
    if (pa.strength != pb.strength) return pa.strength > pb.strength;
    return pa.u < pb.u;
  });
  members.erase(std::unique(members.begin(), members.end(),
                            [&](int a, int b) { return pixels[a].v == pixels[b].v; }),
                members.end());
  return members;
}

// Line candidates of one polarity (§3.4, step 4): repeatedly the densest
// window of corrected columns, re-centred on its pixels' mean; its pixels are
// then used up, so a straight edge whose columns straddle a bin boundary
// yields one line, not two.
std::vector<std::vector<int>> GroupColumns(const std::vector<EdgePixel>& pixels, int polarity,
                                           const VerticalEdgeOptions& options) {
  std::vector<int> sorted;
  for (int i = 0; i < static_cast<int>(pixels.size()); ++i) {
    if (pixels[i].polarity == polarity) sorted.push_back(i);
  }
  auto x = [&](std::size_t k) { return pixels[sorted[k]].column_px; };
  std::sort(sorted.begin(), sorted.end(), [&](int a, int b) {
    const EdgePixel &pa = pixels[a], &pb = pixels[b];
    if (pa.column_px != pb.column_px) return pa.column_px < pb.column_px;
    return pa.v != pb.v ? pa.v < pb.v : pa.u < pb.u;
  });
  const double window = options.column_window_px;
  const auto min_pixels = static_cast<std::size_t>(options.min_pixels);
  std::vector<std::vector<int>> groups;
  while (sorted.size() >= min_pixels) {
    std::size_t best = 0, best_count = 0;
    for (std::size_t i = 0, j = 0; i < sorted.size(); ++i) {
      while (j < sorted.size() && x(j) <= x(i) + window) ++j;
      if (j - i > best_count) best = i, best_count = j - i;
    }
    if (best_count < min_pixels) break;
    std::size_t lo = best, hi = best + best_count;
    for (int it = 0; it < kCentreIterations; ++it) {
      double sum = 0.0;
      for (std::size_t k = lo; k < hi; ++k) sum += x(k);
      const double centre = sum / static_cast<double>(hi - lo);
      std::size_t new_lo = lo, new_hi = hi;
      while (new_lo > 0 && x(new_lo - 1) >= centre - 0.5 * window) --new_lo;
      while (new_lo < hi && x(new_lo) < centre - 0.5 * window) ++new_lo;
      while (new_hi < sorted.size() && x(new_hi) <= centre + 0.5 * window) ++new_hi;
      while (new_hi > new_lo && x(new_hi - 1) > centre + 0.5 * window) --new_hi;
      if (new_hi == new_lo) break;
      lo = new_lo, hi = new_hi;
    }
    groups.push_back(OnePerRow(pixels, sorted, lo, hi));
    const std::size_t used_lo = std::min(lo, best), used_hi = std::max(hi, best + best_count);
    sorted.erase(sorted.begin() + used_lo, sorted.begin() + used_hi);
  }
  return groups;
}

// Var of the weighted mean sum w_i x_i / sum w_i, w_i = 1 / Var(x_i), for the
// grey-level variance `noise_var`: sum_ij w_i w_j C_ij / (sum w)^2, where the
// covariance of two pixels 1 or 2 rows apart (their Sobel kernels share rows)
// is noise_var kRowOverlap[d] sum_k s_i(k) s_j(k - du), s the stencils.
// Without it the variance would be low by up to 8/3 (a long uniform line).
double WeightedMeanVariance(const std::vector<EdgePixel>& pixels, const std::vector<int>& members,
                            double noise_var, double sum_w) {
  double cross = 0.0;
  for (std::size_t a = 0; a < members.size(); ++a) {
    const EdgePixel& pa = pixels[members[a]];
    const double w_a = 1.0 / (noise_var * pa.unit_variance);
    for (std::size_t b = a + 1; b < members.size(); ++b) {
      const EdgePixel& pb = pixels[members[b]];
      const int dv = pb.v - pa.v;
      if (dv >= static_cast<int>(kRowOverlap.size())) break;
      const int du = pb.u - pa.u;
      double overlap = 0.0;
      for (int k = std::max(0, du); k < std::min(kStencilSize, kStencilSize + du); ++k) {
        overlap += pa.stencil[k] * pb.stencil[k - du];
      }
      const double w_b = 1.0 / (noise_var * pb.unit_variance);
      cross += w_a * w_b * noise_var * kRowOverlap[dv] * overlap;
    }
  }
  return (sum_w + 2.0 * cross) / (sum_w * sum_w);
}

// The line through `members` (§3.4, step 4), or nothing if it fails the
// pixel count or fill.
bool FitEdge(const std::vector<EdgePixel>& pixels, const std::vector<int>& members,
             const CameraIntrinsics& camera, double noise_var, const VerticalEdgeOptions& options,
             VerticalEdge* edge) {
  if (static_cast<int>(members.size()) < options.min_pixels) return false;
  const int first_row = pixels[members.front()].v, last_row = pixels[members.back()].v;
  const double fill = static_cast<double>(members.size()) / (last_row - first_row + 1);
  if (fill < options.min_fill) return false;
  double sum_w = 0.0, sum_wx = 0.0, sum_step = 0.0;
  for (int i : members) {
    const double w = 1.0 / (noise_var * pixels[i].unit_variance);
    sum_w += w;
    sum_wx += w * pixels[i].column_px;
    sum_step += pixels[i].step_grey;
  }
  const double column = sum_wx / sum_w;
  const double var_column = WeightedMeanVariance(pixels, members, noise_var, sum_w) +
                            options.calibration_sigma_px * options.calibration_sigma_px;
  // phi = atan((c_u - x) / f): d phi / d x = -f / (f^2 + (c_u - x)^2).
  const double f = camera.focal_px, offset = camera.center_u_px - column;
  const double dphi = f / (f * f + offset * offset);
  edge->bearing_rad = BearingOfColumn(camera, column);
  edge->variance_rad2 = dphi * dphi * var_column;
  edge->column_px = column;
  edge->pixels = static_cast<int>(members.size());
  edge->first_row = first_row;
  edge->last_row = last_row;
  edge->polarity = pixels[members.front()].polarity;
  edge->contrast = sum_step / static_cast<double>(members.size());
  return true;
}

}  // namespace

void VerticalEdgeOptions::Validate() const {
  Require(std::isfinite(image_noise_sigma_grey) && image_noise_sigma_grey >= 0.0,
          "image_noise_sigma_grey", "a finite value >= 0");
  Require(std::isfinite(min_contrast_grey) && min_contrast_grey >= 0.0, "min_contrast_grey",
          "a finite value >= 0");
  Require(std::isfinite(noise_threshold_factor) && noise_threshold_factor >= 0.0,
          "noise_threshold_factor", "a finite value >= 0");
  Require(std::isfinite(column_window_px) && column_window_px > 0.0, "column_window_px",
          "a finite value > 0");
  Require(min_pixels >= 2, "min_pixels", "an integer >= 2");
  Require(std::isfinite(min_fill) && min_fill > 0.0 && min_fill <= 1.0, "min_fill",
          "a value in (0, 1]");
  Require(std::isfinite(calibration_sigma_px) && calibration_sigma_px >= 0.0,
          "calibration_sigma_px", "a finite value >= 0");
}

std::vector<VerticalEdge> ExtractVerticalEdges(const GrayImage& image,
                                               const CameraIntrinsics& camera,
                                               const VerticalEdgeOptions& options,
                                               VerticalEdgeStats* stats) {
  options.Validate();
  camera.Validate();
  if (image.width != camera.width_px || image.height != camera.height_px ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * image.height) {
    throw std::invalid_argument("ExtractVerticalEdges: the image is " +
                                std::to_string(image.width) + " x " + std::to_string(image.height) +
                                ", the camera's " + std::to_string(camera.width_px) + " x " +
                                std::to_string(camera.height_px));
  }
  const int w = image.width, h = image.height;
  const std::vector<std::int16_t> gx = SobelX(image);
  const double gradient_sigma = RobustGradientSigma(gx, w, h);
  const double threshold = std::max(kSobelGain * options.min_contrast_grey,
                                    options.noise_threshold_factor * gradient_sigma);
  double noise_var =
      options.image_noise_sigma_grey * options.image_noise_sigma_grey + kQuantizationVariance;
  if (options.estimate_image_noise) {
    noise_var = std::max(gradient_sigma * gradient_sigma / kSobelNoiseGain, kQuantizationVariance);
  }
  const std::vector<EdgePixel> pixels =
      FindEdgePixels(gx, w, h, threshold, camera, options.subpixel);
  std::vector<VerticalEdge> edges;
  for (int polarity : {1, -1}) {
    for (const std::vector<int>& members : GroupColumns(pixels, polarity, options)) {
      VerticalEdge edge;
      if (FitEdge(pixels, members, camera, noise_var, options, &edge)) edges.push_back(edge);
    }
  }
  std::sort(edges.begin(), edges.end(), [](const VerticalEdge& a, const VerticalEdge& b) {
    return a.column_px != b.column_px ? a.column_px < b.column_px : a.polarity > b.polarity;
  });
  if (stats != nullptr) {
    stats->gradient_threshold = threshold;
    stats->noise_sigma_grey = std::sqrt(noise_var);
    stats->edge_pixels = static_cast<int>(pixels.size());
  }
  return edges;
}

}  // namespace pavilion::core
