#include "core/features/vertical_edges.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/features/camera_model.h"
#include "core/math/chi_square.h"
#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kFov54 = 54.0 * kPi / 180.0;  // the objective of §2.4
constexpr int kWidth = 640;
constexpr int kHeight = 480;
// Grey levels of the synthetic scenes: a pole kStep brighter than the wall.
constexpr double kWall = 90.0;
constexpr double kStep = 60.0;

// The §2.4 camera, with eq. 3.23's correction k1 = -0.25, k2 = 0.08 (up to
// 30 px at the corners) or without distortion.
CameraIntrinsics Camera(bool distorted) {
  CameraIntrinsics c = CameraIntrinsics::FromHorizontalFov(kWidth, kHeight, kFov54);
  if (distorted) c.radial = {-0.25, 0.08, 0.0, 0.0};
  return c;
}

// A vertical band of the pinhole image: undistorted columns [left, right),
// rows [top, bottom), `level` grey levels above the wall.
struct Band {
  double left = 0.0, right = 0.0;
  double level = kStep;
  int top = 0, bottom = kHeight;
};

// A pinhole image of bands on the wall, their vertical edges anti-aliased
// by area coverage. Edges at multiples of 1 / level px are exact in 8 bits.
GrayImage PinholeImage(const std::vector<Band>& bands) {
  GrayImage image(kWidth, kHeight, static_cast<std::uint8_t>(kWall));
  for (int v = 0; v < kHeight; ++v) {
    for (int u = 0; u < kWidth; ++u) {
      double grey = kWall;
      for (const Band& b : bands) {
        if (v < b.top || v >= b.bottom) continue;
        grey += b.level * std::max(0.0, std::min(u + 1.0, b.right) - std::max(u + 0.0, b.left));
      }
      image.at(u, v) = static_cast<std::uint8_t>(std::clamp(grey, 0.0, 255.0) + 0.5);
    }
  }
  return image;
}

// Normalized bearing errors of the Monte-Carlo trials, pooled over edges.
struct ErrorStats {
  std::vector<double> z;          // error / predicted sigma
  double sum_sq_error_px2 = 0.0;  // in undistorted columns, for the report
  double sum_var_px2 = 0.0;
  double sum_error_px = 0.0;
};

// `trials` images of one pole at a random sub-pixel position and width
// (known bearings), distorted by DistortImage, with grey-level noise
// `sigma_n` drawn from an independent stream per trial. Every trial must
// yield exactly the pole's two edges.
ErrorStats MonteCarlo(const CameraIntrinsics& camera, const VerticalEdgeOptions& options,
                      double sigma_n, int trials, std::uint64_t seed) {
  const DistortionMap lens(camera);
  ErrorStats stats;
  for (int t = 0; t < trials; ++t) {
    RandomStream stream(seed, static_cast<std::uint64_t>(t));
    const double left = std::round(stream.Uniform(80.0, 520.0) * kStep) / kStep;
    const double right = left + std::round(stream.Uniform(12.0, 40.0) * kStep) / kStep;
    GrayImage image = lens.Apply(PinholeImage({Band{left, right}}));
    AddImageNoise(sigma_n, stream, &image);
    const std::vector<VerticalEdge> edges = ExtractVerticalEdges(image, camera, options);
    EXPECT_EQ(edges.size(), 2u) << "trial " << t << ", pole [" << left << ", " << right << ")";
    if (edges.size() != 2u) continue;
    EXPECT_EQ(edges[0].polarity, 1);
    EXPECT_EQ(edges[1].polarity, -1);
    const double truth[2] = {left, right};
    for (int k = 0; k < 2; ++k) {
      const double error = edges[k].bearing_rad - BearingOfColumn(camera, truth[k]);
      stats.z.push_back(error / std::sqrt(edges[k].variance_rad2));
      const double dphi_dx =  // rad per px near the truth
          std::abs(BearingOfColumn(camera, truth[k]) - BearingOfColumn(camera, truth[k] + 1e-3)) /
          1e-3;
      stats.sum_error_px += edges[k].column_px - truth[k];
      stats.sum_sq_error_px2 += (edges[k].column_px - truth[k]) * (edges[k].column_px - truth[k]);
      stats.sum_var_px2 += edges[k].variance_rad2 / (dphi_dx * dphi_dx);
    }
  }
  return stats;
}

