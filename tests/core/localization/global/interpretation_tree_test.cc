// The interpretation tree (thesis §5.4-5.5, Algorithms 1-2): completeness on
// small maps with known symmetric solutions, feasibility of every returned
// hypothesis, the node limit, track splitting, and order independence.
#include "core/localization/global/interpretation_tree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/localization/matching.h"
#include "core/random/random_stream.h"
#include "tests/support/localization_world.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
const Eigen::Matrix2d kLineR = testing::LineCovariance(0.2 * kDeg, 0.005);
const Eigen::Matrix2d kEndpointC = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();  // 1 cm
const Eigen::Matrix2d kMapEndpointC = Eigen::Vector2d(4e-6, 4e-6).asDiagonal();

// A room of segments through `corners` (closed polygon), seen from `inside`.
RobotMap PolygonRoom(const std::vector<Eigen::Vector2d>& corners, const Eigen::Vector2d& inside) {
  RobotMap map;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector2d& a = corners[i];
    const Eigen::Vector2d& b = corners[(i + 1) % corners.size()];
    MapSegment s;
    s.id = "wall" + std::to_string(i);
    s.line = testing::MapLineThrough(s.id, a, b, inside, 0.05 * kDeg, 0.002).line;
    s.first_endpoint = {a, kMapEndpointC};
    s.second_endpoint = {b, kMapEndpointC};
    map.segments.push_back(s);
  }
  return map;
}

// Noiseless segment observations of the listed map segments (all when
// empty) from `truth`, fully seen; the true pairing of local i is segment
// which[i].
LocalMap ObserveSegments(const MeasurementPredictor& predictor, const Pose2& truth,
                         const SensorView& view, std::vector<int> which = {}) {
  const RobotMap& map = predictor.map();
  if (which.empty()) {
    for (std::size_t i = 0; i < map.segments.size(); ++i) which.push_back(static_cast<int>(i));
  }
  ObservationBatch batch;
  batch.view = view;
  const Pose2 sensor_from_world = (truth * view.robot_from_sensor).Inverse();
  for (const int i : which) {
    const MapSegment& s = map.segments[static_cast<std::size_t>(i)];
    Observation o;
    o.z = predictor
              .Predict({MapFeatureType::kSegment, i}, ObservationType::kLine,
                       {truth, Eigen::Matrix3d::Zero()}, view)
              .z;
    o.covariance = kLineR;
    o.segments.push_back({{sensor_from_world * s.first_endpoint.position_m, kEndpointC},
                          {sensor_from_world * s.second_endpoint.position_m, kEndpointC}});
    batch.observations.push_back(o);
  }
  LocalMap local;
  AddToLocalMap(batch, &local);
  return local;
}

double PoseError(const Pose2& a, const Pose2& b) {
  return std::max(std::hypot(a.x_m - b.x_m, a.y_m - b.y_m),
                  std::abs(NormalizeAngle(a.theta_rad - b.theta_rad)));
}

// Every non-star pairing of every hypothesis is predicted within its
// validation gate at the hypothesis' location: no infeasible hypothesis.
void ExpectFeasible(const InterpretationTree& tree, const MeasurementPredictor& predictor,
                    const LocalMap& local, const std::vector<LocationHypothesisData>& found) {
  for (const LocationHypothesisData& h : found) {
    int pairings = 0;
    for (const Pairing& p : h.support) {
      if (p.star) continue;
      ++pairings;
      const LocalFeature& f = local.features[static_cast<std::size_t>(p.local)];
      const Innovation v = ComputeInnovation(
          predictor.Predict(p.feature, f.observation.type, h.location, f.view), f.observation);
      EXPECT_LE(v.nis, tree.gate(v.dimension)) << "local " << p.local;
    }
    EXPECT_EQ(pairings, h.pairings);
    EXPECT_GE(h.pairings, tree.options().min_pairings);
  }
}

