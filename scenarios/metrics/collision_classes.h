#pragma once

// Collisions of a robot split by what it hit (metrics.md, Navigation and
// fleet): a wall or exhibit the laser sees, an object invisible to the laser
// (glass, anything below the scan plane), a visitor, another robot — and for
// visitors and robots, who moved into whom.

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/geometry/planar_section.h"

namespace pavilion::scenarios {

enum class CollisionClass { kVisible, kInvisible, kVisitor, kRobot };
inline constexpr std::size_t kCollisionClasses = 4;
const char* ToString(CollisionClass c);

// A collision is a contact episode in which the bodies touched (a contact
// point at or below zero distance, or an impulse: sim::ContactPhase::kTouch);
// a pass is one that came within the contact tracker's 5 mm and parted
// without touching.
struct CollisionCounts {
  std::array<std::int64_t, kCollisionClasses> by_class{};
  std::array<std::int64_t, kCollisionClasses> passes_by_class{};  // within 5 mm, no touch
  std::int64_t robot_into_visitor = 0;  // the robot approached faster than the visitor
  std::int64_t visitor_into_robot = 0;
  std::int64_t robot_into_robot = 0;  // this robot approached the other faster
  std::int64_t robot_hit_by_robot = 0;

  std::int64_t of(CollisionClass c) const { return by_class[static_cast<std::size_t>(c)]; }
  // Adds another robot's counts (a fleet's sums).
  CollisionCounts& operator+=(const CollisionCounts& other) {
    for (std::size_t k = 0; k < kCollisionClasses; ++k) {
      by_class[k] += other.by_class[k];
      passes_by_class[k] += other.passes_by_class[k];
    }
    robot_into_visitor += other.robot_into_visitor;
    visitor_into_robot += other.visitor_into_robot;
    robot_into_robot += other.robot_into_robot;
    robot_hit_by_robot += other.robot_hit_by_robot;
    return *this;
  }
};

// The metrics.json object `collisions_by_class`.
nlohmann::ordered_json CollisionCountsToJson(const CollisionCounts& counts);

// Which class each world element falls in, for a robot whose lasers scan at
// `scan_heights_m`: elements with a non-transparent cut in a section at one of
// those heights are visible; visitors (the walking bodies) and robots (element
// groups) are their own classes.
class CollisionClassifier {
 public:
  // `sections`: the world's sections at the robots' scan heights (bodies at
  // their start); `visitor_element[e]` true for a visitor's element;
  // `robot_of_element[e]` the robot index or -1.
  CollisionClassifier(const std::vector<core::PlanarSection>& sections,
                      std::vector<bool> visitor_element, std::vector<int> robot_of_element);

  CollisionClass Classify(int element) const;

 private:
  std::vector<bool> visible_;
  std::vector<bool> visitor_;
  std::vector<int> robot_;
};

}  // namespace pavilion::scenarios
