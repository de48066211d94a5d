// Free space for a robot set down by hand (issue 18, issue 21): the
// enclosure test and the wheels' run, on a room with an entrance.
#include "scenarios/events/free_space.h"

#include <gtest/gtest.h>

#include <numbers>

namespace pavilion::scenarios {
namespace {

constexpr double kHalfPi = std::numbers::pi / 2.0;

// A 10 m square room centred on the origin whose south wall has a 2 m
// entrance between x = -1 and x = 1; the floor reaches 1 m past the walls.
struct RoomWithEntrance {
  core::PlanarSection section;
  sim::Floor floor;

  RoomWithEntrance() {
    section.height_m = 0.3;
    const int wall = section.AddElement({.id = "wall"});
    const auto add = [&](Eigen::Vector2d a, Eigen::Vector2d b) {
      section.segments.push_back({a, b, wall});
    };
    add({-5, -5}, {-1, -5});
    add({1, -5}, {5, -5});
    add({5, -5}, {5, 5});
    add({5, 5}, {-5, 5});
    add({-5, 5}, {-5, -5});
    floor.min_m = {-6, -6};
    floor.max_m = {6, 6};
  }
};

TEST(FreeSpaceTest, TheFloorOutsideTheWallsIsNotEnclosed) {
  const RoomWithEntrance room;
  EXPECT_TRUE(Enclosed(room.section, room.floor, {0.0, 0.0}));
  EXPECT_TRUE(Enclosed(room.section, room.floor, {4.0, -4.0}));
  EXPECT_FALSE(Enclosed(room.section, room.floor, {3.0, -5.6}));
}

// Set down 1.3 m inside the entrance facing out, a robot whose wheels keep
// turning drives out (expo_day seed 1): enclosed, but its run is not inside.
TEST(FreeSpaceTest, AWheelRunThroughTheEntranceIsNotInside) {
  const RoomWithEntrance room;
  const core::Pose2 facing_out{0.0, -3.7, -kHalfPi};
  EXPECT_TRUE(Enclosed(room.section, room.floor, facing_out.translation()));
  EXPECT_FALSE(WheelsRunInside(room.section, room.floor, facing_out));
  // Backing out is as bad as driving out.
  EXPECT_FALSE(WheelsRunInside(room.section, room.floor, {0.0, -3.7, kHalfPi}));
  // From the far side of the room, the entrance is still straight ahead.
  EXPECT_FALSE(WheelsRunInside(room.section, room.floor, {0.0, 4.0, -kHalfPi}));
  // Turning 10 degrees on the way (within the 15 checked) still finds it.
  EXPECT_FALSE(WheelsRunInside(room.section, room.floor, {-0.8, -2.0, -kHalfPi + 0.17}));
}

TEST(FreeSpaceTest, AWheelRunThatMeetsAWallIsInside) {
  const RoomWithEntrance room;
  EXPECT_TRUE(WheelsRunInside(room.section, room.floor, {0.0, -3.7, 0.0}));
  EXPECT_TRUE(WheelsRunInside(room.section, room.floor, {3.0, -3.7, -kHalfPi}));
  // Beside the entrance, heading past it at more than 15 degrees' spread.
  EXPECT_TRUE(WheelsRunInside(room.section, room.floor, {-3.5, 0.0, -kHalfPi}));
}

}  // namespace
}  // namespace pavilion::scenarios
