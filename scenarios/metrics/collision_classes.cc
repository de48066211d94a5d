#include "scenarios/metrics/collision_classes.h"

namespace pavilion::scenarios {

const char* ToString(CollisionClass c) {
  switch (c) {
    case CollisionClass::kVisible:
      return "wall_or_exhibit_visible";
    case CollisionClass::kInvisible:
      return "invisible_object";
    case CollisionClass::kVisitor:
      return "visitor";
    case CollisionClass::kRobot:
      return "robot";
  }
  return "unknown";
}

nlohmann::ordered_json CollisionCountsToJson(const CollisionCounts& counts) {
  nlohmann::ordered_json j;
  for (std::size_t k = 0; k < kCollisionClasses; ++k) {
    j[ToString(static_cast<CollisionClass>(k))] = counts.by_class[k];
  }
  j["robot_into_visitor"] = counts.robot_into_visitor;
  j["visitor_into_robot"] = counts.visitor_into_robot;
  j["robot_into_robot"] = counts.robot_into_robot;
  j["robot_hit_by_robot"] = counts.robot_hit_by_robot;
  nlohmann::ordered_json passes;
  for (std::size_t k = 0; k < kCollisionClasses; ++k) {
    passes[ToString(static_cast<CollisionClass>(k))] = counts.passes_by_class[k];
  }
  j["passes_within_5mm"] = std::move(passes);
  return j;
}

CollisionClassifier::CollisionClassifier(const std::vector<core::PlanarSection>& sections,
                                         std::vector<bool> visitor_element,
                                         std::vector<int> robot_of_element)
    : visible_(visitor_element.size(), false),
      visitor_(std::move(visitor_element)),
      robot_(std::move(robot_of_element)) {
  const auto mark = [&](const core::PlanarSection& s, int element) {
    if (element < 0 || static_cast<std::size_t>(element) >= visible_.size()) return;
    if (s.elements[element].laser != core::LaserResponse::kTransparent) visible_[element] = true;
  };
  for (const core::PlanarSection& s : sections) {
    for (const core::SectionSegment& seg : s.segments) mark(s, seg.element);
    for (const core::SectionCircle& c : s.circles) mark(s, c.element);
  }
}

CollisionClass CollisionClassifier::Classify(int element) const {
  const auto e = static_cast<std::size_t>(element);
  if (e < robot_.size() && robot_[e] >= 0) return CollisionClass::kRobot;
  if (e < visitor_.size() && visitor_[e]) return CollisionClass::kVisitor;
  if (e < visible_.size() && visible_[e]) return CollisionClass::kVisible;
  return CollisionClass::kInvisible;
}

}  // namespace pavilion::scenarios
