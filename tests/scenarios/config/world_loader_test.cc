#include "scenarios/config/world_loader.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/validate.h"
#include "sim/world/triangle_mesh.h"
#include "sim/world/world.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

// The header every test world shares: two materials and a floor.
const std::string kHeader =
    "kind: world\n"
    "name: test_room\n"
    "materials:\n"
    "  concrete:\n"
    "    friction: 0.8\n"
    "  wood:\n"
    "    friction: 0.6\n"
    "    laser: dark\n"
    "floor:\n"
    "  min: [-5, -5]\n"
    "  max: [5, 5]\n"
    "  material: concrete\n";

// Loads a world file that must fail; returns its diagnostics after checking that
// ValidateFile reports exactly the same ones.
std::vector<Diagnostic> LoadErrors(const std::string& path) {
  std::vector<Diagnostic> diagnostics;
  try {
    LoadWorldFile(path);
    ADD_FAILURE() << "LoadWorldFile accepted " << path;
  } catch (const InputError& e) {
    diagnostics = e.diagnostics();
    EXPECT_EQ(std::string(e.what()), diagnostics.front().ToString());
  }
  const std::vector<Diagnostic> validated = ValidateFile(path);
  EXPECT_EQ(validated.size(), diagnostics.size());
  for (std::size_t i = 0; i < std::min(validated.size(), diagnostics.size()); ++i) {
    EXPECT_EQ(validated[i].ToString(), diagnostics[i].ToString());
  }
  return diagnostics;
}

// The diagnostic with `key_path`, or a failure and an empty one.
Diagnostic Find(const std::vector<Diagnostic>& diagnostics, const std::string& key_path) {
  for (const Diagnostic& d : diagnostics) {
    if (d.key_path == key_path) return d;
  }
  std::string all;
  for (const Diagnostic& d : diagnostics) all += "\n  " + d.ToString();
  ADD_FAILURE() << "no diagnostic for '" << key_path << "' among:" << all;
  return {};
}

// Writes `kHeader + body` as world.yaml, expects exactly `count` diagnostics and
// returns the one at `key_path` after checking its file and line (that of `marker`).
// All diagnostics go to `all` when given.
Diagnostic ExpectError(const std::string& body, std::size_t count, const std::string& key_path,
                       const std::string& marker, std::vector<Diagnostic>* all = nullptr) {
  const std::string text = kHeader + body;
  const std::string path = WriteFile(TestDir(), "world.yaml", text);
  const std::vector<Diagnostic> diagnostics = LoadErrors(path);
  if (all != nullptr) *all = diagnostics;
  EXPECT_EQ(diagnostics.size(), count);
  const Diagnostic d = Find(diagnostics, key_path);
  EXPECT_EQ(d.file, path);
  EXPECT_EQ(d.line, LineOf(text, marker));
  return d;
}

// A valid world using every kind of element.
const std::string kTinyRoom =
    "kind: world\n"
    "name: tiny_room\n"
    "description: a room for tests\n"
    "materials:\n"
    "  concrete:\n"
    "    friction: 0.8\n"
    "    color: [0.5, 0.5, 0.5]\n"
    "    laser: normal\n"
    "  foil:\n"
    "    friction: 0.5\n"
    "    restitution: 0.25\n"
    "    color: [1, 1, 0, 0.5]\n"
    "    laser: retro_reflective\n"
    "  glass:\n"
    "    friction: 0.4\n"
    "    laser: transparent\n"
    "floor:\n"
    "  min: [-5, -4]\n"
    "  max: [5, 4]\n"
    "  material: concrete\n"
    "walls:\n"
    "  - id: outline\n"
    "    points: [[-4, -3], [4, -3], [4, 3], [-4, 3]]\n"
    "    closed: true\n"
    "    thickness: 0.2\n"
    "    height: 2.5\n"
    "    material: concrete\n"
    "boxes:\n"
    "  - id: crate\n"
    "    pose: [1.5, -2, 0.25]\n"
    "    size: [0.5, 0.6, 0.7]\n"
    "    z: 0.1\n"
    "    material: foil\n"
    "cylinders:\n"
    "  - id: column\n"
    "    position: [-2, 1]\n"
    "    radius: 0.3\n"
    "    height: 3\n"
    "    material: concrete\n"
    "doors:\n"
    "  - id: office_door\n"
    "    hinge: [0, 2]\n"
    "    closed_yaw: 0\n"
    "    open_yaw: 1.5\n"
    "    width: 0.9\n"
    "    thickness: 0.04\n"
    "    height: 2.0\n"
    "    state: open\n"
    "    material: glass\n"
    "places:\n"
    "  entrance:\n"
    "    pose: [0, -2.5, 1.25]\n"
    "  spawn:\n"
    "    area: [[-3, -2], [-1, -2], [-1, 0], [-3, 0]]\n";

