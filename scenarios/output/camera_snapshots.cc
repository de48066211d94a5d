#include "scenarios/output/camera_snapshots.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/features/camera_model.h"
#include "scenarios/output/png.h"
#include "scenarios/output/report.h"
#include "sim/render/offscreen_renderer.h"
#include "sim/sensors/camera_sensor.h"

namespace pavilion::scenarios {
namespace {

// The overview camera (chosen): a 60 deg horizontal opening, looking down at
// 45 deg; a robot is seen from 4 m behind and 3 m above.
constexpr double kOverviewFovRad = 60.0 * std::numbers::pi / 180.0;
constexpr double kOverviewPitchRad = 45.0 * std::numbers::pi / 180.0;
constexpr double kFocusBackM = 4.0;
constexpr double kFocusUpM = 3.0;

core::RgbImage ToRgb(const core::GrayImage& grey) {
  core::RgbImage out(grey.width, grey.height);
  for (std::size_t i = 0; i < grey.pixels.size(); ++i) {
    out.pixels[3 * i] = out.pixels[3 * i + 1] = out.pixels[3 * i + 2] = grey.pixels[i];
  }
  return out;
}

// A camera at `eye` looking along `yaw`, pitched down by `pitch` (camera
// frame: x forward, y left, z up).
Eigen::Isometry3d LookFrom(const Eigen::Vector3d& eye, double yaw, double pitch) {
  return Eigen::Translation3d(eye) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY());
}

std::string Safe(const std::string& s) {
  std::string out;
  for (const char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

}  // namespace

core::RgbImage RobotCameraPicture(const sim::World& world, int robot, const sim::CameraMount& mount,
                                  sim::OffscreenRenderer& renderer) {
  core::GrayImage image;
  sim::CameraOptics(mount).Form(renderer, world, robot, world.robot_state(robot).pose, mount.mount,
                                &image);
  return ToRgb(image);
}

core::RgbImage OverviewPicture(const sim::World& world, std::optional<int> focus, int width_px,
                               int height_px, sim::OffscreenRenderer& renderer) {
  sim::RenderView view;
  view.intrinsics = core::CameraIntrinsics::FromHorizontalFov(width_px, height_px, kOverviewFovRad);
  if (focus) {
    const core::Pose2 p = world.robot_state(*focus).pose;
    const Eigen::Vector3d eye(p.x_m - kFocusBackM * std::cos(p.theta_rad),
                              p.y_m - kFocusBackM * std::sin(p.theta_rad), kFocusUpM);
    view.world_from_camera = LookFrom(eye, p.theta_rad, std::atan2(kFocusUpM - 0.5, kFocusBackM));
  } else {
    // From south of the floor, looking north and down at its centre, far
    // enough that the floor's width fills the opening at the centre.
    const Eigen::Vector2d lo = world.description().floor.min_m;
    const Eigen::Vector2d hi = world.description().floor.max_m;
    const double width = hi.x() - lo.x();
    const double depth = hi.y() - lo.y();
    const double reach = std::max(
        1.35 * width * std::cos(kOverviewPitchRad) / (2.0 * std::tan(0.5 * kOverviewFovRad)),
        0.5 * depth + 2.0);  // horizontal distance to the centre
    const Eigen::Vector3d eye(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()) - reach,
                              reach * std::tan(kOverviewPitchRad));
    view.world_from_camera = LookFrom(eye, 0.5 * std::numbers::pi, kOverviewPitchRad);
  }
  view.far_m = 500.0;
  return renderer.RenderRgb(world, view);
}

SnapshotTaker::SnapshotTaker(SnapshotOptions options, std::map<std::string, SnapshotCamera> cameras)
    : options_(std::move(options)), cameras_(std::move(cameras)) {
  options_.Validate();
}

SnapshotTaker::~SnapshotTaker() = default;

void SnapshotTaker::TakeDue(const sim::World& world, double t_s) {
  while (next_ < options_.at.size() && options_.at[next_].at_s <= t_s + 1e-9) {
    Take(world, t_s, options_.at[next_].camera, "");
    ++next_;
  }
}

void SnapshotTaker::OnEvent(const sim::World& world, double t_s, const std::string& robot_id,
                            const std::string& event) {
  if ((event == "kidnap" && options_.on_kidnap) ||
      (event == "collision" && options_.on_collision)) {
    Take(world, t_s, robot_id, event);
  }
}

void SnapshotTaker::Take(const sim::World& world, double t_s, const std::string& camera,
                         const std::string& why) {
  if (static_cast<int>(frames_.size()) >= options_.max) {
    ++skipped_;
    return;
  }
  if (!renderer_) renderer_ = std::make_unique<sim::OffscreenRenderer>();
  SnapshotFrame frame;
  frame.time_s = t_s;
  std::string what;
  core::RgbImage image;
  const auto robot = cameras_.find(camera);
  if (camera == kOverviewCamera) {
    image = OverviewPicture(world, std::nullopt, options_.width_px, options_.height_px, *renderer_);
    what = "overview";
    frame.caption = "Overview";
  } else if (robot == cameras_.end()) {
    throw std::invalid_argument("snapshot camera '" + camera + "' is no robot of the run");
  } else if (robot->second.mount) {
    image = RobotCameraPicture(world, robot->second.robot, *robot->second.mount, *renderer_);
    what = camera + "_" + robot->second.mount->id;
    frame.caption = camera + "'s camera " + robot->second.mount->id;
  } else {  // no level camera: the robot from behind
    image = OverviewPicture(world, robot->second.robot, options_.width_px, options_.height_px,
                            *renderer_);
    what = camera + "_behind";
    frame.caption = camera + " from behind";
  }
  frame.caption += ", " + CrowdFrameCaption(t_s) + (why.empty() ? "" : " (" + why + ")");
  char index[16];
  std::snprintf(index, sizeof index, "%02d", static_cast<int>(frames_.size()) + 1);
  frame.path = "snapshots/camera_" + std::string(index) + "_" + Safe(what) +
               (why.empty() ? "" : "_" + Safe(why)) + ".png";
  frame.png = EncodePng(image);
  frames_.push_back(std::move(frame));
}

}  // namespace pavilion::scenarios
