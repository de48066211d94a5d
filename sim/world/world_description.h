#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/planar_section.h"
#include "core/geometry/polygon.h"
#include "core/types/pose2.h"
#include "sim/world/floor_relief.h"

namespace pavilion::sim {

// Plain description of a world, filled by a loader (scenarios/ reads the YAML)
// and turned into a Bullet world by sim::World. Units: m, rad, kg. See
// docs/world_format.md for the meaning of every field.

struct Material {
  double friction = 0.8;                           // Coulomb coefficient, >= 0
  double restitution = 0.0;                        // [0, 1]
  std::array<double, 4> rgba{0.7, 0.7, 0.7, 1.0};  // rendering colour, [0, 1]
  core::LaserResponse laser = core::LaserResponse::kNormal;
};

struct Floor {
  Eigen::Vector2d min_m{-10.0, -10.0};
  Eigen::Vector2d max_m{10.0, 10.0};
  std::string material;
  // Slopes and bumps (`realism: realistic`); flat by default.
  FloorRelief relief;
};

// An extruded 2D polyline, centred on the polyline, mitred at its joints.
struct Wall {
  std::string id;
  std::vector<Eigen::Vector2d> points_m;
  bool closed = false;
  double thickness_m = 0.2;
  double height_m = 2.5;
  double base_z_m = 0.0;
  std::string material;
};

struct Box {
  std::string id;
  core::Pose2 pose;                 // footprint centre and yaw
  Eigen::Vector3d size_m{1, 1, 1};  // full extents
  double base_z_m = 0.0;            // height of the bottom face
  std::string material;
};

struct Cylinder {
  std::string id;
  Eigen::Vector2d position_m{0, 0};
  double radius_m = 0.5;
  double height_m = 1.0;
  double base_z_m = 0.0;
  std::string material;
};

struct Mesh {
  std::string id;
  std::string file;                     // absolute path, resolved by the loader
  Eigen::Vector3d position_m{0, 0, 0};  // placement of the mesh origin
  double yaw_rad = 0.0;
  Eigen::Vector3d scale{1, 1, 1};
  std::string material;
};

// A hinged panel that stands open or closed.
struct Door {
  std::string id;
  Eigen::Vector2d hinge_m{0, 0};
  double closed_yaw_rad = 0.0;
  double open_yaw_rad = 1.5707963267948966;
  double width_m = 0.9;
  double thickness_m = 0.04;
  double height_m = 2.0;
  bool open = false;
  std::string material;

  // The panel as a box element in its current state.
  Box AsBox() const;
};

// A named point with heading, or a named area.
struct Place {
  std::optional<core::Pose2> pose;
  std::optional<core::Polygon2> area;
  // A goal with a meaning (§6.3.1 station node: an office, a showcase); places
  // named station_* and dock_* are stations anyway. Needs a pose.
  bool station = false;
  // How strongly a station draws visitors of a crowd: its relative chance of
  // being chosen for a visit, >= 0 (0: never visited). Stations only.
  double attraction = 1.0;
};

struct WorldDescription {
  std::string name;
  std::string description;
  std::string source_file;  // for messages
  std::map<std::string, Material> materials;
  Floor floor;
  std::vector<Wall> walls;
  std::vector<Box> boxes;
  std::vector<Cylinder> cylinders;
  std::vector<Mesh> meshes;
  std::vector<Door> doors;
  std::map<std::string, Place> places;

  // Looks up a material; throws std::out_of_range naming it when missing.
  const Material& MaterialNamed(const std::string& name) const;
};

}  // namespace pavilion::sim
