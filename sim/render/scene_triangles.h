#pragma once

// The world as coloured triangles for the off-screen renderer
// (sim/render/offscreen_renderer.h): every face flat-shaded on the CPU by
// fixed directional lights in the world frame, so that surfaces facing
// different ways differ in brightness and the same scene always gives the
// same colours. Pure geometry: no GL here.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/world/world.h"

namespace pavilion::sim {

// What a picture shows beyond the world itself.
struct RenderScene {
  // A robot index whose body is not drawn (the robot a camera is mounted on
  // sees past its own chassis), or -1: every robot drawn.
  int hide_robot = -1;
  // The world material whose colour the crowd's people are drawn in (World
  // does not expose the crowd's material); empty or not a material of the
  // world: kPersonRgb (sim/render/top_down_view.h).
  std::string people_material;
  // Where no surface is (above the walls: the world has no ceiling), RGB.
  std::array<std::uint8_t, 3> background_rgb{32, 32, 36};
};

// One vertex of a shaded triangle: world position and the face's lit colour
// (alpha < 255 for translucent materials).
struct ShadedVertex {
  float x = 0, y = 0, z = 0;
  std::array<std::uint8_t, 4> rgba{0, 0, 0, 255};
};

// Triangles, three vertices each, counter-clockwise seen from outside.
struct TriangleLists {
  std::vector<ShadedVertex> opaque;       // closed solids: back faces may be culled
  std::vector<ShadedVertex> two_sided;    // mesh files, whose winding is not trusted
  std::vector<ShadedVertex> translucent;  // materials with alpha < 1, drawn last, blended

  void Clear();
  std::size_t triangle_count() const;
};

// The brightness factor of a face with unit outward normal `normal_in_world`
// under the renderer's lights: ambient plus two directional lights (chosen so
// that faces towards +x, -x, +y, -y and up all differ by >= 0.1 of full
// scale), in (0, 1].
double FaceShade(const Eigen::Vector3d& normal_in_world);

// A material colour (rgba in [0, 1]) shaded by FaceShade: each channel
// round(255 * clamp(c * shade)), alpha round(255 * a).
std::array<std::uint8_t, 4> ShadedColour(const std::array<double, 4>& rgba,
                                         const Eigen::Vector3d& normal_in_world);

// The static parts of a world: the floor rectangle, walls, boxes, cylinders
// and meshes (not doors, which move). Throws std::out_of_range for an
// unknown material, std::runtime_error for an unreadable mesh file.
void AppendStaticScene(const WorldDescription& description, TriangleLists* out);

// A digest of everything AppendStaticScene reads (geometry, materials' colours,
// mesh files): equal digests give equal triangles.
std::uint64_t StaticSceneDigest(const WorldDescription& description);

// The parts that move, at their current state: doors (open or closed), bodies,
// the crowd's present people and the robots (chassis slabs, wheels, markers),
// except `scene.hide_robot`. Bodies and robots are drawn upright at their
// planar pose (World reports tilt without its axis).
void AppendDynamicScene(const World& world, const RenderScene& scene, TriangleLists* out);

}  // namespace pavilion::sim
