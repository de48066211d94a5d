#pragma once

// Pictures for users (issue 19): what a robot's camera sees, or a free
// perspective overview of the world, rendered off-screen (OSMesa) at chosen
// simulation times and at events (kidnaps, collisions), up to a cap. Taking a
// picture reads the world and draws no random number: a run with snapshots
// writes the same outputs as one without, the pictures aside.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/types/image.h"
#include "scenarios/config/snapshot_options.h"
#include "sim/robot/robot_config.h"
#include "sim/world/world.h"

namespace pavilion::sim {
class OffscreenRenderer;
}

namespace pavilion::scenarios {

// One picture taken.
struct SnapshotFrame {
  std::string path;  // relative to the run's folder: snapshots/camera_NN_<what>.png
  double time_s = 0.0;
  std::string caption;  // what and why: "pygmalion's camera forward, t = 30 s (kidnap)"
  std::vector<std::uint8_t> png;
};

// A camera on a robot of the world, for pictures.
struct SnapshotCamera {
  int robot = -1;                         // world robot index
  std::optional<sim::CameraMount> mount;  // none: the robot has no level camera
};

// The image a robot's camera forms (grey, through its lens, without its
// noise) as RGB: what the robot's software gets, less the electronics.
core::RgbImage RobotCameraPicture(const sim::World& world, int robot, const sim::CameraMount& mount,
                                  sim::OffscreenRenderer& renderer);

// A perspective view from above and aside: the whole floor seen from beyond
// its south edge, or, with `focus`, that robot from 4 m behind and 3 m above.
core::RgbImage OverviewPicture(const sim::World& world, std::optional<int> focus, int width_px,
                               int height_px, sim::OffscreenRenderer& renderer);

class SnapshotTaker {
 public:
  // `cameras`: the run's robots by id. Throws std::invalid_argument for
  // invalid options.
  SnapshotTaker(SnapshotOptions options, std::map<std::string, SnapshotCamera> cameras);
  ~SnapshotTaker();
  SnapshotTaker(const SnapshotTaker&) = delete;
  SnapshotTaker& operator=(const SnapshotTaker&) = delete;

  const SnapshotOptions& options() const { return options_; }
  // The requests due at `t_s` (each once), taken.
  void TakeDue(const sim::World& world, double t_s);
  // An event of `robot_id` ("kidnap", "collision") when the options ask for it.
  void OnEvent(const sim::World& world, double t_s, const std::string& robot_id,
               const std::string& event);
  const std::vector<SnapshotFrame>& frames() const { return frames_; }
  // Pictures not taken because the cap was reached.
  int skipped() const { return skipped_; }

 private:
  void Take(const sim::World& world, double t_s, const std::string& camera, const std::string& why);

  SnapshotOptions options_;
  std::map<std::string, SnapshotCamera> cameras_;
  std::size_t next_ = 0;  // the next request of options_.at
  std::unique_ptr<sim::OffscreenRenderer> renderer_;
  std::vector<SnapshotFrame> frames_;
  int skipped_ = 0;
};

}  // namespace pavilion::scenarios
