#include "sim/world/element_table.h"

#include <algorithm>

namespace pavilion::sim {

int ElementTable::Add(const std::string& id, const std::string& material, bool dynamic, int group) {
  const core::LaserResponse laser =
      material.empty() ? core::LaserResponse::kNormal : description_->MaterialNamed(material).laser;
  elements_.push_back({id, laser, dynamic, group});
  return static_cast<int>(elements_.size()) - 1;
}

bool ElementTable::Contains(const std::string& id) const {
  return std::any_of(elements_.begin(), elements_.end(),
                     [&](const core::SectionElement& e) { return e.id == id; });
}

bool ElementTable::LaserVisible(int element) const {
  return elements_[element].laser != core::LaserResponse::kTransparent;
}

}  // namespace pavilion::sim
