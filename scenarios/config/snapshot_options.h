#pragma once

// A scenario's `snapshots:` block (issue 19): pictures a run takes — a
// robot's camera or a perspective overview — at times and at events, saved
// under snapshots/ and shown in the report (scenarios/output/camera_snapshots.h).

#include <string>
#include <vector>

#include "scenarios/config/yaml_reader.h"

namespace pavilion::scenarios {

// `camera:` of a snapshot: a robot's id (its first level camera), or this.
inline constexpr const char* kOverviewCamera = "overview";

struct SnapshotRequest {
  double at_s = 0.0;   // simulation time, s, >= 0
  std::string camera;  // a robot id or kOverviewCamera
};

struct SnapshotOptions {
  std::vector<SnapshotRequest> at;  // sorted by time
  bool on_kidnap = false;           // every kidnap: the robot's camera just after it
  bool on_collision = false;        // every contact a robot starts: its camera
  int max = 20;                     // pictures a run takes at most, [0, 1000]
  int width_px = 640;               // the overview's size (cameras: their own), [64, 4096]
  int height_px = 480;

  bool empty() const { return at.empty() && !on_kidnap && !on_collision; }
  void Validate() const;  // throws std::invalid_argument naming the field
};

// Reads `snapshots: {at: [{at_s, camera}], on: [kidnap, collision], max,
// width_px, height_px}`; `robot_ids` are the cameras a request may name
// besides `overview`. Errors go to `doc` as file:line: key: message.
void ReadSnapshots(YamlDocument* doc, MapReader& top, const std::vector<std::string>& robot_ids,
                   SnapshotOptions* out);

}  // namespace pavilion::scenarios