// The predicted (phi, sigma_phi^2) are consistent: the mean normalized error
// is zero within its 99% interval and the mean squared normalized error lies
// in the 99% chi^2(n) / n band.
void ExpectConsistent(const ErrorStats& s, const char* what) {
  const int n = static_cast<int>(s.z.size());
  ASSERT_GT(n, 100) << what;
  double sum = 0.0, sum_sq = 0.0;
  for (double z : s.z) {
    sum += z;
    sum_sq += z * z;
  }
  const double mean_z = sum / n;
  const double nees = sum_sq / n;
  const double lo = ChiSquareQuantile(0.005, n) / n, hi = ChiSquareQuantile(0.995, n) / n;
  std::printf(
      "%s: %d edges, bias %.5f px, sample sigma %.5f px, predicted sigma %.5f px, "
      "mean z %.3f, mean z^2 %.3f (band [%.3f, %.3f])\n",
      what, n, s.sum_error_px / n, std::sqrt(s.sum_sq_error_px2 / n), std::sqrt(s.sum_var_px2 / n),
      mean_z, nees, lo, hi);
  EXPECT_LT(std::abs(mean_z) * std::sqrt(n), NormalQuantile(0.995)) << what;
  EXPECT_GT(nees, lo) << what;
  EXPECT_LT(nees, hi) << what;
}

VerticalEdgeOptions NoiseOnly(double sigma_n, SubpixelMethod method) {
  VerticalEdgeOptions o;
  o.image_noise_sigma_grey = sigma_n;
  o.calibration_sigma_px = 0.0;  // the test scenes have no calibration error
  o.subpixel = method;
  return o;
}

constexpr int kTrials = 250;  // 500 edges: the 99% chi^2 band is [0.85, 1.17]
// Grey-level noise of the Monte-Carlo runs: sigma_n / step = 1/15. The
// first-order model holds to a few percent there: with 500 trials for each
// of seeds 20-25, mean z^2 1.034 (pinhole) and 1.031 (distorted) over 6000
// edges each, mean z 0.003 and 0.026. The estimators' second-order bias grows
// as (sigma_n / step)^2 and does not average out along a line.
constexpr double kSigmaN = 4.0;

// Monte-Carlo over poles at random sub-pixel positions, with the lens of §2.4:
// the centroid's first-order uncertainty (noise propagated through Sobel,
// centroid, eq. 3.23 and the row-correlated weighted mean) is consistent.
// Without the correlation of adjacent rows the mean z^2 would be about 8/3.
TEST(VerticalEdgesTest, UncertaintyIsConsistentThroughTheLens) {
  const VerticalEdgeOptions o = NoiseOnly(kSigmaN, SubpixelMethod::kCentroid);
  ExpectConsistent(MonteCarlo(Camera(true), o, kSigmaN, kTrials, 11), "distorted");
}

// The same without distortion (DistortImage is then the identity).
TEST(VerticalEdgesTest, UncertaintyIsConsistentWithoutDistortion) {
  const VerticalEdgeOptions o = NoiseOnly(kSigmaN, SubpixelMethod::kCentroid);
  ExpectConsistent(MonteCarlo(Camera(false), o, kSigmaN, kTrials, 12), "pinhole");
}