// Each expected pose is found exactly once, and nothing else.
void ExpectPoses(const std::vector<LocationHypothesisData>& found,
                 const std::vector<Pose2>& expected, double tolerance) {
  ASSERT_EQ(found.size(), expected.size());
  for (const Pose2& e : expected) {
    const auto hits = std::count_if(found.begin(), found.end(), [&](const auto& h) {
      return PoseError(h.location.pose, e) < tolerance;
    });
    EXPECT_EQ(hits, 1) << e.x_m << " " << e.y_m << " " << e.theta_rad;
  }
}

// The rotations of `pose` about `centre` by k * 2 pi / count.
std::vector<Pose2> Rotations(const Pose2& pose, const Eigen::Vector2d& centre, int count) {
  std::vector<Pose2> out;
  for (int k = 0; k < count; ++k) {
    const Pose2 turn{centre.x(), centre.y(), 2.0 * kPi * k / count};
    const Pose2 to_centre{-centre.x(), -centre.y(), 0.0};
    out.push_back(turn * to_centre * pose);
  }
  return out;
}

// (a) A 6 x 4 m room of four segments, the robot at the centre seeing all
// four walls: exactly the two symmetric poses theta and theta + pi.
TEST(InterpretationTreeTest, RectangularRoomGivesTheTwoSymmetricPoses) {
  const RobotMap map = PolygonRoom({{0, 0}, {6, 0}, {6, 4}, {0, 4}}, {3, 2});
  const MeasurementPredictor predictor(map);
  const InterpretationTree tree(predictor);
  const Pose2 truth{3.0, 2.0, 0.3};
  const LocalMap local = ObserveSegments(predictor, truth, testing::CentredView());
  TreeSearchStats stats;
  const std::vector<LocationHypothesisData> found = tree.Generate(local, &stats);
  EXPECT_FALSE(stats.node_limit_hit);
  EXPECT_GT(stats.nodes, 0);
  ExpectPoses(found, Rotations(truth, {3, 2}, 2), 1e-6);
  ExpectFeasible(tree, predictor, local, found);
  for (const LocationHypothesisData& h : found) EXPECT_EQ(h.pairings, 4);
}

// (a') Off-centre in the same room, looking along the long axis: still
// exactly the truth and its rotation about the centre.
TEST(InterpretationTreeTest, RectangularRoomOffCentre) {
  const RobotMap map = PolygonRoom({{0, 0}, {6, 0}, {6, 4}, {0, 4}}, {3, 2});
  const MeasurementPredictor predictor(map);
  const InterpretationTree tree(predictor);
  const Pose2 truth{1.7, 2.6, -0.5};
  const LocalMap local = ObserveSegments(predictor, truth, testing::CentredView());
  TreeSearchStats stats;
  const std::vector<LocationHypothesisData> found = tree.Generate(local, &stats);
  ExpectPoses(found, Rotations(truth, {3, 2}, 2), 1e-6);
  ExpectFeasible(tree, predictor, local, found);
}

// (b) A 4 x 4 m square room: the four rotations by 90 deg.
TEST(InterpretationTreeTest, SquareRoomGivesFourSymmetricPoses) {
  const RobotMap map = PolygonRoom({{0, 0}, {4, 0}, {4, 4}, {0, 4}}, {2, 2});
  const MeasurementPredictor predictor(map);
  const InterpretationTree tree(predictor);
  const Pose2 truth{1.5, 2.5, 0.2};
  const LocalMap local = ObserveSegments(predictor, truth, testing::CentredView());
  TreeSearchStats stats;
  const std::vector<LocationHypothesisData> found = tree.Generate(local, &stats);
  EXPECT_FALSE(stats.node_limit_hit);
  ExpectPoses(found, Rotations(truth, {2, 2}, 4), 1e-6);
  ExpectFeasible(tree, predictor, local, found);
}

// The L-shaped room (0,0) (6,0) (6,2) (3,2) (3,4) (0,4): no symmetry.
RobotMap LRoom() { return PolygonRoom({{0, 0}, {6, 0}, {6, 2}, {3, 2}, {3, 4}, {0, 4}}, {1, 1}); }

