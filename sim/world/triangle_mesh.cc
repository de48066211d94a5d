#include "sim/world/triangle_mesh.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>

namespace pavilion::sim {
namespace {

void AppendNode(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent,
                TriangleMesh* out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const int base = static_cast<int>(out->vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out->vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      out->triangles.push_back({base + static_cast<int>(face.mIndices[0]),
                                base + static_cast<int>(face.mIndices[1]),
                                base + static_cast<int>(face.mIndices[2])});
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    AppendNode(scene, *node.mChildren[c], transform, out);
  }
}

}  // namespace

std::shared_ptr<const TriangleMesh> LoadTriangleMesh(const std::string& path) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const TriangleMesh>> cache;
  std::lock_guard<std::mutex> lock(mutex);
  if (auto it = cache.find(path); it != cache.end()) return it->second;

  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
  if (scene == nullptr || scene->mRootNode == nullptr) {
    throw std::runtime_error(path + ": cannot load mesh: " + importer.GetErrorString());
  }
  auto mesh = std::make_shared<TriangleMesh>();
  AppendNode(*scene, *scene->mRootNode, aiMatrix4x4(), mesh.get());
  if (mesh->triangles.empty()) {
    throw std::runtime_error(path + ": mesh holds no triangles");
  }
  cache.emplace(path, mesh);
  return mesh;
}

std::vector<Eigen::Vector3d> PlacedVertices(const Mesh& m) {
  const auto source = LoadTriangleMesh(m.file);
  const double c = std::cos(m.yaw_rad);
  const double s = std::sin(m.yaw_rad);
  std::vector<Eigen::Vector3d> out;
  out.reserve(source->vertices.size());
  for (const Eigen::Vector3d& v : source->vertices) {
    const Eigen::Vector3d p = v.cwiseProduct(m.scale);
    out.emplace_back(m.position_m.x() + c * p.x() - s * p.y(),
                     m.position_m.y() + s * p.x() + c * p.y(), m.position_m.z() + p.z());
  }
  return out;
}

}  // namespace pavilion::sim