// Worst |column - truth| over noise-free poles at random sub-pixel positions.
double WorstNoiseFreeError(const CameraIntrinsics& camera, SubpixelMethod method) {
  const DistortionMap lens(camera);
  VerticalEdgeOptions o = NoiseOnly(0.0, method);
  RandomStream stream(5, static_cast<std::uint64_t>(method));
  double worst = 0.0;
  for (int t = 0; t < 40; ++t) {
    const double left = std::round(stream.Uniform(80.0, 520.0) * kStep) / kStep;
    const double right = left + std::round(stream.Uniform(12.0, 40.0) * kStep) / kStep;
    const auto edges =
        ExtractVerticalEdges(lens.Apply(PinholeImage({Band{left, right}})), camera, o);
    EXPECT_EQ(edges.size(), 2u);
    if (edges.size() != 2u) continue;
    worst = std::max(
        {worst, std::abs(edges[0].column_px - left), std::abs(edges[1].column_px - right)});
  }
  return worst;
}

// Both estimators are exact on area-coverage edges of a pinhole image; through
// DistortImage's bilinear resampling the centroid stays within 0.01 px and
// the parabola within 0.1 px (SubpixelMethod), the default calibration floor.
TEST(VerticalEdgesTest, NoiseFreeEdgesAreExactOrWithinTheirStatedBias) {
  EXPECT_LT(WorstNoiseFreeError(Camera(false), SubpixelMethod::kCentroid), 1e-9);
  EXPECT_LT(WorstNoiseFreeError(Camera(false), SubpixelMethod::kParabola), 1e-9);
  const double centroid = WorstNoiseFreeError(Camera(true), SubpixelMethod::kCentroid);
  const double parabola = WorstNoiseFreeError(Camera(true), SubpixelMethod::kParabola);
  std::printf("noise-free through the lens: centroid %.4f px, parabola %.4f px\n", centroid,
              parabola);
  EXPECT_LT(centroid, 0.01);
  EXPECT_LT(parabola, 0.1);
  EXPECT_GT(parabola, 0.01);  // the parabola's bias is real: the floor is needed for it
}

// With the default options (0.1 px calibration floor) the parabola's bias
// through the lens is covered: every truth lies in its edge's 99% interval.
TEST(VerticalEdgesTest, ParabolaWithTheFloorCoversItsBias) {
  VerticalEdgeOptions o;
  o.subpixel = SubpixelMethod::kParabola;
  o.image_noise_sigma_grey = kSigmaN;
  const ErrorStats s = MonteCarlo(Camera(true), o, kSigmaN, 60, 14);
  ASSERT_EQ(s.z.size(), 120u);
  for (double z : s.z) EXPECT_LT(std::abs(z), NormalQuantile(0.995));
}

// A uniform wall with noise has no edges: the dynamic threshold (5 robust
// sigmas of gx) keeps noise maxima out, which the absolute one alone does not.
TEST(VerticalEdgesTest, UniformNoisyWallHasNoEdges) {
  const CameraIntrinsics camera = Camera(true);
  for (double sigma_n : {2.0, 8.0}) {
    for (int t = 0; t < 20; ++t) {
      GrayImage image(kWidth, kHeight, 120);
      RandomStream stream(17, static_cast<std::uint64_t>(t));
      AddImageNoise(sigma_n, stream, &image);
      VerticalEdgeOptions o;
      o.image_noise_sigma_grey = sigma_n;
      VerticalEdgeStats stats;
      EXPECT_TRUE(ExtractVerticalEdges(image, camera, o, &stats).empty());
      EXPECT_LT(stats.edge_pixels, 20) << "sigma_n " << sigma_n;
      // The threshold follows the noise: 5 sigma of gx = 5 sqrt(12) sigma_n.
      EXPECT_NEAR(stats.gradient_threshold,
                  std::max(40.0, 5.0 * std::sqrt(12.0 * (sigma_n * sigma_n + 1.0 / 12.0))),
                  0.1 * stats.gradient_threshold);
      if (sigma_n == 8.0) {
        o.noise_threshold_factor = 0.0;
        EXPECT_TRUE(ExtractVerticalEdges(image, camera, o, &stats).empty());
        EXPECT_GT(stats.edge_pixels, 5000);
      }
    }
  }
}

