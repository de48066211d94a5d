// The robot's camera as a Sensor (sim/sensors/camera_sensor.h): a pole lands
// at the column the lens model predicts (distortion on and off, curved off the
// middle row); the vertical-edge extractor recovers its silhouette from the
// sensor's image within the sigma it predicts; the lens' image has no black
// border; the grabber delivers after its delay with the believed stamps; the
// noise is deterministic per seed and of the mount's level.
#include "sim/sensors/camera_sensor.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/features/camera_model.h"
#include "core/features/vertical_edges.h"
#include "core/random/random_stream.h"
#include "sim/render/offscreen_renderer.h"
#include "sim/render/scene_triangles.h"
#include "sim/robot/sim_robot.h"
#include "sim/world/world.h"
#include "tests/support/floor_world.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kPhysicsHz = 200.0;
constexpr double kDtS = 1.0 / kPhysicsHz;
constexpr double kDeg = kPi / 180.0;
// The studio: a light floor and a backdrop wall across x = kWallX (its face
// towards the robot at x = 5.9), tall enough to fill the upper image up to
// the lens' corners.
constexpr double kWallX = 6.0;
constexpr double kWallHeightM = 8.0;
// The robot, and its camera's mount on it (turned and offset so that an
// error in composing the two shows).
const core::Pose2 kRobotPose{-1.0, 0.5, 0.15};
const core::Pose2 kMountPose{0.12, -0.04, 0.05};
constexpr double kMountZM = 1.0;
// Dark poles 2 m from the camera, one at each bearing (camera frame).
constexpr double kPoleRadiusM = 0.03;
constexpr double kPoleRangeM = 2.0;
const std::vector<double> kPoleBearingsDeg{-22.0, -13.5, -4.0, 0.0, 6.5, 15.0, 22.0};
// Pygmalion's camera (robots/pygmalion/robot.yaml): 640 x 480, 54 deg, barrel
// distortion k1 = 0.06, k2 = 0.01 of eq. 3.23, 2 grey levels of noise.
constexpr int kWidthPx = 640;
constexpr int kHeightPx = 480;
constexpr double kHfovRad = 54.0 * kDeg;
constexpr double kK1 = 0.06;
constexpr double kK2 = 0.01;
constexpr double kNoiseGrey = 2.0;
// The rasterizer's share of the edge "calibration" error: a silhouette edge is
// drawn at the pixel boundary nearest its true column (coverage of pixel
// centres), an error uniform in +-0.5 px shared by all rows of the edge: its
// sigma is 1 / sqrt(12) = 0.29 px.
constexpr double kRasterSigmaPx = 0.3;

// The camera as a robot file describes it; without distortion and noise when
// `lens` is false.
CameraMount PygmalionCamera(bool lens) {
  CameraMount m;
  m.id = "forward";
  m.link = "camera";
  m.mount.link = "camera";
  m.mount.pose = kMountPose;
  m.mount.z_m = kMountZM;
  m.width_px = kWidthPx;
  m.height_px = kHeightPx;
  m.hfov_rad = kHfovRad;
  m.rate_hz = 10.0;
  m.grayscale = true;
  m.radial_k1 = lens ? kK1 : 0.0;
  m.radial_k2 = lens ? kK2 : 0.0;
  m.calibration_sigma_px = kRasterSigmaPx;
  return m;
}

WorldDescription Studio() {
  WorldDescription d;
  d.name = "studio";
  d.materials["floor"] = Material{0.8, 0.0, {0.6, 0.6, 0.6, 1}, core::LaserResponse::kNormal};
  d.materials["white"] = Material{0.8, 0.0, {0.95, 0.95, 0.95, 1}, core::LaserResponse::kNormal};
  d.materials["black"] = Material{0.8, 0.0, {0.05, 0.05, 0.05, 1}, core::LaserResponse::kNormal};
  d.floor = {{-10, -10}, {10, 10}, "floor", {}};
  Wall w;
  w.id = "backdrop";
  w.points_m = {{kWallX, -10}, {kWallX, 10}};
  w.height_m = kWallHeightM;
  w.material = "white";
  d.walls.push_back(w);
  return d;
}

// The camera's true position on the floor and heading, composed here by hand
// (not by WorldFromMount, which the sensor uses).
core::Pose2 CameraOnFloor(const core::Pose2& robot) {
  const double c = std::cos(robot.theta_rad), s = std::sin(robot.theta_rad);
  return {robot.x_m + c * kMountPose.x_m - s * kMountPose.y_m,
          robot.y_m + s * kMountPose.x_m + c * kMountPose.y_m,
          robot.theta_rad + kMountPose.theta_rad};
}

