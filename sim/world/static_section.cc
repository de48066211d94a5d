#include "sim/world/static_section.h"

#include <Eigen/Geometry>

#include "sim/world/triangle_mesh.h"
#include "sim/world/wall_geometry.h"

namespace pavilion::sim {
namespace {

// Cuts a triangle by the plane z = h and appends the section segment, oriented
// with the solid on its left (the triangle's outward normal to its right).
void CutTriangle(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                 double h, int element, core::PlanarSection* out) {
  const Eigen::Vector3d p[3] = {p0, p1, p2};
  Eigen::Vector2d hits[3];
  int count = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& a = p[k];
    const Eigen::Vector3d& b = p[(k + 1) % 3];
    const bool a_above = a.z() >= h;
    const bool b_above = b.z() >= h;
    if (a_above == b_above) continue;
    const double t = (h - a.z()) / (b.z() - a.z());
    hits[count++] = (a + t * (b - a)).head<2>();
  }
  if (count != 2 || (hits[0] - hits[1]).squaredNorm() < 1e-18) return;
  const Eigen::Vector3d normal = (p1 - p0).cross(p2 - p0);
  const Eigen::Vector2d dir(-normal.y(), normal.x());  // normal rotated by +90°
  core::SectionSegment s;
  s.element = element;
  if ((hits[1] - hits[0]).dot(dir) >= 0) {
    s.a_m = hits[0];
    s.b_m = hits[1];
  } else {
    s.a_m = hits[1];
    s.b_m = hits[0];
  }
  out->segments.push_back(s);
}

void AddPolygonSegments(const Quad& q, int element, core::PlanarSection* out) {
  for (int k = 0; k < 4; ++k) out->segments.push_back({q[k], q[(k + 1) % 4], element});
}

bool SpansHeight(double base_z, double height, double z) {
  return z >= base_z && z < base_z + height;
}

}  // namespace

void AppendStaticSection(const WorldDescription& description, double z, core::PlanarSection* out) {
  int element = 1;  // 0 is the floor
  for (const Wall& wall : description.walls) {
    if (SpansHeight(wall.base_z_m, wall.height_m, z)) {
      for (const auto& seg : WallOutline(wall)) out->segments.push_back({seg[0], seg[1], element});
    }
    ++element;
  }
  for (const Box& box : description.boxes) {
    if (SpansHeight(box.base_z_m, box.size_m.z(), z)) {
      AddPolygonSegments(BoxFootprint(box), element, out);
    }
    ++element;
  }
  for (const Cylinder& c : description.cylinders) {
    if (SpansHeight(c.base_z_m, c.height_m, z))
      out->circles.push_back({c.position_m, c.radius_m, element});
    ++element;
  }
  for (const Mesh& m : description.meshes) {
    const auto source = LoadTriangleMesh(m.file);
    const std::vector<Eigen::Vector3d> v = PlacedVertices(m);
    for (const auto& tri : source->triangles) {
      CutTriangle(v[tri[0]], v[tri[1]], v[tri[2]], z, element, out);
    }
    ++element;
  }
  for (const Door& door : description.doors) {
    const Box box = door.AsBox();
    if (SpansHeight(box.base_z_m, box.size_m.z(), z)) {
      AddPolygonSegments(BoxFootprint(box), element, out);
    }
    ++element;
  }
}

}  // namespace pavilion::sim
