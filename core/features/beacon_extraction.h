#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// A retro-reflecting beacon seen in a scan (thesis §3.3), in the sensor frame:
// polar position (rho_b, theta_b) with its covariance (eqs. 3.21-3.22).
struct Beacon {
  double range_m = 0.0;                                        // rho_b, eq. 3.17
  double bearing_rad = 0.0;                                    // theta_b, eq. 3.19
  Eigen::Matrix2d polar_covariance = Eigen::Matrix2d::Zero();  // C_b of (rho, theta), eq. 3.22
  int point_count = 0;                                         // n_b, inlier readings
  int first_index = -1;                                        // reading indices in the scan
  int last_index = -1;

  // The position in Cartesian coordinates with its first-order covariance.
  Point2Uncertain Cartesian() const;
};

struct BeaconExtractionOptions {
  double range_sigma_m = 0.01;     // sigma_rho of a reading on a reflector (LMS 200), > 0
  double max_range_jump_m = 0.15;  // consecutive inliers farther apart in range split, > 0
  int min_points = 1;              // readings a beacon needs, >= 1
  // Angular resolution Delta-theta of eq. 3.20; 0: taken from the scan's bearings.
  double angular_resolution_rad = 0.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Beacons from the intensity (reflector) flag, which solves their segmentation
// (§3.3): maximal runs of consecutive valid reflector readings, split at range
// jumps, each estimated by the information filter in range (eqs. 3.17-3.18)
// and the mean bearing with the ad-hoc angular sigma of eq. 3.20.
std::vector<Beacon> ExtractBeacons(const LaserScan& scan, const BeaconExtractionOptions& options);

}  // namespace pavilion::core