// The studio with the robot at kRobotPose and, with `poles`, a pole at each of
// kPoleBearingsDeg from its camera.
struct Stage {
  std::unique_ptr<World> world;
  int robot = -1;

  explicit Stage(bool poles) {
    WorldDescription d = Studio();
    const core::Pose2 camera = CameraOnFloor(kRobotPose);
    for (std::size_t i = 0; poles && i < kPoleBearingsDeg.size(); ++i) {
      const double a = camera.theta_rad + kPoleBearingsDeg[i] * kDeg;
      Cylinder pole;
      pole.id = "pole_" + std::to_string(i);
      pole.position_m = Eigen::Vector2d(camera.x_m, camera.y_m) +
                        kPoleRangeM * Eigen::Vector2d(std::cos(a), std::sin(a));
      pole.radius_m = kPoleRadiusM;
      pole.height_m = 2.5;
      pole.material = "black";
      d.cylinders.push_back(pole);
    }
    world = std::make_unique<World>(d, WorldOptions{});
    robot = pavilion::testing::AddRobot(
        *world, {"robot", pavilion::testing::PygmalionLikeModel("black"), {}, kRobotPose});
  }
};

// One exposure of `sensor` at tick 0 (its delay must be 0: the image arrives
// in the same tick).
ImageRecord ExposeNow(CameraSensor& sensor, const World& world, int robot) {
  SensorTick tick;
  tick.world = &world;
  tick.robot = robot;
  tick.before = tick.after = world.robot_state(robot);
  SensorOutputs out;
  sensor.Sample(tick, &out);
  if (out.images.size() != 1) throw std::runtime_error("the sensor delivered no image");
  return out.images.front();
}

// The distorted column at which the undistorted vertical line u = `u_line`
// crosses the distorted image's height `y_px`: DistortPoint of the line's
// undistorted point (u_line, v) for the v whose image lies at y_px.
double DistortedColumnOnRow(const core::CameraIntrinsics& c, double u_line, double y_px) {
  double v = y_px;
  for (int i = 0; i < 40; ++i) v += y_px - core::DistortPoint(c, {u_line, v}).y();
  const Eigen::Vector2d p = core::DistortPoint(c, {u_line, v});
  if (std::abs(p.y() - y_px) > 1e-6) throw std::runtime_error("no convergence");
  return p.x();
}

// The undistorted columns of a pole's silhouette edges (its tangents from the
// camera centre), left then right, for the pole at `bearing_rad`.
std::array<double, 2> TangentColumns(const core::CameraIntrinsics& c, double bearing_rad) {
  const double half = std::asin(kPoleRadiusM / kPoleRangeM);
  return {core::ColumnOfBearing(c, bearing_rad + half),
          core::ColumnOfBearing(c, bearing_rad - half)};
}

// Where row v's grey profile crosses half-way between the bright surround
// and the dark pole, searched inwards from around - reach and around + reach:
// the pole's left and right silhouette transitions (linear between pixel
// centres). NaN when a transition is missing.
std::array<double, 2> SilhouetteCrossings(const core::GrayImage& image, int v, double around,
                                          double reach) {
  const int lo = std::max(1, static_cast<int>(std::floor(around - reach)));
  const int hi = std::min(image.width - 2, static_cast<int>(std::ceil(around + reach)));
  int dark = 255;
  for (int u = lo; u <= hi; ++u) dark = std::min<int>(dark, image.at(u, v));
  const auto g = [&](int u) { return static_cast<double>(image.at(u, v)); };
  std::array<double, 2> x{std::nan(""), std::nan("")};
  const double left_level = 0.5 * (g(lo) + dark);
  for (int u = lo + 1; u <= hi; ++u) {
    if (g(u) >= left_level) continue;
    x[0] = u - 0.5 + (g(u - 1) - left_level) / (g(u - 1) - g(u));
    break;
  }
  const double right_level = 0.5 * (g(hi) + dark);
  for (int u = hi - 1; u >= lo; --u) {
    if (g(u) >= right_level) continue;
    x[1] = u + 0.5 + (right_level - g(u)) / (g(u + 1) - g(u));
    break;
  }
  return x;
}

