#pragma once

#include <string>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/world/world_description.h"

namespace pavilion::sim {

// The elements of a world by element index (sim/world/world.h): ids, laser
// responses from their materials, and the robot groups of robot parts.
class ElementTable {
 public:
  // `description` outlives the table; its materials give the laser responses.
  explicit ElementTable(const WorldDescription* description) : description_(description) {}

  // Appends an element; an empty material is laser-normal. Throws
  // std::out_of_range for an unknown material. Returns its index.
  int Add(const std::string& id, const std::string& material, bool dynamic, int group = -1);
  bool Contains(const std::string& id) const;
  bool LaserVisible(int element) const;
  int size() const { return static_cast<int>(elements_.size()); }
  const std::vector<core::SectionElement>& all() const { return elements_; }

 private:
  const WorldDescription* description_;
  std::vector<core::SectionElement> elements_;
};

}  // namespace pavilion::sim