// Writes kTinyRoom as world.yaml and loads it; `path` receives the file.
sim::WorldDescription LoadTinyRoom(std::string* path) {
  *path = WriteFile(TestDir(), "world.yaml", kTinyRoom);
  return LoadWorldFile(*path);
}

// Confirms that a valid world loads with the values written in the file: its
// name, materials and floor.
TEST(WorldLoaderTest, LoadsMinimalWorldWithItsValues) {
  std::string path;
  const sim::WorldDescription w = LoadTinyRoom(&path);
  EXPECT_TRUE(ValidateFile(path).empty());

  EXPECT_EQ(w.name, "tiny_room");
  EXPECT_EQ(w.description, "a room for tests");
  EXPECT_EQ(w.source_file, path);
  ASSERT_EQ(w.materials.size(), 3u);
  EXPECT_EQ(w.materials.at("concrete").laser, core::LaserResponse::kNormal);
  EXPECT_EQ(w.materials.at("foil").laser, core::LaserResponse::kRetroReflective);
  EXPECT_EQ(w.materials.at("glass").laser, core::LaserResponse::kTransparent);
  EXPECT_DOUBLE_EQ(w.materials.at("foil").friction, 0.5);
  EXPECT_DOUBLE_EQ(w.materials.at("foil").restitution, 0.25);
  EXPECT_EQ(w.materials.at("foil").rgba, (std::array<double, 4>{1, 1, 0, 0.5}));
  EXPECT_EQ(w.materials.at("concrete").rgba[3], 1.0);  // alpha defaults to opaque

  EXPECT_EQ(w.floor.min_m, Eigen::Vector2d(-5, -4));
  EXPECT_EQ(w.floor.max_m, Eigen::Vector2d(5, 4));
  EXPECT_EQ(w.floor.material, "concrete");
}

// Confirms that the minimal world's walls, boxes and cylinders have the values
// written in the file.
TEST(WorldLoaderTest, LoadsMinimalWorldsSolids) {
  std::string path;
  const sim::WorldDescription w = LoadTinyRoom(&path);
  ASSERT_EQ(w.walls.size(), 1u);
  EXPECT_EQ(w.walls[0].id, "outline");
  ASSERT_EQ(w.walls[0].points_m.size(), 4u);
  EXPECT_EQ(w.walls[0].points_m[0], Eigen::Vector2d(-4, -3));
  EXPECT_EQ(w.walls[0].points_m[2], Eigen::Vector2d(4, 3));
  EXPECT_TRUE(w.walls[0].closed);
  EXPECT_DOUBLE_EQ(w.walls[0].thickness_m, 0.2);
  EXPECT_DOUBLE_EQ(w.walls[0].height_m, 2.5);
  EXPECT_DOUBLE_EQ(w.walls[0].base_z_m, 0.0);

  ASSERT_EQ(w.boxes.size(), 1u);
  EXPECT_EQ(w.boxes[0].pose, (core::Pose2{1.5, -2.0, 0.25}));
  EXPECT_EQ(w.boxes[0].size_m, Eigen::Vector3d(0.5, 0.6, 0.7));
  EXPECT_DOUBLE_EQ(w.boxes[0].base_z_m, 0.1);
  EXPECT_EQ(w.boxes[0].material, "foil");

  ASSERT_EQ(w.cylinders.size(), 1u);
  EXPECT_EQ(w.cylinders[0].position_m, Eigen::Vector2d(-2, 1));
  EXPECT_DOUBLE_EQ(w.cylinders[0].radius_m, 0.3);
}

// Confirms that the minimal world's door and places (a pose, an area) have
// the values written in the file.
TEST(WorldLoaderTest, LoadsMinimalWorldsDoorsAndPlaces) {
  std::string path;
  const sim::WorldDescription w = LoadTinyRoom(&path);
  ASSERT_EQ(w.doors.size(), 1u);
  EXPECT_TRUE(w.doors[0].open);
  EXPECT_EQ(w.doors[0].hinge_m, Eigen::Vector2d(0, 2));
  EXPECT_DOUBLE_EQ(w.doors[0].open_yaw_rad, 1.5);
  EXPECT_DOUBLE_EQ(w.doors[0].width_m, 0.9);

  ASSERT_EQ(w.places.size(), 2u);
  ASSERT_TRUE(w.places.at("entrance").pose.has_value());
  EXPECT_FALSE(w.places.at("entrance").area.has_value());
  EXPECT_EQ(*w.places.at("entrance").pose, (core::Pose2{0.0, -2.5, 1.25}));
  ASSERT_TRUE(w.places.at("spawn").area.has_value());
  EXPECT_FALSE(w.places.at("spawn").pose.has_value());
  const core::Polygon2 expected_area = {{-3, -2}, {-1, -2}, {-1, 0}, {-3, 0}};
  EXPECT_EQ(*w.places.at("spawn").area, expected_area);
}