// Thin dark poles at bearings up to 22 deg either side: in the middle row and
// in rows near the top and bottom (where the lens bends the pole), the mean of
// the silhouette's two transitions is where DistortPoint puts the pole's
// tangents, within 0.5 px, with distortion on and off. The lens moves the
// outer poles by more than 2 px, so an image without it would fail.
TEST(CameraSensorTest, PoleLandsAtThePredictedColumn) {
  const Stage stage(/*poles=*/true);
  const int middle = kHeightPx / 2;
  double max_error_px = 0.0, max_lens_shift_px = 0.0;
  for (const bool lens : {false, true}) {
    CameraSensor sensor(PygmalionCamera(lens), core::RandomStream(1, 1), core::RandomStream(1, 2),
                        kPhysicsHz);
    const core::GrayImage image = ExposeNow(sensor, *stage.world, stage.robot).image.image;
    const core::CameraIntrinsics& c = sensor.intrinsics();
    ASSERT_EQ(c.distorted(), lens);
    for (const double bearing_deg : kPoleBearingsDeg) {
      const std::array<double, 2> tangents = TangentColumns(c, bearing_deg * kDeg);
      for (const int v : {12, 100, middle, 380, 468}) {
        const double y = v + 0.5;
        const double predicted = 0.5 * (DistortedColumnOnRow(c, tangents[0], y) +
                                        DistortedColumnOnRow(c, tangents[1], y));
        const double reach = 0.5 * (tangents[1] - tangents[0]) + 6.0;
        const std::array<double, 2> x = SilhouetteCrossings(image, v, predicted, reach);
        ASSERT_FALSE(std::isnan(x[0]) || std::isnan(x[1])) << bearing_deg << " row " << v;
        const double error = 0.5 * (x[0] + x[1]) - predicted;
        EXPECT_LE(std::abs(error), 0.5) << "lens " << lens << " bearing " << bearing_deg
                                        << " deg, row " << v << ": predicted " << predicted;
        max_error_px = std::max(max_error_px, std::abs(error));
        max_lens_shift_px =
            std::max(max_lens_shift_px, std::abs(predicted - 0.5 * (tangents[0] + tangents[1])));
      }
    }
  }
  EXPECT_GT(max_lens_shift_px, 2.0);
  RecordProperty("max_centre_error_px", std::to_string(max_error_px));
}

// The sensor's image (lens and 2 grey levels of noise) through
// ExtractVerticalEdges: one edge per silhouette side of every pole, of the
// right polarity, each within 3 of its predicted sigmas of the true tangent
// bearing; the predicted sigma (the raster's 0.3 px and the noise) is below
// 0.05 deg.
TEST(CameraSensorTest, EdgeExtractionRecoversThePoleTangents) {
  const Stage stage(/*poles=*/true);
  CameraMount mount = PygmalionCamera(/*lens=*/true);
  mount.noise_grey = kNoiseGrey;
  CameraSensor sensor(mount, core::RandomStream(3, 1), core::RandomStream(3, 2), kPhysicsHz);
  const core::GrayImage image = ExposeNow(sensor, *stage.world, stage.robot).image.image;
  core::VerticalEdgeOptions options;
  options.image_noise_sigma_grey = mount.noise_grey;
  options.calibration_sigma_px = mount.calibration_sigma_px;
  const std::vector<core::VerticalEdge> edges =
      core::ExtractVerticalEdges(image, sensor.intrinsics(), options);
  ASSERT_EQ(edges.size(), 2 * kPoleBearingsDeg.size());
  const double half = std::asin(kPoleRadiusM / kPoleRangeM);
  double max_normalized = 0.0;
  for (std::size_t i = 0; i < kPoleBearingsDeg.size(); ++i) {
    // Edges by bearing descending; poles by bearing ascending.
    const double bearing = kPoleBearingsDeg[kPoleBearingsDeg.size() - 1 - i] * kDeg;
    for (int side = 0; side < 2; ++side) {
      const core::VerticalEdge& e = edges[2 * i + side];
      const double truth = side == 0 ? bearing + half : bearing - half;
      EXPECT_EQ(e.polarity, side == 0 ? -1 : 1) << i;  // bright to dark entering the pole
      const double sigma = std::sqrt(e.variance_rad2);
      EXPECT_LT(sigma, 0.05 * kDeg) << i;
      EXPECT_GT(sigma, 0.0) << i;
      const double normalized = std::abs(e.bearing_rad - truth) / sigma;
      EXPECT_LE(normalized, 3.0) << "pole at " << bearing / kDeg << " deg, side " << side
                                 << ": error " << (e.bearing_rad - truth) / kDeg << " deg";
      max_normalized = std::max(max_normalized, normalized);
    }
  }
  RecordProperty("max_error_in_sigmas", std::to_string(max_normalized));
}

