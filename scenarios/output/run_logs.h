#pragma once

// The line files of a run: trajectories.csv (every body and robot at the
// trajectory rate: truth, the robot's odometry and estimate) and
// localization.csv (one row per localization cycle of every robot).

#include <optional>
#include <string>
#include <vector>

#include "core/odometry/diff_drive.h"
#include "scenarios/metrics/localization_tracker.h"
#include "scenarios/output/output_files.h"
#include "sim/crowd/person.h"

namespace pavilion::scenarios {

class TrajectoryLog {
 public:
  explicit TrajectoryLog(const std::string& path);
  void AddBody(double time_s, const std::string& id, const core::Pose2& truth);
  // A row per present person of the crowd (position and heading), named by
  // `ids` (the pool's element ids, by person index).
  void AddPeople(double time_s, const std::vector<sim::crowd::PersonState>& people,
                 const std::vector<std::string>& ids);
  // `estimate`: robots that localize.
  void AddRobot(double time_s, const std::string& id, const core::Pose2& truth,
                const core::Pose2& odometry, const core::PoseWithCovariance* estimate);
  void Flush() { writer_.Flush(); }

 private:
  LineWriter writer_;
};

class LocalizationLog {
 public:
  explicit LocalizationLog(const std::string& path);
  // The `index`-th cycle (0-based) of robot `id`.
  void Add(const std::string& id, std::int64_t index, const LocalizationCycle& cycle);
  void Flush() { writer_.Flush(); }

 private:
  LineWriter writer_;
};

}  // namespace pavilion::scenarios
