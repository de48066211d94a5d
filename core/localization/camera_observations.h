#pragma once

// One camera image as an observation batch (thesis §4.4.1.2, eq. 4.3): the
// bearings of the vertical edges extracted from it (§3.4), each with its
// variance, and the view of the camera they were seen with.

#include <string>

#include "core/features/camera_model.h"
#include "core/features/vertical_edges.h"
#include "core/localization/observation.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// How the Localizer turns one camera's images into observations.
struct CameraSensorOptions {
  std::string id;               // CameraImage::sensor_id these options apply to
  CameraIntrinsics intrinsics;  // the calibration (§2.4)
  // x_S^R: the camera's planar mount (its optical axis' heading). Known and
  // deterministic, unlike the Acuity laser's (§4.5.1.1: "the robot-to-sensor
  // frame transform ... deterministic for the CCD camera").
  Pose2 robot_from_sensor;
  // R_S: vertical edges farther than this are not predicted, m; > 0. An
  // edge's depth is not observed: far away, an unmapped edge (an open door's
  // leaf, furniture) lies within a mapped one's gate at nearly the same
  // bearing and, as the robot approaches, drags the estimate along by its
  // parallax. 5 m (chosen): the corridor_vision run stays consistent, at 8 m
  // it does not.
  double perception_radius_m = 5.0;
  VerticalEdgeOptions edges;
  // Edges closer than this to the image's left or right border are not used,
  // and the view's bearings stop there: an object cut by the border shows a
  // partial silhouette. px, [0, width / 4].
  double border_margin_px = 16.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The batch of an image: kVerticalEdge observations z = phi, R = sigma_phi^2
// (eq. 4.3), stamped at the image's stamp; the view's field of view is the
// image's horizontal opening. Throws std::invalid_argument for an image that
// is not the camera's size.
ObservationBatch EdgeObservations(const CameraImage& image, const CameraSensorOptions& camera);

}  // namespace pavilion::core
