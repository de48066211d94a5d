#include "sim/sensors/laser_sensor.h"

#include <algorithm>
#include <utility>

#include "sim/raycast/laser_hit_finder.h"
#include "sim/raycast/planar_caster.h"

namespace pavilion::sim {

LaserSensor::LaserSensor(std::string scanner_id, const LaserScannerOptions& options,
                         const core::Pose2& robot_from_sensor, double mount_height_m,
                         core::RandomStream stream, double physics_rate_hz)
    : id_("laser/" + scanner_id),
      laser_(std::move(scanner_id), options, robot_from_sensor, mount_height_m, std::move(stream)),
      physics_rate_hz_(physics_rate_hz) {}

void LaserSensor::Sample(const SensorTick& tick, SensorOutputs* out) {
  const double t0 = tick.start_s;
  const double t1 = tick.end_s;
  // Sweeps start every 1/scan_rate from t = 0; one may start inside the tick.
  if (!sweeping_ && next_sweep_s_ < t1) {
    laser_.BeginSweep(next_sweep_s_);
    sweeping_ = true;
    fell_back_ = false;
  }
  if (!sweeping_) return;
  const WorldHitFinder bullet(*tick.world);
  const LaserHitFinder* finder = &bullet;
  if (tick.planar != nullptr) {
    // Brings the slice to this tick (once per tick, and only in ticks with
    // readings to cast).
    const PlanarSlice& slice = tick.planar->SliceAt(laser_.mount_height_m());
    const bool level =
        std::max(tick.before.tilt_rad, tick.after.tilt_rad) <= tick.planar->options().max_tilt_rad;
    // Every reading of the tick starts between the sensor's two positions.
    const Eigen::Vector2d from = (tick.before.pose * laser_.robot_from_sensor()).translation();
    const Eigen::Vector2d to = (tick.after.pose * laser_.robot_from_sensor()).translation();
    if (level && slice.Covers(to, laser_.options().max_range_m + (to - from).norm(), tick.group)) {
      finder = &slice;
    } else {
      fell_back_ = true;
    }
  }
  laser_.Cast(*finder, t0, tick.before.pose, t1, tick.after.pose, tick.group);
  if (laser_.SweepComplete()) {
    out->scans.push_back({laser_.scan(), laser_.truth(), fell_back_});
    sweeping_ = false;
    next_sweep_s_ += 1.0 / laser_.options().scan_rate_hz;
  }
}

}  // namespace pavilion::sim
