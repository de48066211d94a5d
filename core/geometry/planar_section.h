#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace pavilion::core {

// How a surface answers a laser ray (thesis §2.2 and §3.3).
enum class LaserResponse {
  kNormal,           // regular return with the sensor's range noise
  kRetroReflective,  // return with the intensity (reflector) flag set, §3.3
  kDark,             // weak return: large noise and dropouts, §2.2.1
  kSpecular,         // dropout at grazing incidence
  kTransparent,      // not seen by the laser (glass)
};

const char* ToString(LaserResponse response);

// What a section primitive belongs to: a world element or a dynamic body.
struct SectionElement {
  std::string id;  // element or body id, unique in the world
  LaserResponse laser = LaserResponse::kNormal;
  bool dynamic = false;  // true for bodies that move (robots, visitors, props)
  int group = -1;        // parts of one robot share a group (>= 0); -1 otherwise
};

// A line segment of a section, in the world frame.
struct SectionSegment {
  Eigen::Vector2d a_m;
  Eigen::Vector2d b_m;
  int element = -1;  // index into PlanarSection::elements
};

// A circle of a section (an upright cylinder cut by the plane), or the ellipse
// of a tilted one: radius_m across major_axis, radius_m / squash along it,
// where squash is the cosine of the cylinder's tilt and major_axis the
// horizontal direction of its axis (a unit vector).
struct SectionCircle {
  Eigen::Vector2d center_m;
  double radius_m = 0.0;
  int element = -1;  // index into PlanarSection::elements
  Eigen::Vector2d major_axis{1.0, 0.0};
  double squash = 1.0;  // (0, 1]; 1: a circle
};

// The 2D cut of a world by the horizontal plane z = height_m. Segments of one
// element's outline are oriented counter-clockwise around its solid interior
// (the solid is on the left of a -> b), so the outward normal of a segment is
// its direction rotated by -90°.
struct PlanarSection {
  double height_m = 0.0;
  std::vector<SectionElement> elements;
  std::vector<SectionSegment> segments;
  std::vector<SectionCircle> circles;

  // Adds an element and returns its index.
  int AddElement(SectionElement element);
  // Sum of all segment lengths (m); circles not included.
  double TotalSegmentLength() const;
  // Axis-aligned bounds of all primitives; false when the section is empty.
  bool Bounds(Eigen::Vector2d* min_m, Eigen::Vector2d* max_m) const;
};

}  // namespace pavilion::core
