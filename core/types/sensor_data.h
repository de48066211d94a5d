#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types/image.h"
#include "core/types/pose2.h"

namespace pavilion::core {

// One reading of a 2D laser scanner, in the sensor frame.
struct LaserReading {
  double range_m = 0.0;        // measured range; max range when !valid
  double bearing_rad = 0.0;    // angle of the beam, counter-clockwise from the sensor's x axis
  double time_offset_s = 0.0;  // time of this reading after the scan's stamp
  bool valid = false;          // false: no return (max-range reading) or dropout
  bool reflector = false;      // intensity flag of a retro-reflective target (thesis §3.3)
};

// A laser scan as a robot receives it: timestamped in simulation time, readings
// in the order the mirror takes them (right to left for a SICK LMS 200).
struct LaserScan {
  std::string sensor_id;
  double stamp_s = 0.0;  // time of the first reading (plus any configured bias)
  double max_range_m = 8.0;
  Pose2 robot_from_sensor;  // mounting pose of the sensor on the robot
  std::vector<LaserReading> readings;
};

// Ground truth of a scan, for metrics only (never given to the robot stack).
struct LaserScanTruth {
  std::vector<Pose2> world_from_sensor;  // true sensor pose at each reading's time
  std::vector<double> true_range_m;      // geometric range before noise; max range when no hit
  std::vector<int> element;              // world element index hit, -1 for none
};

// Cumulative wheel encoder counts (quantized), as the odometry task reads them.
struct EncoderReading {
  double stamp_s = 0.0;
  std::int64_t left_ticks = 0;
  std::int64_t right_ticks = 0;
  int ticks_per_revolution = 0;
};

// Tactile bumper zones in contact, bit i for zone i.
struct BumperReading {
  double stamp_s = 0.0;
  std::uint32_t zones_in_contact = 0;
};

// A grey-level image as a robot receives it from its camera (§2.4): stamped
// with the time the robot's software believes it was exposed (arrival minus
// the grabber's assumed delay, §4.5.2.2).
struct CameraImage {
  std::string sensor_id;
  double stamp_s = 0.0;
  GrayImage image;
};

}  // namespace pavilion::core
