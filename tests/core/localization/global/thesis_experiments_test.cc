// The experiments of thesis §5.7 as patterns: the Fig. 5.21 statistics of
// hypothesis generation for a local map of six segments with a half-open
// door, against p'_min.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "core/localization/global/interpretation_tree.h"
#include "tests/support/localization_world.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
const Eigen::Matrix2d kLineR = testing::LineCovariance(0.3 * kDeg, 0.01);
const Eigen::Matrix2d kEndpointC = Eigen::Vector2d(4e-4, 4e-4).asDiagonal();  // 2 cm
const Eigen::Matrix2d kMapEndpointC = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();

void AddSegment(RobotMap* map, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                const Eigen::Vector2d& seen_from) {
  MapSegment s;
  s.id = std::to_string(map->segments.size());
  s.line = testing::MapLineThrough(s.id, a, b, seen_from, 0.1 * kDeg, 0.005).line;
  s.first_endpoint = {a, kMapEndpointC};
  s.second_endpoint = {b, kMapEndpointC};
  map->segments.push_back(s);
}

// An office-like floor (designed for this test, not the thesis' map): a
// corridor y in [0, 2] along x in [0, 12] and three offices north of it,
// 4, 3 and 5 m wide and 4 m deep, each with a 1 m door in the corridor wall
// at a different place (the corridor sides of the office walls are left
// out); office 0's walls come first.
RobotMap OfficeFloor() {
  RobotMap map;
  const double x0[3] = {0.0, 4.0, 7.0};
  const double width[3] = {4.0, 3.0, 5.0};
  const double door[3] = {1.5, 0.4, 3.2};  // door start from the office's west wall
  for (int k = 0; k < 3; ++k) {
    const double w = x0[k];
    const double e = x0[k] + width[k];
    const Eigen::Vector2d in(0.5 * (w + e), 4.0);
    AddSegment(&map, {w, 2}, {w, 6}, in);                  // west
    AddSegment(&map, {w, 6}, {e, 6}, in);                  // north
    AddSegment(&map, {e, 6}, {e, 2}, in);                  // east
    AddSegment(&map, {w, 2}, {w + door[k], 2}, in);        // south, west of the door
    AddSegment(&map, {w + door[k] + 1.0, 2}, {e, 2}, in);  // south, east of the door
  }
  AddSegment(&map, {0, 0}, {12, 0}, {6, 1});  // corridor south wall
  return map;
}

// One observed segment from `world_from_robot` (sensor at the robot), noiseless.
Observation ObserveSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                           const Pose2& world_from_robot) {
  const Line world = testing::MapLineThrough("", a, b, world_from_robot.translation()).line;
  Observation o = testing::ObserveLine(world, world_from_robot, kLineR);
  const Pose2 robot_from_world = world_from_robot.Inverse();
  o.segments.push_back({{robot_from_world * a, kEndpointC}, {robot_from_world * b, kEndpointC}});
  return o;
}

// Fig. 5.21: six local segments in office 0 — west, north, east, the two
// pieces of the south wall, and a door standing half open (45 deg, not in
// the map). Generation with p'_min = 2..6 (pairing_margin large, so only
// p'_min filters): the counts fall as p' rises, none pairs all six (the
// door is unmodelled), and the best (largest p') is the truth.
TEST(ThesisExperimentsTest, Figure521HypothesesAgainstMinimumPairings) {
  const RobotMap map = OfficeFloor();
  const MeasurementPredictor predictor(map);
  const Pose2 truth{1.3, 3.8, 0.4};
  ObservationBatch batch;
  batch.view = testing::CentredView();
  for (const auto& [a, b] : std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{
           {{0, 2}, {0, 6}},
           {{0, 6}, {4, 6}},
           {{4, 6}, {4, 2}},
           {{0, 2}, {1.5, 2}},
           {{2.5, 2}, {4, 2}},
           {{2.5, 2}, {2.5 - std::cos(kPi / 4), 2 + std::sin(kPi / 4)}}}) {
    batch.observations.push_back(ObserveSegment(a, b, truth));
  }
  LocalMap local;
  AddToLocalMap(batch, &local);
  const int thesis[5] = {63, 4, 2, 1, 0};  // p' >= 2..6, Fig. 5.21 and §5.7.2.1
  std::vector<std::size_t> counts;
  std::printf("p'_min  hypotheses  thesis (Fig. 5.21)\n");
  for (int p = 2; p <= 6; ++p) {
    InterpretationTreeOptions options;
    options.min_pairings = p;
    options.pairing_margin = 100;
    options.max_hypotheses = 100000;
    options.max_tree_nodes = 10000000;
    const InterpretationTree tree(predictor, options);
    TreeSearchStats stats;
    const std::vector<LocationHypothesisData> found = tree.Generate(local, &stats);
    EXPECT_FALSE(stats.node_limit_hit);
    EXPECT_FALSE(stats.hypothesis_limit_hit);
    counts.push_back(found.size());
    std::printf("%6d  %10zu  %6d\n", p, found.size(), thesis[p - 2]);
    if (found.empty()) continue;
    const Pose2& best = found.front().location.pose;
    EXPECT_EQ(found.front().pairings, 5) << p;
    EXPECT_LT(std::hypot(best.x_m - truth.x_m, best.y_m - truth.y_m), 0.01) << p;
    EXPECT_LT(std::abs(NormalizeAngle(best.theta_rad - truth.theta_rad)), 0.5 * kDeg) << p;
    EXPECT_TRUE(found.front().support[5].star) << "the door is unmodelled";
  }
  for (std::size_t k = 1; k < counts.size(); ++k) EXPECT_LE(counts[k], counts[k - 1]) << k;
  EXPECT_GT(counts[0], counts[2]);  // p' >= 2 admits many more than p' >= 4
  EXPECT_EQ(counts[3], 1u);         // p' >= 5: the truth alone
  EXPECT_EQ(counts[4], 0u);         // p' = 6: none
}

}  // namespace
}  // namespace pavilion::core