// estimate_image_noise recovers sigma_n (with quantization) from the image.
TEST(VerticalEdgesTest, EstimatesTheImageNoise) {
  const CameraIntrinsics camera = Camera(true);
  GrayImage image = DistortImage(PinholeImage({Band{200.0, 230.0}, Band{400.0, 420.0}}), camera);
  RandomStream stream(19, 0);
  AddImageNoise(4.0, stream, &image);
  VerticalEdgeOptions o;
  o.estimate_image_noise = true;
  VerticalEdgeStats stats;
  EXPECT_EQ(ExtractVerticalEdges(image, camera, o, &stats).size(), 4u);
  EXPECT_NEAR(stats.noise_sigma_grey, std::sqrt(16.0 + 1.0 / 12.0), 0.2);
}

// An office-like scene through the lens: door frames darker than the wall,
// poles and a cupboard brighter, some of partial height. Every edge is found
// once, with its polarity and step, ordered by column (bearing descending).
TEST(VerticalEdgesTest, FindsEveryEdgeOfAnOfficeScene) {
  const CameraIntrinsics camera = Camera(true);
  const std::vector<Band> scene = {
      {40.5, 70.25, -50.0, 0, kHeight},   // door frame, dark
      {150.0, 162.5, 80.0, 0, kHeight},   // pole
      {262.75, 330.0, 40.0, 100, 420},    // cupboard, partial height
      {420.2, 426.8, 100.0, 0, kHeight},  // thin pole
      {500.0, 590.0, -40.0, 0, 300},      // dark panel, upper part
  };
  GrayImage image = DistortImage(PinholeImage(scene), camera);
  RandomStream stream(23, 0);
  AddImageNoise(2.0, stream, &image);
  VerticalEdgeOptions o;
  const std::vector<VerticalEdge> edges = ExtractVerticalEdges(image, camera, o);
  ASSERT_EQ(edges.size(), 2 * scene.size());
  for (std::size_t i = 0; i < scene.size(); ++i) {
    const Band& b = scene[i];
    const int sign = b.level > 0 ? 1 : -1;
    const VerticalEdge* pair[2] = {&edges[2 * i], &edges[2 * i + 1]};
    const double truth[2] = {b.left, b.right};
    for (int k = 0; k < 2; ++k) {
      const VerticalEdge& e = *pair[k];
      EXPECT_EQ(e.polarity, k == 0 ? sign : -sign) << "band " << i;
      EXPECT_NEAR(e.bearing_rad, BearingOfColumn(camera, truth[k]),
                  NormalQuantile(0.995) * std::sqrt(e.variance_rad2))
          << "band " << i;
      EXPECT_NEAR(e.contrast, std::abs(b.level), 0.1 * std::abs(b.level)) << "band " << i;
      // Rows: the band's distorted extent, less the Sobel kernel's border row.
      const double top = DistortPoint(camera, Eigen::Vector2d(truth[k], b.top)).y();
      const double bottom = DistortPoint(camera, Eigen::Vector2d(truth[k], b.bottom)).y();
      EXPECT_NEAR(e.first_row, std::max(top, 1.0), 3.0) << "band " << i;
      EXPECT_NEAR(e.last_row, std::min(bottom, kHeight - 2.0), 3.0) << "band " << i;
      EXPECT_GE(e.pixels, 0.9 * (e.last_row - e.first_row + 1)) << "band " << i;
    }
  }
  for (std::size_t i = 1; i < edges.size(); ++i) {
    EXPECT_GT(edges[i - 1].bearing_rad, edges[i].bearing_rad);
    EXPECT_LT(edges[i - 1].column_px, edges[i].column_px);
  }
}

