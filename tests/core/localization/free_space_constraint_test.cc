// The free-space constraint (negative evidence) of global localization: a
// beam that reads well beyond a mapped wall contradicts a hypothesis; a beam
// cut short by something unmapped never does; the margins grow with the
// hypothesis' uncertainty; infinite lines, which have no extent, are ignored.
#include "core/localization/free_space_constraint.h"

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/random/random_stream.h"
#include "tests/support/localization_world.h"
#include "tests/support/ray_cast_scanner.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;

// Two 4 x 4 m rooms side by side, x 0..4 and 5..9, opening onto a corridor
// y 4..6 through a 1 m door each: the west room's door at its west end, the
// east room's at its east end — mirror images, as the office floor's rooms.
std::vector<testing::Wall> TwoRooms() {
  return {
      {{0, 0}, {4, 0}}, {{4, 0}, {4, 4}}, {{0, 0}, {0, 4}}, {{1, 4}, {4, 4}},  // west room
      {{5, 0}, {9, 0}}, {{9, 0}, {9, 4}}, {{5, 0}, {5, 4}}, {{5, 4}, {8, 4}},  // east room
      {{0, 4}, {0, 6}}, {{9, 4}, {9, 6}}, {{0, 6}, {9, 6}},                    // corridor
  };
}

RobotMap SegmentsOf(const std::vector<testing::Wall>& walls) {
  RobotMap map;
  const Eigen::Matrix2d endpoint = Eigen::Vector2d(2.5e-5, 2.5e-5).asDiagonal();
  for (std::size_t i = 0; i < walls.size(); ++i) {
    MapSegment s;
    s.id = "wall" + std::to_string(i);
    s.line = testing::MapLineThrough(s.id, walls[i].a, walls[i].b, {4.5, 5.0}).line;
    s.first_endpoint = {walls[i].a, endpoint};
    s.second_endpoint = {walls[i].b, endpoint};
    map.segments.push_back(s);
  }
  return map;
}

testing::Scanner FullCircle() {
  testing::Scanner s;
  s.beams = 360;
  s.field_of_view_rad = 2.0 * kPi;
  return s;
}

PoseWithCovariance Certain(const Pose2& pose, double sigma_m = 0.01, double sigma_rad = 0.005) {
  PoseWithCovariance p;
  p.pose = pose;
  p.covariance =
      Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
  return p;
}

TEST(FreeSpaceConstraintTest, TheTruePoseSeesNothingThroughAWall) {
  const std::vector<testing::Wall> walls = TwoRooms();
  const FreeSpaceConstraint constraint(SegmentsOf(walls));
  RandomStream rng(1, RandomStream::StreamId("free_space_test"));
  for (const Pose2 truth : {Pose2{1.5, 2.0, 0.3}, Pose2{2.0, 5.0, -1.0}, Pose2{7.0, 1.0, 2.0}}) {
    const LaserScan scan = testing::CastScan(walls, truth, FullCircle(), 0.0, &rng);
    const FreeSpaceCheck check = constraint.Check(scan, Certain(truth));
    EXPECT_EQ(check.beams, 360);
    EXPECT_EQ(check.see_through, 0) << truth.x_m << ", " << truth.y_m;
    EXPECT_TRUE(constraint.Satisfied(check));
  }
}

// In the west room near its door, the robot sees through the door into the
// corridor. Its look-alike in the east room (the mirror image: the same walls
// around it, the door on the other side) has a wall where those beams went.
TEST(FreeSpaceConstraintTest, ALookAlikeWithAWallWhereTheBeamsWentIsContradicted) {
  const std::vector<testing::Wall> walls = TwoRooms();
  const FreeSpaceConstraint constraint(SegmentsOf(walls));
  const Pose2 truth{1.5, 3.0, 0.5 * kPi};
  const LaserScan scan = testing::CastScan(walls, truth, FullCircle(), 0.0, nullptr);
  // The same place in the east room: the same walls west, south and east at
  // the same distances (every pairing the truth has), but its door is 7 m east.
  const Pose2 look_alike{6.5, 3.0, 0.5 * kPi};
  const FreeSpaceCheck wrong = constraint.Check(scan, Certain(look_alike));
  EXPECT_GT(wrong.see_through, 10);
  EXPECT_FALSE(constraint.Satisfied(wrong));
  EXPECT_TRUE(constraint.Satisfied(constraint.Check(scan, Certain(truth))));
}

TEST(FreeSpaceConstraintTest, BeamsCutShortByUnmappedObjectsNeverContradict) {
  std::vector<testing::Wall> world = TwoRooms();
  const FreeSpaceConstraint constraint(SegmentsOf(world));  // the map: walls only
  // A cupboard and a visitor the map does not know.
  for (const testing::Wall& w : testing::PolygonWalls({{2, 1}, {3, 1}, {3, 1.5}, {2, 1.5}})) {
    world.push_back(w);
  }
  for (const testing::Wall& w :
       testing::PolygonWalls({{1.2, 4.6}, {1.5, 4.6}, {1.5, 4.9}, {1.2, 4.9}})) {
    world.push_back(w);
  }
  const Pose2 truth{1.5, 3.0, 0.5 * kPi};
  const LaserScan scan = testing::CastScan(world, truth, FullCircle(), 0.0, nullptr);
  EXPECT_EQ(constraint.Check(scan, Certain(truth)).see_through, 0);
}

