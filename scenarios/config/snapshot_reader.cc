#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "scenarios/config/snapshot_options.h"

namespace pavilion::scenarios {

void SnapshotOptions::Validate() const {
  for (const SnapshotRequest& r : at) {
    if (!(std::isfinite(r.at_s) && r.at_s >= 0.0)) {
      throw std::invalid_argument("SnapshotOptions.at.at_s must be a finite time >= 0 s");
    }
    if (r.camera.empty()) throw std::invalid_argument("SnapshotOptions.at.camera must be set");
  }
  if (!std::is_sorted(at.begin(), at.end(), [](const SnapshotRequest& a, const SnapshotRequest& b) {
        return a.at_s < b.at_s;
      })) {
    throw std::invalid_argument("SnapshotOptions.at must be in time order");
  }
  if (max < 0 || max > 1000)
    throw std::invalid_argument("SnapshotOptions.max must be in [0, 1000]");
  if (width_px < 64 || width_px > 4096 || height_px < 64 || height_px > 4096) {
    throw std::invalid_argument("SnapshotOptions.width_px, height_px must be in [64, 4096]");
  }
}

void ReadSnapshots(YamlDocument* doc, MapReader& top, const std::vector<std::string>& robot_ids,
                   SnapshotOptions* out) {
  YAML::Node node = top.Child("snapshots");
  if (!node.IsDefined() || node.IsNull()) return;
  MapReader m(doc, node, top.PathOf("snapshots"));
  if (!m.valid()) return;
  out->max = static_cast<int>(m.Integer("max", out->max, 0, 1000));
  out->width_px = static_cast<int>(m.Integer("width_px", out->width_px, 64, 4096));
  out->height_px = static_cast<int>(m.Integer("height_px", out->height_px, 64, 4096));
  ForEachMapping(doc, m, "at", false, [&](MapReader& r, std::size_t) {
    SnapshotRequest request;
    request.at_s = r.RequiredNumber("at_s", 0.0, 1e9).value_or(0.0);
    request.camera = r.RequiredString("camera").value_or(kOverviewCamera);
    if (request.camera != kOverviewCamera &&
        std::find(robot_ids.begin(), robot_ids.end(), request.camera) == robot_ids.end()) {
      doc->Error(r.Child("camera"), r.PathOf("camera"),
                 "expected 'overview' or a robot id of the scenario, not '" + request.camera + "'");
    }
    out->at.push_back(request);
  });
  std::stable_sort(
      out->at.begin(), out->at.end(),
      [](const SnapshotRequest& a, const SnapshotRequest& b) { return a.at_s < b.at_s; });
  if (YAML::Node on = m.Child("on"); on.IsDefined()) {
    if (!on.IsSequence()) {
      doc->Error(on, m.PathOf("on"), "expected a list of events: kidnap, collision");
    } else {
      for (std::size_t k = 0; k < on.size(); ++k) {
        const std::string event = on[k].as<std::string>("");
        if (event == "kidnap") {
          out->on_kidnap = true;
        } else if (event == "collision") {
          out->on_collision = true;
        } else {
          doc->Error(on[k], IndexPath(m.PathOf("on"), k),
                     "expected 'kidnap' or 'collision', not '" + event + "'");
        }
      }
    }
  }
  m.Finish();
}

}  // namespace pavilion::scenarios
