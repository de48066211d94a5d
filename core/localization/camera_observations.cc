#include "core/localization/camera_observations.h"

#include <cmath>
#include <stdexcept>

namespace pavilion::core {

void CameraSensorOptions::Validate() const {
  const std::string prefix = "cameras[" + id + "].";
  try {
    intrinsics.Validate();
    edges.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(prefix + e.what());
  }
  if (!(std::isfinite(robot_from_sensor.x_m) && std::isfinite(robot_from_sensor.y_m) &&
        std::isfinite(robot_from_sensor.theta_rad))) {
    throw std::invalid_argument(prefix + "robot_from_sensor must be finite");
  }
  if (!(border_margin_px >= 0.0 && border_margin_px <= 0.25 * intrinsics.width_px)) {
    throw std::invalid_argument(prefix + "border_margin_px must be in [0, width_px / 4]");
  }
  if (!(std::isfinite(perception_radius_m) && perception_radius_m > 0.0)) {
    throw std::invalid_argument(prefix + "perception_radius_m must be a finite value > 0");
  }
}

ObservationBatch EdgeObservations(const CameraImage& image, const CameraSensorOptions& camera) {
  ObservationBatch batch;
  batch.sensor_id = image.sensor_id;
  batch.stamp_s = image.stamp_s;
  batch.types = {ObservationType::kVerticalEdge};
  batch.view.robot_from_sensor = camera.robot_from_sensor;
  batch.view.perception_radius_m = camera.perception_radius_m;
  batch.view.min_view_angle_rad = 0.0;  // an edge is a point: no extent to see (eq. 5.51)
  // The undistorted image's horizontal opening less the border margins: the
  // bearings of the margins' inner edges on the centre row, corrected by eq. 3.23.
  const CameraIntrinsics& c = camera.intrinsics;
  const double m = camera.border_margin_px;
  const double left = UndistortPoint(c, {m, c.center_v_px}).x();
  const double right = UndistortPoint(c, {c.width_px - m, c.center_v_px}).x();
  batch.view.max_bearing_rad = BearingOfColumn(c, left);
  batch.view.min_bearing_rad = BearingOfColumn(c, right);
  for (const VerticalEdge& e : ExtractVerticalEdges(image.image, c, camera.edges)) {
    if (e.column_px < left || e.column_px > right) continue;  // too near a border
    Observation o;
    o.type = ObservationType::kVerticalEdge;
    o.z = {e.bearing_rad, 0.0};
    o.covariance(0, 0) = e.variance_rad2;  // eq. 4.3
    batch.observations.push_back(o);
  }
  return batch;
}

}  // namespace pavilion::core
