#include "sim/sensors/camera_sensor.h"

#include <cmath>
#include <utility>

#include "sim/render/offscreen_renderer.h"
#include "sim/runtime/schedule.h"

namespace pavilion::sim {

CameraOptics::CameraOptics(const CameraMount& mount)
    : intrinsics((mount.Validate(), mount.Intrinsics())),
      pinhole(core::PinholeSource(intrinsics)),
      lens(intrinsics, pinhole) {}

void CameraOptics::Form(OffscreenRenderer& renderer, const World& world, int robot,
                        const core::Pose2& world_from_base, const MountSpec& mount,
                        core::GrayImage* out, Eigen::Isometry3d* world_from_camera) const {
  RenderView view;
  view.world_from_camera = WorldFromMount(world_from_base, mount);
  view.intrinsics = pinhole;
  RenderScene scene;
  scene.hide_robot = robot;
  lens.Apply(renderer.RenderGray(world, view, scene), out);
  if (world_from_camera != nullptr) *world_from_camera = view.world_from_camera;
}

CameraSensor::CameraSensor(const CameraMount& mount, core::RandomStream noise,
                           core::RandomStream delay, double physics_rate_hz)
    : id_("camera/" + mount.id),
      mount_(mount),
      optics_(mount),
      noise_(std::move(noise)),
      delay_(std::move(delay)),
      physics_rate_hz_(physics_rate_hz),
      period_ticks_(PeriodTicks(physics_rate_hz, mount.rate_hz, "camera " + mount.id)) {}

CameraSensor::~CameraSensor() = default;

ImageRecord CameraSensor::Expose(const SensorTick& tick) {
  if (!renderer_) renderer_ = std::make_unique<OffscreenRenderer>();
  ImageRecord record;
  record.exposure_s = tick.end_s;
  record.image.sensor_id = mount_.id;
  Eigen::Isometry3d camera;
  optics_.Form(*renderer_, *tick.world, tick.robot, tick.after.pose, mount_.mount,
               &record.image.image, &camera);
  if (mount_.noise_grey > 0.0) core::AddImageNoise(mount_.noise_grey, noise_, &record.image.image);
  const Eigen::Vector3d x = camera.linear().col(0);
  record.world_from_camera =
      core::Pose2{camera.translation().x(), camera.translation().y(), std::atan2(x.y(), x.x())};
  return record;
}

void CameraSensor::Sample(const SensorTick& tick, SensorOutputs* out) {
  if (tick.tick % period_ticks_ == 0) {
    ImageRecord record = Expose(tick);
    double delay = mount_.grabber_delay_s;
    if (mount_.grabber_delay_sigma_s > 0.0) {
      delay = std::max(0.0, delay + delay_.Normal(0.0, mount_.grabber_delay_sigma_s));
    }
    const double arrival = tick.end_s + delay;
    // What the software believes: the arrival less the delay it assumes.
    record.image.stamp_s = arrival - mount_.grabber_delay_s;
    in_flight_.push_back({arrival, std::move(record)});
  }
  // Arrivals of this tick, oldest first (the grabber delivers in order).
  while (!in_flight_.empty() && in_flight_.front().arrival_s <= tick.end_s + 1e-9) {
    out->images.push_back(std::move(in_flight_.front().record));
    in_flight_.pop_front();
  }
}

}  // namespace pavilion::sim
