#pragma once

// A strip of frames of the crowd around a robot for report.html: small crops
// of the top-down view (people drawn as people, sim/render/top_down_view.h)
// taken during the run at evenly spaced times, written at its end as
// snapshots/crowd_NN.png.

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "core/types/image.h"
#include "scenarios/config/scenario.h"
#include "scenarios/output/report.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {

struct CrowdStripOptions {
  double duration_s = 60.0;       // the run's length, s, (0, 1e9]
  int frames = 6;                 // frames over the run, [1, 99]
  double crop_m = 8.0;            // side of the square crop, m, (0, 1000]
  int size_px = 240;              // side of a frame, px, [50, 2000]
  double section_height_m = 0.5;  // the cut drawn (TopDownOptions), m, [0, 100]
  std::string people_material;    // TopDownOptions::people_material

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The strip of a scenario: its duration, section height and crowd material,
// the other fields at their defaults.
CrowdStripOptions CrowdStripOptionsFor(const Scenario& scenario);

// Where the strip looks: the first robot's true position, or the floor's
// centre in a world without robots.
Eigen::Vector2d CrowdStripCentre(const sim::World& world);

// The top-down view cropped to a square of side `crop_m` centred on
// `center_m`, `size_px` wide, with `caption` stamped in its top-left corner
// (the strip's frames, and the snapshot of a run's first overlap deadlock).
core::RgbImage RenderCrop(const sim::World& world, const Eigen::Vector2d& center_m, double crop_m,
                          int size_px, double section_height_m, const std::string& people_material,
                          const std::string& caption);

// Captures crops of the top-down view at the frame times
// t_k = (k + 0.5) duration / frames, k = 0 .. frames - 1, while a run goes.
class CrowdStrip {
 public:
  explicit CrowdStrip(CrowdStripOptions options);  // validates

  const CrowdStripOptions& options() const { return options_; }
  double frame_time_s(int k) const;
  // A frame's time has come (t_s within kDueToleranceS of it or later) and it
  // has not been captured: call each tick with the simulation time.
  bool Due(double t_s) const;
  // Renders the crop of side crop_m centred on `center_m` now, as the frame of
  // the latest due time; due frames before it are skipped (their times passed
  // between two calls, so they would show the same moment). Does nothing when
  // no frame is due.
  void Capture(const sim::World& world, const Eigen::Vector2d& center_m, double t_s);
  int captured() const { return static_cast<int>(frames_.size()); }

  // Writes snapshots/crowd_NN.png under `out_dir` for the frames captured (NN
  // the frame's number from 01) and returns them in time order.
  std::vector<CrowdFrame> Write(const std::filesystem::path& out_dir) const;

 private:
  struct Frame {
    int index = 0;        // k
    double time_s = 0.0;  // when it was captured
    core::RgbImage image;
  };
  CrowdStripOptions options_;
  int next_ = 0;  // the first frame neither captured nor skipped
  std::vector<Frame> frames_;
};

}  // namespace pavilion::scenarios