// Confirms that unparsable YAML is reported with a line and "malformed YAML".
TEST(WorldLoaderTest, ReportsMalformedYaml) {
  const std::string text = kHeader +
                           "walls:\n"
                           "  - id: a\n"
                           "    points: [[0, 0], [1, 0]\n"
                           "    thickness: 0.2\n";
  const std::string path = WriteFile(TestDir(), "world.yaml", text);
  const std::vector<Diagnostic> diagnostics = LoadErrors(path);
  ASSERT_EQ(diagnostics.size(), 1u);
  EXPECT_EQ(diagnostics[0].file, path);
  EXPECT_EQ(diagnostics[0].key_path, "");
  // yaml-cpp notices the unclosed bracket at the next line's key.
  EXPECT_EQ(diagnostics[0].line, LineOf(text, "thickness: 0.2"));
  EXPECT_TRUE(Contains(diagnostics[0].message, "malformed YAML"));
}

// Confirms that a file that does not exist is one diagnostic, not a crash.
TEST(WorldLoaderTest, ReportsMissingFile) {
  const std::string path = (TestDir() / "nope.yaml").string();
  const std::vector<Diagnostic> diagnostics = LoadErrors(path);
  ASSERT_EQ(diagnostics.size(), 1u);
  EXPECT_EQ(diagnostics[0].file, path);
  EXPECT_EQ(diagnostics[0].message, "cannot open file");
}

// Confirms that a misspelt key is reported at its line with its path.
TEST(WorldLoaderTest, ReportsUnknownKey) {
  const std::string body =
      "walls:\n"
      "  - id: a\n"
      "    points: [[0, 0], [1, 0]]\n"
      "    thicknes: 0.2\n"
      "    height: 2\n"
      "    material: concrete\n";
  std::vector<Diagnostic> all;
  const Diagnostic d = ExpectError(body, 2, "walls[0].thicknes", "thicknes:", &all);
  EXPECT_EQ(d.message, "unknown key");
  // The real key is then missing, reported at the wall's mapping.
  const std::string text = kHeader + body;
  const Diagnostic missing = Find(all, "walls[0].thickness");
  EXPECT_EQ(missing.line, LineOf(text, "id: a"));
  EXPECT_EQ(missing.message, "required key is missing");
}

// Confirms that a string where a list of numbers belongs is reported.
TEST(WorldLoaderTest, ReportsWrongType) {
  const Diagnostic d = ExpectError(
      "boxes:\n"
      "  - id: crate\n"
      "    pose: [0, 0, 0]\n"
      "    size: big\n"
      "    material: wood\n",
      1, "boxes[0].size", "size: big");
  EXPECT_TRUE(Contains(d.message, "expected a list of 3 numbers"));
}

// Confirms that a mesh file that does not exist is reported at the file key.
TEST(WorldLoaderTest, ReportsMissingMeshFile) {
  const Diagnostic d = ExpectError(
      "meshes:\n"
      "  - id: statue\n"
      "    file: meshes/statue.stl\n"
      "    pose: [0, 0, 0, 0]\n"
      "    material: wood\n",
      1, "meshes[0].file", "file: meshes/statue.stl");
  EXPECT_TRUE(Contains(d.message, "not found"));
  EXPECT_TRUE(Contains(d.message, "meshes/statue.stl"));
}

// Confirms that a negative thickness is a range error.
TEST(WorldLoaderTest, ReportsNegativeThickness) {
  const Diagnostic d = ExpectError(
      "walls:\n"
      "  - id: a\n"
      "    points: [[0, 0], [1, 0]]\n"
      "    thickness: -0.2\n"
      "    height: 2\n"
      "    material: concrete\n",
      1, "walls[0].thickness", "thickness: -0.2");
  EXPECT_TRUE(Contains(d.message, "must be in"));
  EXPECT_TRUE(Contains(d.message, "got -0.2"));
}

