#include "core/features/beacon_extraction.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::core {

Point2Uncertain Beacon::Cartesian() const {
  const double c = std::cos(bearing_rad);
  const double s = std::sin(bearing_rad);
  Point2Uncertain p;
  p.position_m = {range_m * c, range_m * s};
  // Jacobian of (rho cos theta, rho sin theta) with respect to (rho, theta).
  Eigen::Matrix2d j;
  j << c, -range_m * s, s, range_m * c;
  p.covariance = j * polar_covariance * j.transpose();
  return p;
}

void BeaconExtractionOptions::Validate() const {
  const auto require = [](bool ok, const char* field, const char* expected) {
    if (!ok) throw std::invalid_argument(std::string(field) + " must be " + expected);
  };
  require(std::isfinite(range_sigma_m) && range_sigma_m > 0.0, "range_sigma_m", "> 0");
  require(std::isfinite(max_range_jump_m) && max_range_jump_m > 0.0, "max_range_jump_m", "> 0");
  require(min_points >= 1, "min_points", ">= 1");
  require(std::isfinite(angular_resolution_rad) && angular_resolution_rad >= 0.0,
          "angular_resolution_rad", ">= 0");
}

namespace {

double ScanResolution(const LaserScan& scan) {
  const std::size_t n = scan.readings.size();
  if (n < 2) return 0.0;
  return std::abs(scan.readings.back().bearing_rad - scan.readings.front().bearing_rad) /
         static_cast<double>(n - 1);
}

Beacon Estimate(const LaserScan& scan, int first, int last, double sigma, double resolution) {
  Beacon b;
  double information = 0.0;  // sum sigma_i^-2
  double weighted = 0.0;     // sum rho_i / sigma_i^2
  double bearings = 0.0;
  const double w = 1.0 / (sigma * sigma);
  for (int i = first; i <= last; ++i) {
    information += w;
    weighted += w * scan.readings[i].range_m;
    bearings += scan.readings[i].bearing_rad;
  }
  const int n = last - first + 1;
  const double range_variance = 1.0 / information;           // eq. 3.18 (the parallel resistor)
  b.range_m = range_variance * weighted;                     // eq. 3.17
  b.bearing_rad = bearings / n;                              // eq. 3.19
  const double bearing_sigma = 0.25 * resolution * (n + 1);  // eq. 3.20
  b.polar_covariance << range_variance, 0.0, 0.0, bearing_sigma * bearing_sigma;  // eq. 3.22
  b.point_count = n;
  b.first_index = first;
  b.last_index = last;
  return b;
}

}  // namespace

std::vector<Beacon> ExtractBeacons(const LaserScan& scan, const BeaconExtractionOptions& options) {
  options.Validate();
  const double resolution =
      options.angular_resolution_rad > 0.0 ? options.angular_resolution_rad : ScanResolution(scan);
  std::vector<Beacon> beacons;
  const int n = static_cast<int>(scan.readings.size());
  int first = -1;
  auto close = [&](int last) {
    if (first >= 0 && last - first + 1 >= options.min_points) {
      beacons.push_back(Estimate(scan, first, last, options.range_sigma_m, resolution));
    }
    first = -1;
  };
  for (int i = 0; i < n; ++i) {
    const LaserReading& r = scan.readings[i];
    const bool inlier = r.valid && r.reflector && std::isfinite(r.range_m) && r.range_m > 0.0;
    if (!inlier) {
      close(i - 1);
      continue;
    }
    if (first >= 0 &&
        std::abs(r.range_m - scan.readings[i - 1].range_m) > options.max_range_jump_m) {
      close(i - 1);  // another reflector behind or in front
    }
    if (first < 0) first = i;
  }
  close(n - 1);
  return beacons;
}

}  // namespace pavilion::core
