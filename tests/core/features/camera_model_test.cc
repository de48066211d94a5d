#include "core/features/camera_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kFov54 = 54.0 * kPi / 180.0;  // the objective of §2.4 (fig. 2.8)

// The camera of §2.4 with eq. 3.23's correction shrinking the radius
// (k1 < 0: the lens magnifies towards the border).
CameraIntrinsics Pincushion() {
  CameraIntrinsics c = CameraIntrinsics::FromHorizontalFov(640, 480, kFov54);
  c.radial = {-0.25, 0.08, 0.0, 0.0};
  return c;
}

// The same with the correction growing the radius (k1 > 0: barrel, the
// lens compresses the border), all four coefficients in use.
CameraIntrinsics Barrel() {
  CameraIntrinsics c = CameraIntrinsics::FromHorizontalFov(640, 480, kFov54);
  c.radial = {0.2, 0.05, -0.02, 0.01};
  c.center_u_px = 323.7;  // an off-centre principal point
  c.center_v_px = 236.2;
  return c;
}

// The focal length and centre of a centred pinhole (§3.4's C_x).
TEST(CameraModelTest, FocalFromHorizontalFov) {
  const CameraIntrinsics c = CameraIntrinsics::FromHorizontalFov(640, 480, kFov54);
  EXPECT_NEAR(c.focal_px, 320.0 / std::tan(27.0 * kPi / 180.0), 1e-9);
  EXPECT_NEAR(c.focal_px, 628.03, 0.01);
  EXPECT_EQ(c.center_u_px, 320.0);
  EXPECT_EQ(c.center_v_px, 240.0);
  EXPECT_FALSE(c.distorted());
  // The image border is at half the field of view.
  EXPECT_NEAR(BearingOfColumn(c, 0.0), 0.5 * kFov54, 1e-12);
  EXPECT_NEAR(BearingOfColumn(c, 640.0), -0.5 * kFov54, 1e-12);
  EXPECT_THROW(CameraIntrinsics::FromHorizontalFov(640, 480, kPi), std::invalid_argument);
  EXPECT_THROW(CameraIntrinsics::FromHorizontalFov(640, 480, 0.0), std::invalid_argument);
  EXPECT_THROW(CameraIntrinsics::FromHorizontalFov(0, 480, 1.0), std::invalid_argument);
}

// Bearings are positive to the left and ColumnOfBearing inverts BearingOfColumn.
TEST(CameraModelTest, BearingColumnRoundTrip) {
  const CameraIntrinsics c = Barrel();
  for (double u = -50.0; u <= 690.0; u += 7.3) {
    EXPECT_NEAR(ColumnOfBearing(c, BearingOfColumn(c, u)), u, 1e-9);
  }
  EXPECT_GT(BearingOfColumn(c, 100.0), 0.0);
  EXPECT_LT(BearingOfColumn(c, 500.0), 0.0);
  EXPECT_NEAR(BearingOfColumn(c, c.center_u_px), 0.0, 1e-15);
  // A point (x, y) = (2, 0.5) m in the camera frame: u = c_u - f y / x.
  EXPECT_NEAR(BearingOfColumn(c, c.center_u_px - c.focal_px * 0.25), std::atan2(0.5, 2.0), 1e-12);
}

// Eq. 3.23 as written: the correction scales the offset from the centre.
TEST(CameraModelTest, UndistortPointIsEquation323) {
  const CameraIntrinsics c = Barrel();
  const Eigen::Vector2d xd(600.0, 50.0);
  const Eigen::Vector2d d = xd - Eigen::Vector2d(c.center_u_px, c.center_v_px);
  const double r2 = d.squaredNorm() / (c.focal_px * c.focal_px);
  const double s = 1.0 + 0.2 * r2 + 0.05 * r2 * r2 - 0.02 * r2 * r2 * r2 + 0.01 * std::pow(r2, 4);
  const Eigen::Vector2d expected = Eigen::Vector2d(c.center_u_px, c.center_v_px) + s * d;
  EXPECT_NEAR((UndistortPoint(c, xd) - expected).norm(), 0.0, 1e-9);
  EXPECT_EQ(UndistortPoint(c, Eigen::Vector2d(c.center_u_px, c.center_v_px)),
            Eigen::Vector2d(c.center_u_px, c.center_v_px));
}

// DistortPoint inverts UndistortPoint to 1e-6 px over the whole image, both ways.
TEST(CameraModelTest, DistortUndistortRoundTrip) {
  for (const CameraIntrinsics& c : {Pincushion(), Barrel()}) {
    double worst = 0.0;
    for (double v = 0.0; v <= 480.0; v += 4.0) {
      for (double u = 0.0; u <= 640.0; u += 4.0) {
        const Eigen::Vector2d p(u, v);
        worst = std::max(worst, (UndistortPoint(c, DistortPoint(c, p)) - p).norm());
        worst = std::max(worst, (DistortPoint(c, UndistortPoint(c, p)) - p).norm());
      }
    }
    EXPECT_LT(worst, 1e-6);
  }
  // The distortion is not small: the corner moves by tens of pixels.
  const CameraIntrinsics c = Pincushion();
  EXPECT_GT((DistortPoint(c, Eigen::Vector2d(0, 0)) - Eigen::Vector2d(0, 0)).norm(), 20.0);
}