// Two edges of one polarity 5 px apart stay two lines; edges too short
// (min_pixels) or too sparse along their rows (min_fill) are no lines.
TEST(VerticalEdgesTest, GroupsColumnsIntoLines) {
  const CameraIntrinsics camera = Camera(true);
  VerticalEdgeOptions o;
  const auto extract = [&](const std::vector<Band>& bands) {
    GrayImage image = DistortImage(PinholeImage(bands), camera);
    RandomStream stream(29, 0);
    AddImageNoise(2.0, stream, &image);
    return ExtractVerticalEdges(image, camera, o);
  };
  // A staircase: two steps up, then one down.
  const auto stairs = extract({Band{300.0, 400.0, 40.0}, Band{305.0, 400.0, 40.0}});
  ASSERT_EQ(stairs.size(), 3u);
  EXPECT_NEAR(stairs[0].column_px, 300.0, 0.1);
  EXPECT_NEAR(stairs[1].column_px, 305.0, 0.1);
  EXPECT_EQ(stairs[1].polarity, 1);
  EXPECT_NEAR(stairs[2].column_px, 400.0, 0.1);
  EXPECT_EQ(extract({Band{300.0, 320.0, 60.0, 200, 250}}).size(), 0u);  // 50 rows < 60
  o.min_pixels = 40;
  EXPECT_EQ(extract({Band{300.0, 320.0, 60.0, 200, 250}}).size(), 2u);
  o = VerticalEdgeOptions{};
  std::vector<Band> dashes;  // 10 rows of every 40: fill 0.25
  for (int top = 0; top < kHeight; top += 40)
    dashes.push_back(Band{300.0, 320.0, 60.0, top, top + 10});
  EXPECT_EQ(extract(dashes).size(), 0u);
  o.min_fill = 0.2;
  EXPECT_EQ(extract(dashes).size(), 2u);
}

void ExpectInvalid(const VerticalEdgeOptions& o, const std::string& field) {
  try {
    o.Validate();
    ADD_FAILURE() << "no error for " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("VerticalEdgeOptions." + field), std::string::npos)
        << e.what();
  }
}

// Validate names the offending field; the image must be the camera's size.
TEST(VerticalEdgesTest, ValidatesOptionsAndInput) {
  EXPECT_NO_THROW(VerticalEdgeOptions{}.Validate());
  VerticalEdgeOptions o;
  o.image_noise_sigma_grey = -1.0;
  ExpectInvalid(o, "image_noise_sigma_grey");
  o = {};
  o.min_contrast_grey = NAN;
  ExpectInvalid(o, "min_contrast_grey");
  o = {};
  o.noise_threshold_factor = -0.5;
  ExpectInvalid(o, "noise_threshold_factor");
  o = {};
  o.column_window_px = 0.0;
  ExpectInvalid(o, "column_window_px");
  o = {};
  o.min_pixels = 1;
  ExpectInvalid(o, "min_pixels");
  o = {};
  o.min_fill = 1.5;
  ExpectInvalid(o, "min_fill");
  o = {};
  o.calibration_sigma_px = INFINITY;
  ExpectInvalid(o, "calibration_sigma_px");
  o = {};
  EXPECT_THROW(ExtractVerticalEdges(GrayImage(320, 240), Camera(true), o), std::invalid_argument);
  CameraIntrinsics bad = Camera(true);
  bad.focal_px = -1.0;
  EXPECT_THROW(ExtractVerticalEdges(GrayImage(kWidth, kHeight), bad, o), std::invalid_argument);
  o.min_pixels = 0;
  EXPECT_THROW(ExtractVerticalEdges(GrayImage(kWidth, kHeight), Camera(true), o),
               std::invalid_argument);
}

// Tiny images are handled (no edge fits).
TEST(VerticalEdgesTest, TinyImages) {
  for (int size : {1, 3, 6}) {
    CameraIntrinsics c = CameraIntrinsics::FromHorizontalFov(size, size, 1.0);
    EXPECT_TRUE(ExtractVerticalEdges(GrayImage(size, size, 50), c, VerticalEdgeOptions{}).empty());
  }
}

}  // namespace
}  // namespace pavilion::core
