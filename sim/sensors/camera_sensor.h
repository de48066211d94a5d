#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <memory>
#include <string>

#include "core/features/camera_model.h"
#include "core/random/random_stream.h"
#include "sim/robot/robot_config.h"
#include "sim/sensors/sensor.h"

namespace pavilion::sim {

class OffscreenRenderer;

// A camera's optics, built once per camera: its image's intrinsics (with the
// lens), the pinhole rendered for it (core::PinholeSource: enlarged to all
// the lens sees) and the lens that resamples that pinhole.
struct CameraOptics {
  explicit CameraOptics(const CameraMount& mount);  // throws for an invalid mount

  core::CameraIntrinsics intrinsics;
  core::CameraIntrinsics pinhole;
  core::DistortionMap lens;

  // What the lens forms of `world` (no noise) from `mount` on robot `robot`
  // at `world_from_base`, the robot's own body hidden; the camera's pose
  // goes to `world_from_camera` when given.
  void Form(OffscreenRenderer& renderer, const World& world, int robot,
            const core::Pose2& world_from_base, const MountSpec& mount, core::GrayImage* out,
            Eigen::Isometry3d* world_from_camera = nullptr) const;
};

// A robot's grey-level camera (§2.4) as a Sensor (id "camera/<mount id>").
// Every 1/rate_hz from t = 0 it exposes: the world at the end of the tick is
// rendered through an ideal pinhole from the camera's true pose (the robot's
// own body hidden; the pinhole enlarged to all the lens sees,
// core::PinholeSource), the lens' radial distortion is applied (the forward
// model whose inverse is eq. 3.23) and the electronics' noise added. The image
// arrives grabber_delay_s (plus a draw of grabber_delay_sigma_s) later, in
// SensorOutputs::images, stamped at its arrival minus the mean delay: the
// software's belief about the exposure (§4.5.2.2).
class CameraSensor final : public Sensor {
 public:
  // `noise` draws the pixel noise, `delay` the grabber's delay. Throws
  // std::invalid_argument for an invalid mount or a rate that does not divide
  // the physics rate.
  CameraSensor(const CameraMount& mount, core::RandomStream noise, core::RandomStream delay,
               double physics_rate_hz);
  ~CameraSensor() override;

  const std::string& id() const override { return id_; }
  // Sampled every tick: exposures at the mount's rate, arrivals in between.
  double sample_rate_hz() const override { return physics_rate_hz_; }
  void Sample(const SensorTick& tick, SensorOutputs* out) override;
  // Renders in the ticks it exposes an image.
  bool Heavy(std::int64_t tick, double end_s) const override {
    (void)end_s;
    return tick % period_ticks_ == 0;
  }

  const CameraMount& mount() const { return mount_; }
  const core::CameraIntrinsics& intrinsics() const { return optics_.intrinsics; }

 private:
  struct InFlight {
    double arrival_s = 0.0;
    ImageRecord record;
  };

  ImageRecord Expose(const SensorTick& tick);

  std::string id_;
  CameraMount mount_;
  CameraOptics optics_;
  core::RandomStream noise_;
  core::RandomStream delay_;
  double physics_rate_hz_;
  std::int64_t period_ticks_ = 1;
  std::unique_ptr<OffscreenRenderer> renderer_;  // created at the first exposure
  std::deque<InFlight> in_flight_;
};

}  // namespace pavilion::sim
