#include "core/localization/scan_observations.h"

#include <algorithm>
#include <limits>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "core/localization/scan_deskew.h"

namespace pavilion::core {
namespace {

SensorView ScanView(const LaserScan& registered, const LaserScan& raw,
                    const LaserSensorOptions& laser) {
  SensorView view;
  view.robot_from_sensor = registered.robot_from_sensor;
  view.robot_from_sensor_covariance = laser.robot_from_sensor_covariance;
  view.perception_radius_m =
      laser.perception_radius_m > 0.0 ? laser.perception_radius_m : registered.max_range_m;
  view.min_view_angle_rad = laser.min_view_angle_rad;
  if (raw.readings.size() >= 2) {  // field of view: the span of the bearings
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (const LaserReading& r : raw.readings) {
      lo = std::min(lo, r.bearing_rad);
      hi = std::max(hi, r.bearing_rad);
    }
    if (hi > lo && hi - lo < 2.0 * std::numbers::pi) {
      view.min_bearing_rad = lo;
      view.max_bearing_rad = hi;
    }
  }
  return view;
}

}  // namespace

ObservationBatch ScanObservations(const LaserScan& registered, const LaserScan& raw,
                                  const LaserSensorOptions& laser) {
  ObservationBatch batch;
  batch.sensor_id = registered.sensor_id;
  batch.stamp_s = registered.stamp_s;
  batch.view = ScanView(registered, raw, laser);
  batch.types.push_back(ObservationType::kLine);
  const std::vector<Segment> segments = ExtractLines(registered, laser.lines);
  std::map<int, std::size_t> by_line_id;
  for (const Segment& s : segments) {
    if (s.line_id >= 0) {
      const auto it = by_line_id.find(s.line_id);
      if (it != by_line_id.end()) {
        batch.observations[it->second].segments.push_back({s.first_endpoint, s.last_endpoint});
        continue;
      }
      by_line_id[s.line_id] = batch.observations.size();
    }
    Observation o;
    o.type = ObservationType::kLine;
    o.z = {s.line.alpha_rad, s.line.r_m};
    o.covariance = s.line.covariance;
    o.segments.push_back({s.first_endpoint, s.last_endpoint});
    batch.observations.push_back(std::move(o));
  }
  if (laser.extract_beacons) {
    batch.types.push_back(ObservationType::kBeacon);
    for (const Beacon& b : ExtractBeacons(registered, laser.beacons)) {
      const Point2Uncertain p = b.Cartesian();
      Observation o;
      o.type = ObservationType::kBeacon;
      o.z = p.position_m;
      o.covariance = p.covariance;
      batch.observations.push_back(std::move(o));
    }
  }
  return batch;
}

std::optional<LaserScan> RegisterScan(const LaserScan& raw, const LaserSensorOptions& laser,
                                      const OdometryBuffer& buffer) {
  if (laser.deskew) return DeskewScan(raw, buffer);
  LaserScan scan = raw;
  if (!scan.readings.empty()) scan.stamp_s += scan.readings.front().time_offset_s;
  return scan;
}

}  // namespace pavilion::core