// (c) An asymmetric (L-shaped) room, all six walls in view: exactly one.
TEST(InterpretationTreeTest, LShapedRoomGivesOnePose) {
  const RobotMap map = LRoom();
  const MeasurementPredictor predictor(map);
  const InterpretationTree tree(predictor);
  const Pose2 truth{1.5, 1.0, 0.7};
  const LocalMap local = ObserveSegments(predictor, truth, testing::CentredView());
  TreeSearchStats stats;
  const std::vector<LocationHypothesisData> found = tree.Generate(local, &stats);
  EXPECT_FALSE(stats.node_limit_hit);
  ExpectPoses(found, {truth}, 1e-6);
  ExpectFeasible(tree, predictor, local, found);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_EQ(found[0].pairings, 6);
  for (std::size_t i = 0; i < found[0].support.size(); ++i) {
    EXPECT_FALSE(found[0].support[i].star);
    EXPECT_EQ(found[0].support[i].feature.index, static_cast<int>(i));
  }
}

// (d) The node limit: the search stops at exactly max_tree_nodes pairing
// tests and says so.
TEST(InterpretationTreeTest, NodeLimitStopsTheSearch) {
  const RobotMap map = LRoom();
  const MeasurementPredictor predictor(map);
  const Pose2 truth{1.5, 1.0, 0.7};
  const LocalMap local = ObserveSegments(predictor, truth, testing::CentredView());
  TreeSearchStats full;
  InterpretationTree(predictor).Generate(local, &full);
  ASSERT_GT(full.nodes, 10);
  for (const long limit : {1L, 5L, 10L}) {
    InterpretationTreeOptions options;
    options.max_tree_nodes = limit;
    const InterpretationTree tree(predictor, options);
    TreeSearchStats stats;
    tree.Generate(local, &stats);
    EXPECT_TRUE(stats.node_limit_hit) << limit;
    EXPECT_EQ(stats.nodes, limit);
  }
  InterpretationTreeOptions exact;
  exact.max_tree_nodes = full.nodes + 1;
  TreeSearchStats stats;
  InterpretationTree(predictor, exact).Generate(local, &stats);
  EXPECT_FALSE(stats.node_limit_hit);
  EXPECT_EQ(stats.nodes, full.nodes);
}

// (e) Track at the true pose with a small covariance: the single supporting
// set that pairs every observation with its own wall.
TEST(InterpretationTreeTest, TrackAtTheTruthReturnsTheFullSupportingSet) {
  const RobotMap map = LRoom();
  const MeasurementPredictor predictor(map);
  const InterpretationTree tree(predictor);
  const Pose2 truth{1.5, 1.0, 0.7};
  const LocalMap local = ObserveSegments(predictor, truth, testing::CentredView());
  const PoseWithCovariance predicted{
      truth, Eigen::Vector3d(1e-4, 1e-4, std::pow(0.5 * kDeg, 2)).asDiagonal()};
  TreeSearchStats stats;
  const std::vector<LocationHypothesisData> sets = tree.Track(local, predicted, nullptr, &stats);
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets[0].pairings, 6);
  for (std::size_t i = 0; i < sets[0].support.size(); ++i) {
    EXPECT_FALSE(sets[0].support[i].star);
    EXPECT_EQ(sets[0].support[i].feature.index, static_cast<int>(i));
  }
  EXPECT_EQ(PoseError(sets[0].location.pose, truth), 0.0);
}