// Confirms that NaN is rejected as a non-finite number.
TEST(WorldLoaderTest, ReportsNan) {
  const Diagnostic d = ExpectError(
      "cylinders:\n"
      "  - id: column\n"
      "    position: [1, 1]\n"
      "    radius: .nan\n"
      "    height: 2\n"
      "    material: concrete\n",
      1, "cylinders[0].radius", "radius: .nan");
  EXPECT_TRUE(Contains(d.message, "finite"));
}

// Confirms that a reference to a material the world does not define is reported.
TEST(WorldLoaderTest, ReportsUnknownMaterial) {
  const Diagnostic d = ExpectError(
      "boxes:\n"
      "  - id: crate\n"
      "    pose: [0, 0, 0]\n"
      "    size: [1, 1, 1]\n"
      "    material: marble\n",
      1, "boxes[0].material", "material: marble");
  EXPECT_TRUE(Contains(d.message, "unknown material 'marble'"));
}

// Confirms that ids are unique across element kinds (and that "floor" is reserved).
TEST(WorldLoaderTest, ReportsDuplicateElementId) {
  const Diagnostic d = ExpectError(
      "boxes:\n"
      "  - id: crate\n"
      "    pose: [0, 0, 0]\n"
      "    size: [1, 1, 1]\n"
      "    material: wood\n"
      "cylinders:\n"
      "  - id: crate\n"
      "    position: [3, 3]\n"
      "    radius: 0.2\n"
      "    height: 1\n"
      "    material: wood\n",
      1, "cylinders[0].id", "  - id: crate\n    position");
  EXPECT_TRUE(Contains(d.message, "'crate' is already used"));

  const Diagnostic reserved = ExpectError(
      "walls:\n"
      "  - id: floor\n"
      "    points: [[0, 0], [1, 0]]\n"
      "    thickness: 0.2\n"
      "    height: 2\n"
      "    material: concrete\n",
      1, "walls[0].id", "id: floor");
  EXPECT_TRUE(Contains(reserved.message, "reserved"));
}

// Confirms that a wall that turns back on itself is rejected for its mitre.
TEST(WorldLoaderTest, ReportsWallTurningBackOnItself) {
  const Diagnostic d = ExpectError(
      "walls:\n"
      "  - id: hairpin\n"
      "    points: [[0, 0], [4, 0], [0, 0.1]]\n"
      "    thickness: 0.2\n"
      "    height: 2\n"
      "    material: concrete\n",
      1, "walls[0].points", "points:");
  EXPECT_TRUE(Contains(d.message, "turns too sharply"));
}

// Confirms that every problem of one file is reported, each at its own line.
TEST(WorldLoaderTest, ReportsEveryProblemOfAFile) {
  const std::string text = kHeader +
                           "colour: red\n"
                           "boxes:\n"
                           "  - id: crate\n"
                           "    pose: [0, 0, .inf]\n"
                           "    size: [1, 0, 1]\n"
                           "    material: marble\n"
                           "places:\n"
                           "  nowhere: {}\n";
  const std::string path = WriteFile(TestDir(), "world.yaml", text);
  const auto all = LoadErrors(path);
  ASSERT_EQ(all.size(), 5u);
  EXPECT_EQ(Find(all, "colour").line, LineOf(text, "colour"));
  EXPECT_EQ(Find(all, "boxes[0].pose[2]").line, LineOf(text, "pose:"));
  EXPECT_EQ(Find(all, "boxes[0].size").line, LineOf(text, "size:"));
  EXPECT_EQ(Find(all, "boxes[0].material").line, LineOf(text, "marble"));
  EXPECT_EQ(Find(all, "places.nowhere").line, LineOf(text, "nowhere"));
}

// The 12 triangles of the unit cube [0, 1]^3, outward-facing, as ASCII STL.
std::string UnitCubeStl() {
  const int tris[12][3][3] = {{{0, 0, 0}, {1, 1, 0}, {1, 0, 0}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}},
                              {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}}, {{0, 0, 1}, {1, 1, 1}, {0, 1, 1}},
                              {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}}, {{0, 0, 0}, {1, 0, 1}, {0, 0, 1}},
                              {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}}, {{0, 1, 0}, {1, 1, 1}, {1, 1, 0}},
                              {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}}, {{0, 0, 0}, {0, 1, 1}, {0, 1, 0}},
                              {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}}, {{1, 0, 0}, {1, 1, 1}, {1, 0, 1}}};
  std::string stl = "solid cube\n";
  for (const auto& tri : tris) {
    stl += "  facet normal 0 0 0\n    outer loop\n";
    for (const auto& v : tri) {
      stl += "      vertex " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
             std::to_string(v[2]) + "\n";
    }
    stl += "    endloop\n  endfacet\n";
  }
  return stl + "endsolid cube\n";
}