// Where r_u(r_d) folds (dr_u/dr_d <= 0 before the point), DistortPoint throws.
TEST(CameraModelTest, DistortPointThrowsBeyondTheFold) {
  CameraIntrinsics c = CameraIntrinsics::FromHorizontalFov(640, 480, kFov54);
  c.radial = {-1.0, 0.0, 0.0, 0.0};  // r_u = r_d - r_d^3 peaks at 0.385 (r_d = 0.577)
  const double f = c.focal_px;
  const Eigen::Vector2d inside(c.center_u_px + 0.3 * f, c.center_v_px);
  EXPECT_NEAR((UndistortPoint(c, DistortPoint(c, inside)) - inside).norm(), 0.0, 1e-9);
  EXPECT_LT((DistortPoint(c, inside) - Eigen::Vector2d(c.center_u_px, c.center_v_px)).norm(),
            f / std::sqrt(3.0));  // on the principal branch
  EXPECT_THROW(DistortPoint(c, Eigen::Vector2d(c.center_u_px + 0.39 * f, c.center_v_px)),
               std::invalid_argument);
  // A fold with a second rising branch beyond it (k2 > 0) is caught too.
  c.radial = {-1.0, 0.3, 0.0, 0.0};
  EXPECT_THROW(DistortPoint(c, Eigen::Vector2d(c.center_u_px + 0.6 * f, c.center_v_px)),
               std::invalid_argument);
}

// UndistortPointJacobian against central differences at random points.
TEST(CameraModelTest, UndistortJacobianMatchesNumerical) {
  RandomStream rng(3, 1);
  for (const CameraIntrinsics& c : {Pincushion(), Barrel()}) {
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector2d p(rng.Uniform(0, 640), rng.Uniform(0, 480));
      const Eigen::Matrix2d J = UndistortPointJacobian(c, p);
      constexpr double kStep = 1e-4;
      Eigen::Matrix2d numerical;
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d e = Eigen::Vector2d::Unit(k) * kStep;
        numerical.col(k) = (UndistortPoint(c, p + e) - UndistortPoint(c, p - e)) / (2 * kStep);
      }
      EXPECT_LT((J - numerical).norm(), 1e-7) << "at " << p.transpose();
    }
  }
}

// A pinhole image of a vertical bar (anti-aliased by area coverage) of width
// `width_px` centred on undistorted column `centre_px`, on black.
GrayImage Bar(double centre_px, double width_px) {
  GrayImage image(640, 480, 0);
  const double left = centre_px - 0.5 * width_px, right = centre_px + 0.5 * width_px;
  for (int u = 0; u < 640; ++u) {
    const double cover = std::max(0.0, std::min(u + 1.0, right) - std::max(u + 0.0, left));
    for (int v = 0; v < 480; ++v) image.at(u, v) = static_cast<std::uint8_t>(200.0 * cover + 0.5);
  }
  return image;
}

// The distorted column of undistorted column x on distorted row centre y_d.
double PredictedColumn(const CameraIntrinsics& c, double x, double y_d) {
  double y_u = y_d;  // fixed point on the row: the distortion is smooth
  for (int i = 0; i < 50; ++i) y_u += y_d - DistortPoint(c, Eigen::Vector2d(x, y_u)).y();
  return DistortPoint(c, Eigen::Vector2d(x, y_u)).x();
}

// A bar lands where DistortPoint predicts, row by row (intensity centroid).
TEST(CameraModelTest, DistortImageMovesABarWhereDistortPointPredicts) {
  for (const CameraIntrinsics& c : {Pincushion(), Barrel()}) {
    for (double centre : {40.3, 171.8, 320.0, 505.55, 610.2}) {
      const GrayImage distorted = DistortImage(Bar(centre, 5.0), c);
      double worst = 0.0;
      for (int v = 0; v < 480; v += 17) {
        const double predicted = PredictedColumn(c, centre, v + 0.5);
        if (predicted < 12.0 || predicted > 628.0) continue;
        double sum = 0.0, moment = 0.0;
        for (int u = static_cast<int>(predicted) - 10; u <= static_cast<int>(predicted) + 10; ++u) {
          sum += distorted.at(u, v);
          moment += distorted.at(u, v) * (u + 0.5);
        }
        worst = std::max(worst, std::abs(moment / sum - predicted));
      }
      EXPECT_LT(worst, 0.25) << "bar at " << centre;
    }
  }
}