// A hypothesis 0.25 m off: certain, its beams end beyond the walls it puts in
// their way; uncertain by 0.2 m, the margins cover the offset.
TEST(FreeSpaceConstraintTest, MarginsGrowWithTheHypothesisUncertainty) {
  const std::vector<testing::Wall> walls = TwoRooms();
  const FreeSpaceConstraint constraint(SegmentsOf(walls));
  const Pose2 truth{2.0, 2.0, 0.0};
  const LaserScan scan = testing::CastScan(walls, truth, FullCircle(), 0.0, nullptr);
  const Pose2 off{2.0, 1.45, 0.0};  // 0.55 m towards the south wall
  EXPECT_FALSE(constraint.Satisfied(constraint.Check(scan, Certain(off, 0.005, 0.001))));
  EXPECT_TRUE(constraint.Satisfied(constraint.Check(scan, Certain(off, 0.2, 0.001))));
}

// The beams that reach a wall between visitors: every `cut`-th reading ends
// 0.5 m out (a limb); 0: none.
LaserScan CutEvery(LaserScan scan, int cut) {
  for (std::size_t i = 0; cut > 0 && i < scan.readings.size(); i += cut) {
    scan.readings[i].range_m = 0.5;
  }
  return scan;
}

// wall_run_m: the longest stretch of a wall that one unbroken run of at
// least min_wall_run_beams consecutive beams reached; pieces are not joined
// (the extraction keeps a line only for such a run).
TEST(FreeSpaceConstraintTest, MeasuresTheLongestUnbrokenRunOnAWall) {
  const std::vector<testing::Wall> walls = TwoRooms();
  const FreeSpaceConstraint constraint(SegmentsOf(walls));
  // In the west room, facing its 4 m south wall from 2 m: a 180 deg scan
  // sees all of it, and the side walls.
  const Pose2 truth{2.0, 2.0, -0.5 * kPi};
  const LaserScan scan = testing::CastScan(walls, truth, testing::Scanner{}, 0.0, nullptr);
  const auto run_m = [&](int cut) {
    return constraint.Check(CutEvery(scan, cut), Certain(truth), /*count_short=*/true).wall_run_m;
  };
  ASSERT_EQ(FreeSpaceOptions{}.min_wall_run_beams, 4);
  EXPECT_NEAR(run_m(0), 4.0, 0.05);  // whole
  // Cut every 60 readings (30 deg): the longest piece, not the wall.
  EXPECT_GT(run_m(60), 0.5);
  EXPECT_LT(run_m(60), 2.5);
  // Pieces of two readings: none counts.
  EXPECT_EQ(run_m(3), 0.0);
  // Without count_short nothing is measured.
  EXPECT_EQ(constraint.Check(scan, Certain(truth)).wall_run_m, 0.0);
}

TEST(FreeSpaceConstraintTest, InfiniteLinesAreIgnored) {
  RobotMap map;
  map.lines.push_back(testing::MapLineThrough("wall", {3, -10}, {3, 10}, {0, 0}));
  const FreeSpaceConstraint constraint(map);
  // Every beam reads 8 m: through where the infinite line would be.
  LaserScan scan;
  scan.max_range_m = 10.0;
  for (int i = 0; i < 90; ++i) {
    scan.readings.push_back(LaserReading{8.0, -0.7 + i * 0.015, 0.0, true, false});
  }
  EXPECT_EQ(constraint.Check(scan, Certain(Pose2{})).see_through, 0);
}

TEST(FreeSpaceConstraintTest, ToleratesAFewBeamsThroughAWall) {
  const FreeSpaceConstraint constraint(RobotMap{});
  const int allowed = FreeSpaceOptions{}.max_see_through;
  EXPECT_TRUE(constraint.Satisfied(FreeSpaceCheck{361, allowed}));
  EXPECT_FALSE(constraint.Satisfied(FreeSpaceCheck{361, allowed + 4}));
}

TEST(FreeSpaceConstraintTest, RejectsInvalidOptions) {
  FreeSpaceOptions o;
  o.beam_stride = 0;
  EXPECT_THROW(FreeSpaceConstraint(RobotMap{}, o), std::invalid_argument);
  o = {};
  o.max_incidence_rad = 0.5 * kPi;
  EXPECT_THROW(FreeSpaceConstraint(RobotMap{}, o), std::invalid_argument);
  o = {};
  o.max_see_through_ratio = 1.5;
  EXPECT_THROW(FreeSpaceConstraint(RobotMap{}, o), std::invalid_argument);
  o = {};
  o.min_wall_run_beams = 1;
  EXPECT_THROW(FreeSpaceConstraint(RobotMap{}, o), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