// The grey level a flat-shaded face of `material` shows with this normal.
int FaceGrey(const WorldDescription& d, const std::string& material, const Eigen::Vector3d& n) {
  const auto c = ShadedColour(d.MaterialNamed(material).rgba, n);
  return static_cast<int>(std::lround(0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]));
}

// With Pygmalion's barrel lens the image's border shows the scene: its top
// corners the backdrop's grey, its bottom corners the floor's and no border
// pixel darker than both. The lens applied to a pinhole image of the camera's
// own size (core::DistortImage) leaves the corners black: what the enlarged
// source (core::PinholeSource) avoids.
TEST(CameraSensorTest, LensImageHasNoBlackBorder) {
  const Stage stage(/*poles=*/false);
  CameraSensor sensor(PygmalionCamera(/*lens=*/true), core::RandomStream(1, 1),
                      core::RandomStream(1, 2), kPhysicsHz);
  const core::GrayImage image = ExposeNow(sensor, *stage.world, stage.robot).image.image;
  const WorldDescription d = Studio();
  const int wall = FaceGrey(d, "white", {-1, 0, 0});
  const int floor = FaceGrey(d, "floor", {0, 0, 1});
  const int w = image.width, h = image.height;
  EXPECT_NEAR(image.at(0, 0), wall, 1);
  EXPECT_NEAR(image.at(w - 1, 0), wall, 1);
  EXPECT_NEAR(image.at(0, h - 1), floor, 1);
  EXPECT_NEAR(image.at(w - 1, h - 1), floor, 1);
  const int darkest = std::min(wall, floor) - 1;
  for (int u = 0; u < w; ++u) {
    ASSERT_GE(image.at(u, 0), darkest) << u;
    ASSERT_GE(image.at(u, h - 1), darkest) << u;
  }
  for (int v = 0; v < h; ++v) {
    ASSERT_GE(image.at(0, v), darkest) << v;
    ASSERT_GE(image.at(w - 1, v), darkest) << v;
  }
  // The same lens on the camera-sized pinhole: black corners.
  RenderView view;
  view.world_from_camera =
      WorldFromMount(stage.world->robot_state(stage.robot).pose, PygmalionCamera(true).mount);
  view.intrinsics = sensor.intrinsics();
  RenderScene scene;
  scene.hide_robot = stage.robot;
  OffscreenRenderer renderer;
  const core::GrayImage cropped =
      core::DistortImage(renderer.RenderGray(*stage.world, view, scene), sensor.intrinsics());
  EXPECT_EQ(cropped.at(0, 0), 0);
}

// A robot built in code with a 10 Hz camera (grabber delay 40 ms, 200 Hz
// physics): the image exposed at tick t (a multiple of 20) arrives at tick
// t + 8, stamped at its exposure time, from the robot's camera pose.
TEST(CameraSensorTest, ImagesArriveAfterTheGrabberDelay) {
  World world(pavilion::testing::FloorWorld(5, false), WorldOptions{});
  RobotConfig config;
  config.description = pavilion::testing::PygmalionLikeModel("floor");
  config.encoders.rate_hz = 100.0;
  CameraMount camera = PygmalionCamera(/*lens=*/false);
  camera.width_px = 64;
  camera.height_px = 48;
  camera.grabber_delay_s = 0.04;
  config.cameras.push_back(camera);
  SimRobot robot(&world, config, RobotPlacement{"r", kRobotPose}, 1);
  std::vector<std::int64_t> arrivals;
  for (int k = 0; k < 200; ++k) {
    const RobotState before = world.robot_state(robot.index());
    world.Step();
    const SensorOutputs out = robot.AfterStep(before, world.robot_state(robot.index()));
    for (const ImageRecord& r : out.images) {
      arrivals.push_back(world.tick());
      const std::int64_t exposed = world.tick() - 8;
      EXPECT_EQ(exposed % 20, 0) << world.tick();
      EXPECT_NEAR(r.exposure_s, exposed * kDtS, 1e-9);
      EXPECT_NEAR(r.image.stamp_s, r.exposure_s, 1e-9);
      EXPECT_EQ(r.image.sensor_id, "forward");
      EXPECT_EQ(r.image.image.width, 64);
      const core::Pose2 truth = CameraOnFloor(world.robot_state(robot.index()).pose);
      EXPECT_NEAR(r.world_from_camera.x_m, truth.x_m, 1e-3);
      EXPECT_NEAR(r.world_from_camera.y_m, truth.y_m, 1e-3);
      EXPECT_NEAR(r.world_from_camera.theta_rad, truth.theta_rad, 1e-3);
    }
  }
  // Exposed at ticks 20 .. 180 (tick 200's arrives after the run).
  EXPECT_EQ(arrivals, (std::vector<std::int64_t>{28, 48, 68, 88, 108, 128, 148, 168, 188}));
}

