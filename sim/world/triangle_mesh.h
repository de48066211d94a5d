#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "sim/world/world_description.h"

namespace pavilion::sim {

// A triangle soup in the mesh file's own frame and units.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// Loads an STL, OBJ or DAE file with assimp (triangulated, identical vertices
// joined), caching by path so that each file is read once per process.
// Throws std::runtime_error naming the file when it cannot be read or holds no
// triangles.
std::shared_ptr<const TriangleMesh> LoadTriangleMesh(const std::string& path);

// A mesh element's vertices scaled, yawed and placed in the world frame
// (indexed as the triangles of LoadTriangleMesh(m.file)).
std::vector<Eigen::Vector3d> PlacedVertices(const Mesh& m);

}  // namespace pavilion::sim