// (e') Track splitting: two parallel walls 0.4 m apart (y = 1 and y = 1.4)
// and a cross wall x = 3, the robot seeing y = 1 and x = 3 with a 0.3 m
// position sigma: the observation fits either parallel wall (0.4^2 / 0.09 =
// 1.8 < chi^2_{0.95,2} = 5.99), so two supporting sets; with a 3 cm sigma one.
TEST(InterpretationTreeTest, TrackSplitsBetweenParallelWalls) {
  RobotMap map;
  map.lines.push_back(testing::MapLineThrough("near", {-5, 1.0}, {5, 1.0}, {0, 0}));
  map.lines.push_back(testing::MapLineThrough("far", {-5, 1.4}, {5, 1.4}, {0, 0}));
  map.lines.push_back(testing::MapLineThrough("cross", {3, -5}, {3, 5}, {0, 0}));
  const MeasurementPredictor predictor(map);
  const InterpretationTree tree(predictor);
  const Pose2 truth{0.0, 0.0, 0.1};
  ObservationBatch batch;
  batch.view = testing::CentredView();
  for (const int i : {0, 2}) {
    batch.observations.push_back(
        testing::ObserveLine(map.lines[static_cast<std::size_t>(i)].line, truth, kLineR));
  }
  LocalMap local;
  AddToLocalMap(batch, &local);
  for (const auto& [sigma_m, expected] : {std::pair{0.3, 2u}, std::pair{0.03, 1u}}) {
    const PoseWithCovariance predicted{
        truth, Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, 1e-4).asDiagonal()};
    TreeSearchStats stats;
    const std::vector<LocationHypothesisData> sets = tree.Track(local, predicted, nullptr, &stats);
    ASSERT_EQ(sets.size(), expected) << sigma_m;
    std::vector<int> paired_with_first;
    for (const LocationHypothesisData& s : sets) {
      EXPECT_EQ(s.pairings, 2);
      EXPECT_EQ(s.support[1].feature.index, 2);
      paired_with_first.push_back(s.support[0].feature.index);
    }
    std::sort(paired_with_first.begin(), paired_with_first.end());
    EXPECT_EQ(paired_with_first, expected == 2u ? std::vector<int>({0, 1}) : std::vector<int>({0}));
  }
}

// (f) The observation order only affects speed: shuffled local maps (with
// noisy observations) give the same hypotheses, poses within 1e-9.
TEST(InterpretationTreeTest, ObservationOrderDoesNotChangeTheHypotheses) {
  const RobotMap map = PolygonRoom({{0, 0}, {6, 0}, {6, 4}, {0, 4}}, {3, 2});
  const MeasurementPredictor predictor(map);
  const InterpretationTree tree(predictor);
  const Pose2 truth{2.2, 1.4, 1.1};
  LocalMap local = ObserveSegments(predictor, truth, testing::CentredView());
  RandomStream rng(5, RandomStream::StreamId("interpretation_tree_order"));
  for (LocalFeature& f : local.features) {
    f.observation.z += testing::SampleGaussian<2>(f.observation.covariance, rng);
    f.geometry = ObservationConstraintFeature(f.observation, f.view);
  }
  TreeSearchStats stats;
  const std::vector<LocationHypothesisData> reference = tree.Generate(local, &stats);
  ASSERT_EQ(reference.size(), 2u);
  for (int trial = 0; trial < 6; ++trial) {
    LocalMap shuffled = local;
    for (std::size_t i = shuffled.features.size() - 1; i > 0; --i) {
      const auto j = static_cast<std::size_t>(rng.UniformInt(0, static_cast<std::int64_t>(i)));
      std::swap(shuffled.features[i], shuffled.features[j]);
    }
    TreeSearchStats s;
    const std::vector<LocationHypothesisData> found = tree.Generate(shuffled, &s);
    ASSERT_EQ(found.size(), reference.size()) << trial;
    for (const LocationHypothesisData& r : reference) {
      const auto hits = std::count_if(found.begin(), found.end(), [&](const auto& h) {
        return PoseError(h.location.pose, r.location.pose) < 1e-9 && h.pairings == r.pairings;
      });
      EXPECT_EQ(hits, 1) << trial;
    }
  }
}

// Every option is validated, naming the field.
TEST(InterpretationTreeTest, ValidatesOptions) {
  const auto expect_field = [](const InterpretationTreeOptions& o, const std::string& field) {
    try {
      o.Validate();
      ADD_FAILURE() << "no throw for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  InterpretationTreeOptions o;
  o.significance = 1.0;
  expect_field(o, "significance");
  o = {};
  o.min_pairings = 0;
  expect_field(o, "min_pairings");
  o = {};
  o.pairing_margin = -1;
  expect_field(o, "pairing_margin");
  o = {};
  o.max_tree_nodes = 0;
  expect_field(o, "max_tree_nodes");
  o = {};
  o.max_hypotheses = 0;
  expect_field(o, "max_hypotheses");
}

}  // namespace
}  // namespace pavilion::core