// With a random grabber delay (40 ms, sigma 5 ms) each image arrives at the
// first tick ending at or after its exposure plus its delay, and its stamp
// (arrival less the mean delay) errs from the exposure by the delay's draw:
// over 400 images, zero mean and a standard deviation within 20 % of sigma.
TEST(CameraSensorTest, StampErrorsFollowTheDelaySpread) {
  const World world(pavilion::testing::FloorWorld(5, false), WorldOptions{});
  CameraMount camera = PygmalionCamera(/*lens=*/false);
  camera.width_px = 64;
  camera.height_px = 48;
  camera.grabber_delay_s = 0.04;
  camera.grabber_delay_sigma_s = 0.005;
  CameraSensor sensor(camera, core::RandomStream(5, 1), core::RandomStream(5, 2), kPhysicsHz);
  constexpr int kImages = 400;
  std::vector<double> errors;
  SensorTick tick;
  tick.world = &world;
  for (std::int64_t k = 1; k <= kImages * 20; ++k) {
    tick.tick = k;
    tick.start_s = (k - 1) * kDtS;
    tick.end_s = k * kDtS;
    SensorOutputs out;
    sensor.Sample(tick, &out);
    for (const ImageRecord& r : out.images) {
      const double arrival = r.image.stamp_s + camera.grabber_delay_s;
      EXPECT_GE(tick.end_s, arrival - 1e-9) << k;
      EXPECT_LT(tick.start_s, arrival - 1e-9) << k;
      errors.push_back(r.image.stamp_s - r.exposure_s);
    }
  }
  ASSERT_GE(errors.size(), kImages - 1u);
  double sum = 0.0, sum2 = 0.0;
  for (const double e : errors) sum += e;
  const double mean = sum / errors.size();
  for (const double e : errors) sum2 += (e - mean) * (e - mean);
  const double std_s = std::sqrt(sum2 / (errors.size() - 1));
  EXPECT_NEAR(std_s, camera.grabber_delay_sigma_s, 0.2 * camera.grabber_delay_sigma_s);
  // The mean's standard error is sigma / 20: four of them.
  EXPECT_NEAR(mean, 0.0, 4.0 * camera.grabber_delay_sigma_s / std::sqrt(errors.size()));
}

// Two sensors with the same seeds give the same bytes; another noise seed
// gives another image; where the noiseless image is flat (the backdrop), the
// noise's standard deviation is the mount's noise_grey within 10 %.
TEST(CameraSensorTest, NoiseIsSeededAndOfTheMountsLevel) {
  const Stage stage(/*poles=*/true);
  CameraMount camera = PygmalionCamera(/*lens=*/true);
  camera.width_px = 160;
  camera.height_px = 120;
  const auto image_with_seed = [&](std::uint64_t seed) {
    CameraSensor sensor(camera, core::RandomStream(seed, 1), core::RandomStream(seed, 2),
                        kPhysicsHz);
    return ExposeNow(sensor, *stage.world, stage.robot).image.image;
  };
  const core::GrayImage clean = image_with_seed(7);  // noise_grey 0
  camera.noise_grey = 3.0;
  const core::GrayImage a = image_with_seed(7);
  EXPECT_EQ(image_with_seed(7).pixels, a.pixels);
  EXPECT_NE(image_with_seed(8).pixels, a.pixels);
  const int wall = FaceGrey(Studio(), "white", {-1, 0, 0});
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    if (clean.pixels[i] != wall) continue;
    const double e = static_cast<double>(a.pixels[i]) - clean.pixels[i];
    sum += e;
    sum2 += e * e;
    ++n;
  }
  ASSERT_GE(n, 3000);  // most of the upper image
  const double mean = sum / n;
  const double std_grey = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(std_grey, camera.noise_grey, 0.1 * camera.noise_grey);
  EXPECT_NEAR(mean, 0.0, 0.2);
}

}  // namespace
}  // namespace pavilion::sim