// Confirms that an STL mesh loads with its scale and pose, and is cut where it was placed.
TEST(WorldLoaderTest, LoadsScaledStlMesh) {
  const fs::path dir = TestDir();
  fs::create_directories(dir / "meshes");
  WriteFile(dir / "meshes", "cube.stl", UnitCubeStl());
  const std::string path = WriteFile(dir, "world.yaml",
                                     kHeader +
                                         "meshes:\n"
                                         "  - id: cube\n"
                                         "    file: meshes/cube.stl\n"
                                         "    pose: [1, 2, 0, 0.5]\n"
                                         "    scale: 2\n"
                                         "    material: wood\n");
  const sim::WorldDescription w = LoadWorldFile(path);
  EXPECT_TRUE(ValidateFile(path).empty());
  ASSERT_EQ(w.meshes.size(), 1u);
  const sim::Mesh& m = w.meshes[0];
  EXPECT_EQ(fs::path(m.file), (dir / "meshes" / "cube.stl").lexically_normal());
  EXPECT_EQ(m.scale, Eigen::Vector3d(2, 2, 2));
  EXPECT_EQ(m.position_m, Eigen::Vector3d(1, 2, 0));
  EXPECT_DOUBLE_EQ(m.yaw_rad, 0.5);
  const auto mesh = sim::LoadTriangleMesh(m.file);
  EXPECT_EQ(mesh->triangles.size(), 12u);
  EXPECT_EQ(mesh->vertices.size(), 8u);

  // The cut at z = 1 is the 2 m square's outline, yawed by 0.5 about (1, 2).
  sim::World world(w, sim::WorldOptions{});
  const core::PlanarSection section = world.SectionAt(1.0);
  const Eigen::Rotation2Dd mesh_from_world(-0.5);
  const Eigen::Vector2d origin(1, 2);
  const Eigen::Vector2d centre = origin + Eigen::Rotation2Dd(0.5) * Eigen::Vector2d(1, 1);
  constexpr double kTol = 1e-9;
  double length = 0.0;
  for (const core::SectionSegment& s : section.segments) {
    if (section.elements[s.element].id != "cube") continue;
    length += (s.b_m - s.a_m).norm();
    for (const Eigen::Vector2d& p : {s.a_m, s.b_m}) {
      const Eigen::Vector2d q = mesh_from_world * (p - origin);
      EXPECT_GE(q.minCoeff(), -kTol);
      EXPECT_LE(q.maxCoeff(), 2.0 + kTol);
      const double to_edge = std::min({q.x(), q.y(), 2.0 - q.x(), 2.0 - q.y()});
      EXPECT_NEAR(to_edge, 0.0, kTol);
    }
    // Solid on the left: the outward normal (direction turned by -90°) points away.
    const Eigen::Vector2d d = s.b_m - s.a_m;
    const Eigen::Vector2d outward(d.y(), -d.x());
    EXPECT_GT(outward.dot(0.5 * (s.a_m + s.b_m) - centre), 0.0);
  }
  EXPECT_NEAR(length, 8.0, 1e-9);
}

// Confirms that every shipped world loads and validates without a diagnostic.
TEST(WorldLoaderTest, EveryShippedWorldLoadsAndValidates) {
  const fs::path worlds = fs::path(PAVILION_SOURCE_DIR) / "worlds";
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(worlds)) {
    const fs::path file = entry.path() / "world.yaml";
    if (!entry.is_directory() || !fs::is_regular_file(file)) continue;
    SCOPED_TRACE(file.string());
    names.insert(entry.path().filename().string());
    sim::WorldDescription w;
    try {
      w = LoadWorldFile(file.string());
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what() << " (" << e.diagnostics().size() << " problems)";
      continue;
    }
    EXPECT_EQ(w.name, entry.path().filename().string()) << "name differs from its folder";
    const std::vector<Diagnostic> diagnostics = ValidateFile(file.string());
    for (const Diagnostic& d : diagnostics) ADD_FAILURE() << d.ToString();
  }
  EXPECT_GE(names.size(), 3u);
  for (const char* expected : {"expo_hall", "office_floor", "small_lab"}) {
    EXPECT_TRUE(names.contains(expected)) << "missing worlds/" << expected << "/world.yaml";
  }
}

}  // namespace
}  // namespace pavilion::scenarios