// Without distortion the image is unchanged; with barrel distortion the
// corners, which see beyond the pinhole image, are black; the map equals the
// convenience function.
TEST(CameraModelTest, DistortImageIdentityBorderAndMap) {
  GrayImage image(640, 480, 0);
  RandomStream rng(8, 2);
  for (auto& p : image.pixels) p = static_cast<std::uint8_t>(rng.UniformInt(1, 255));
  const CameraIntrinsics plain = CameraIntrinsics::FromHorizontalFov(640, 480, kFov54);
  EXPECT_EQ(DistortImage(image, plain).pixels, image.pixels);
  const CameraIntrinsics barrel = Barrel();
  const GrayImage distorted = DistortImage(image, barrel);
  EXPECT_EQ(distorted.at(0, 0), 0);
  EXPECT_EQ(distorted.at(639, 479), 0);
  EXPECT_GT(distorted.at(320, 240), 0);
  const DistortionMap map(barrel);
  EXPECT_EQ(map.Apply(image).pixels, distorted.pixels);
  GrayImage reused(3, 3, 9);
  map.Apply(image, &reused);
  EXPECT_EQ(reused.pixels, distorted.pixels);
  EXPECT_EQ(reused.width, 640);
  EXPECT_THROW(DistortImage(GrayImage(320, 240), barrel), std::invalid_argument);
}

// A uniform image stays uniform (the weights sum to one, rounding is exact)
// where the lens sees inside the pinhole image.
TEST(CameraModelTest, DistortImageKeepsUniformLevels) {
  const GrayImage distorted = DistortImage(GrayImage(640, 480, 137), Pincushion());
  for (std::uint8_t p : distorted.pixels) ASSERT_EQ(p, 137);
}

// Tiny images (one row or column) are handled without reading out of bounds.
TEST(CameraModelTest, DistortImageTinySizes) {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 7}, std::pair{9, 1}}) {
    CameraIntrinsics c = CameraIntrinsics::FromHorizontalFov(w, h, 1.0);
    c.radial = {0.1, 0.0, 0.0, 0.0};
    const GrayImage out = DistortImage(GrayImage(w, h, 77), c);
    ASSERT_EQ(out.pixels.size(), static_cast<std::size_t>(w) * h);
    for (std::uint8_t p : out.pixels) EXPECT_LE(p, 77);
  }
}

// The noise has the requested sigma (plus rounding's 1/12), zero mean, and
// repeats with the seed.
TEST(CameraModelTest, ImageNoiseStatistics) {
  GrayImage image(640, 480, 128);
  RandomStream stream(21, 4);
  AddImageNoise(3.0, stream, &image);
  double sum = 0.0, sum_sq = 0.0;
  for (std::uint8_t p : image.pixels) {
    sum += p - 128.0;
    sum_sq += (p - 128.0) * (p - 128.0);
  }
  const double n = static_cast<double>(image.pixels.size());
  const double var = sum_sq / n - (sum / n) * (sum / n);
  // 307200 draws: sd of the mean 0.005, relative sd of the variance 0.26%.
  EXPECT_NEAR(sum / n, 0.0, 0.03);
  EXPECT_NEAR(var, 9.0 + 1.0 / 12.0, 9.0 * 0.02);
  GrayImage again(640, 480, 128);
  RandomStream same(21, 4);
  AddImageNoise(3.0, same, &again);
  EXPECT_EQ(again.pixels, image.pixels);
  GrayImage clipped(4, 4, 254);
  AddImageNoise(50.0, stream, &clipped);  // clamped to [0, 255]
  GrayImage untouched(4, 4, 10);
  AddImageNoise(0.0, stream, &untouched);
  EXPECT_EQ(untouched.pixels, GrayImage(4, 4, 10).pixels);
  EXPECT_THROW(AddImageNoise(-1.0, stream, &image), std::invalid_argument);
  EXPECT_THROW(AddImageNoise(NAN, stream, &image), std::invalid_argument);
}

void ExpectInvalid(const CameraIntrinsics& c, const std::string& field) {
  try {
    c.Validate();
    ADD_FAILURE() << "no error for " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

// Validate names the offending field.
TEST(CameraModelTest, ValidateNamesTheField) {
  const CameraIntrinsics good = Barrel();
  EXPECT_NO_THROW(good.Validate());
  CameraIntrinsics c = good;
  c.width_px = 0;
  ExpectInvalid(c, "width_px");
  c = good;
  c.height_px = -3;
  ExpectInvalid(c, "height_px");
  c = good;
  c.focal_px = 0.0;
  ExpectInvalid(c, "focal_px");
  c.focal_px = INFINITY;
  ExpectInvalid(c, "focal_px");
  c = good;
  c.center_u_px = NAN;
  ExpectInvalid(c, "center_u_px");
  c = good;
  c.center_v_px = INFINITY;
  ExpectInvalid(c, "center_v_px");
  c = good;
  c.radial[2] = NAN;
  ExpectInvalid(c, "radial");
  EXPECT_THROW(DistortionMap{c}, std::invalid_argument);
  EXPECT_THROW(CameraIntrinsics{}.Validate(), std::invalid_argument);  // focal 0 by default
}

}  // namespace
}  // namespace pavilion::core
