#include "scenarios/realism/world_realism.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/geometry/segment2.h"
#include "core/random/random_stream.h"

namespace pavilion::scenarios {
namespace {

using Vec2 = Eigen::Vector2d;

// Heights at which the free space in front of a face is probed: below every
// object and at the robots' scan plane (m).
constexpr std::array<double, 2> kProbeHeightsM = {0.2, 0.5};
// An object needs this much free floor in front of it (m): clutter narrows a
// corridor, it does not close it.
constexpr double kFreeBeyondM = 1.0;
// A face that meets nothing within this (m) faces the outside of the building.
constexpr double kInsideRangeM = 30.0;
// Objects keep this far from a face's ends (corners, openings) and from
// each other (m).
constexpr double kEndMarginM = 0.3;
constexpr double kObjectGapM = 0.1;
// ... and this far beyond a door's width from its hinge (m).
constexpr double kDoorMarginM = 0.5;
// Carpet squares, and the least extra wheel turn of one as a share of the most.
constexpr double kCarpetSquareM = 4.0;
constexpr double kCarpetMinShare = 0.2;

enum class Kind { kRadiator, kCabinet, kPoster, kTable, kPlant };
// A table's legs: radius and inset from its footprint's corners (m); its top's height.
constexpr double kTableLegRadiusM = 0.02;
constexpr double kTableLegInsetM = 0.05;
constexpr double kTableHeightM = 0.72;

// One object against a face: its footprint rectangle (centre, along the face
// u with half width, into the room n with half depth).
struct Footprint {
  Vec2 centre;
  Vec2 u;
  Vec2 n;
  double half_width = 0.0;
  double half_depth = 0.0;

  std::array<Vec2, 4> Corners() const {
    const Vec2 a = half_width * u, b = half_depth * n;
    return {centre - a - b, centre + a - b, centre + a + b, centre - a + b};
  }
  double Radius() const { return std::hypot(half_width, half_depth); }
};

double DistanceToSegment(const Footprint& f, const Vec2& a, const Vec2& b) {
  const std::array<Vec2, 4> c = f.Corners();
  double d = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k)
    d = std::min(d, core::SegmentSegmentDistance(c[k], c[(k + 1) % 4], a, b));
  return d;
}

class ClutterPlacer {
 public:
  ClutterPlacer(const RealismProfile& profile, std::uint64_t seed, const sim::World& survey,
                const sim::WorldDescription& description, const ClutterKeepOut& keep_out)
      : profile_(profile),
        survey_(survey),
        description_(description),
        keep_out_(keep_out),
        seed_(seed),
        random_(seed, core::RandomStream::StreamId("realism/world")) {}

  RealWorldChanges Draw() {
    if (profile_.clutter_per_m > 0.0) {
      for (const sim::Wall& wall : description_.walls) PlaceAlong(wall);
    }
    for (const sim::Door& door : description_.doors) {
      // One draw per door whatever its state, so the doors do not shift each other.
      const double u = random_.Uniform();
      if (!door.open && u < profile_.door_flip_probability)
        changes_.opened_doors.push_back(door.id);
    }
    LayCarpets();
    return changes_;
  }

 private:
  // Carpet squares over the floor (their own stream: clutter and doors keep their draws).
  void LayCarpets() {
    if (profile_.carpet_fraction <= 0.0) return;
    core::RandomStream draw(seed_, core::RandomStream::StreamId("realism/carpet"));
    const sim::Floor& floor = description_.floor;
    for (double x = floor.min_m.x(); x < floor.max_m.x(); x += kCarpetSquareM) {
      for (double y = floor.min_m.y(); y < floor.max_m.y(); y += kCarpetSquareM) {
        const double u = draw.Uniform();
        const double error = draw.Uniform(kCarpetMinShare, 1.0) * profile_.carpet_travel_error;
        if (u >= profile_.carpet_fraction) continue;
        const double x1 = std::min(x + kCarpetSquareM, floor.max_m.x());
        const double y1 = std::min(y + kCarpetSquareM, floor.max_m.y());
        changes_.carpets.push_back({"carpet_" + std::to_string(changes_.carpets.size() + 1),
                                    {{x, y}, {x1, y}, {x1, y1}, {x, y1}},
                                    error});
      }
    }
  }

  void PlaceAlong(const sim::Wall& wall) {
    const std::size_t n = wall.points_m.size();
    const std::size_t segments = wall.closed ? n : n - 1;
    for (std::size_t k = 0; k < segments && n >= 2; ++k) {
      const Vec2 a = wall.points_m[k], b = wall.points_m[(k + 1) % n];
      const double length = (b - a).norm();
      if (length < 2.0 * kEndMarginM) continue;
      const Vec2 u = (b - a) / length;
      for (const double side : {1.0, -1.0}) {
        const Vec2 normal = side * Vec2(-u.y(), u.x());
        PlaceAlongFace(a + 0.5 * wall.thickness_m * normal, u, normal, length);
      }
    }
  }

  // Objects at exponential gaps along the face from `start` along u.
  void PlaceAlongFace(const Vec2& start, const Vec2& u, const Vec2& normal, double length) {
    double t = kEndMarginM;
    while (true) {
      t += -std::log(1.0 - random_.Uniform()) / profile_.clutter_per_m;
      const Kind kind = DrawKind();
      const double width = DrawWidth(kind);
      if (t + width > length - kEndMarginM) return;
      TryPlace(kind, start + (t + 0.5 * width) * u, u, normal, width);
      t += width + kObjectGapM;
    }
  }

  Kind DrawKind() {
    const double p = random_.Uniform();
    if (p < 0.25) return Kind::kRadiator;
    if (p < 0.55) return Kind::kCabinet;
    if (p < 0.7) return Kind::kPoster;
    if (p < 0.9) return Kind::kTable;
    return Kind::kPlant;
  }
  double DrawWidth(Kind kind) {
    switch (kind) {
      case Kind::kRadiator:
        return random_.Uniform(0.8, 1.6);
      case Kind::kCabinet:
        return random_.Uniform(0.4, 1.2);
      case Kind::kPoster:
        return random_.Uniform(0.4, 1.0);
      case Kind::kTable:
        return random_.Uniform(1.2, 1.8);
      case Kind::kPlant:
        return 2.0 * random_.Uniform(0.15, 0.3);
    }
    return 1.0;
  }

  void TryPlace(Kind kind, const Vec2& on_face, const Vec2& u, const Vec2& normal, double width) {
    // Draws first, so that a rejected place consumes the same numbers.
    const double gap = kind == Kind::kPoster ? 0.0 : random_.Uniform(0.01, 0.05);
    const double depth = kind == Kind::kRadiator  ? 0.10
                         : kind == Kind::kCabinet ? random_.Uniform(0.35, 0.5)
                         : kind == Kind::kPoster  ? random_.Uniform(0.01, 0.03)
                         : kind == Kind::kTable   ? random_.Uniform(0.6, 0.8)
                                                  : width;
    const double height = kind == Kind::kCabinet ? random_.Uniform(0.8, 2.0) : 0.0;
    Footprint f{on_face + (gap + 0.5 * depth) * normal, u, normal, 0.5 * width, 0.5 * depth};
    if (!Free(on_face, u, normal, width, gap + depth) || !ClearOfOthers(f)) return;
    placed_.push_back(f);
    const std::string id = Id();
    if (kind == Kind::kPlant) {
      sim::Cylinder c;
      c.id = id;
      c.position_m = f.centre;
      c.radius_m = 0.5 * width;
      c.height_m = 1.2;
      c.material = kClutterMaterial;
      changes_.cylinders.push_back(c);
      return;
    }
    if (kind == Kind::kTable) {
      AddTable(id, f);
      return;
    }
    sim::Box box;
    box.id = id;
    box.pose = core::Pose2{f.centre.x(), f.centre.y(), std::atan2(u.y(), u.x())};
    box.material = kClutterMaterial;
    switch (kind) {
      case Kind::kRadiator:
        box.size_m = {width, depth, 0.6};
        box.base_z_m = 0.12;
        break;
      case Kind::kPoster:  // a framed board hanging from 1.2 m down to 0.3 m
        box.size_m = {width, depth, 0.9};
        box.base_z_m = 0.3;
        break;
      default:
        box.size_m = {width, depth, height};
        break;
    }
    changes_.boxes.push_back(box);
  }

  // Four thin legs (what the scan plane cuts: isolated readings in front of
  // the wall) under a top above the scan plane.
  void AddTable(const std::string& id, const Footprint& f) {
    const double a = f.half_width - kTableLegInsetM, b = f.half_depth - kTableLegInsetM;
    int leg = 0;
    for (const double su : {-1.0, 1.0}) {
      for (const double sn : {-1.0, 1.0}) {
        sim::Cylinder c;
        c.id = id + "_leg" + std::to_string(++leg);
        c.position_m = f.centre + su * a * f.u + sn * b * f.n;
        c.radius_m = kTableLegRadiusM;
        c.height_m = kTableHeightM;
        c.material = kClutterMaterial;
        changes_.cylinders.push_back(c);
      }
    }
    sim::Box top;
    top.id = id;
    top.pose = core::Pose2{f.centre.x(), f.centre.y(), std::atan2(f.u.y(), f.u.x())};
    top.size_m = {2.0 * f.half_width, 2.0 * f.half_depth, 0.03};
    top.base_z_m = kTableHeightM;
    top.material = kClutterMaterial;
    changes_.boxes.push_back(top);
  }

  // The face is there under the whole width, inside the building, with free
  // floor in front of it, away from doors.
  bool Free(const Vec2& centre, const Vec2& u, const Vec2& normal, double width, double depth) {
    for (const double s : {-0.5, 0.0, 0.5}) {
      const Vec2 p = centre + s * width * u;
      for (const double z : kProbeHeightsM) {
        // The face: a ray from just in front of it back onto it.
        const Vec2 front = p + 0.02 * normal;
        const sim::RayHit back = survey_.CastRay(
            {front.x(), front.y(), z}, {p.x() - 0.02 * normal.x(), p.y() - 0.02 * normal.y(), z});
        if (!back.hit) return false;
        const sim::RayHit ahead = survey_.CastRay(
            {front.x(), front.y(), z},
            {front.x() + kInsideRangeM * normal.x(), front.y() + kInsideRangeM * normal.y(), z});
        if (!ahead.hit || ahead.distance_m < depth + kFreeBeyondM) return false;
      }
    }
    for (const sim::Door& door : description_.doors) {
      if ((door.hinge_m - centre).norm() < door.width_m + kDoorMarginM + 0.5 * width) return false;
    }
    return true;
  }

  bool ClearOfOthers(const Footprint& f) const {
    for (const Vec2& p : keep_out_.points_m) {
      if ((p - f.centre).norm() < keep_out_.clearance_m + f.Radius()) return false;
    }
    for (const auto& [a, b] : keep_out_.roads_m) {
      if (DistanceToSegment(f, a, b) < keep_out_.clearance_m) return false;
    }
    for (const Footprint& other : placed_) {
      if ((other.centre - f.centre).norm() < other.Radius() + f.Radius() + kObjectGapM) {
        return false;
      }
    }
    return true;
  }

  std::string Id() {
    char id[32];
    std::snprintf(id, sizeof(id), "clutter_%03d", ++count_);
    return id;
  }

  const RealismProfile& profile_;
  const sim::World& survey_;
  const sim::WorldDescription& description_;
  const ClutterKeepOut& keep_out_;
  std::uint64_t seed_;
  core::RandomStream random_;
  std::vector<Footprint> placed_;
  RealWorldChanges changes_;
  int count_ = 0;
};

}  // namespace

void AddRoads(const core::RobotMap& map, ClutterKeepOut* keep_out) {
  std::map<std::string, Vec2> at;
  for (const core::MapNode& node : map.nodes) {
    at[node.id] = node.pose.translation();
    keep_out->points_m.push_back(node.pose.translation());
  }
  for (const core::MapEdge& edge : map.edges) {
    const auto a = at.find(edge.from), b = at.find(edge.to);
    if (a != at.end() && b != at.end()) keep_out->roads_m.emplace_back(a->second, b->second);
  }
}

RealWorldChanges DrawRealWorld(const RealismProfile& profile, std::uint64_t seed,
                               const sim::World& survey, const sim::WorldDescription& description,
                               const ClutterKeepOut& keep_out) {
  if (!profile.realistic) return {};
  RealWorldChanges changes = ClutterPlacer(profile, seed, survey, description, keep_out).Draw();
  if (profile.floor_max_slope_rad > 0.0) {  // its own stream: the other draws keep theirs
    core::RandomStream draw(seed, core::RandomStream::StreamId("realism/floor"));
    sim::FloorReliefOptions relief;
    relief.max_slope_rad = profile.floor_max_slope_rad;
    relief.min_wavelength_m = profile.floor_min_wavelength_m;
    relief.max_wavelength_m = profile.floor_max_wavelength_m;
    changes.relief =
        sim::DrawFloorRelief(relief, description.floor.min_m, description.floor.max_m, &draw);
  }
  return changes;
}

void ApplyRealWorld(const RealWorldChanges& changes, sim::WorldDescription* description) {
  if (!changes.boxes.empty() || !changes.cylinders.empty()) {
    sim::Material clutter;  // painted wood and metal: a normal laser surface
    clutter.friction = 0.6;
    clutter.rgba = {0.55, 0.45, 0.35, 1.0};
    description->materials.emplace(kClutterMaterial, clutter);
  }
  description->boxes.insert(description->boxes.end(), changes.boxes.begin(), changes.boxes.end());
  description->cylinders.insert(description->cylinders.end(), changes.cylinders.begin(),
                                changes.cylinders.end());
  if (!changes.relief.flat()) description->floor.relief = changes.relief;
  for (sim::Door& door : description->doors) {
    if (std::find(changes.opened_doors.begin(), changes.opened_doors.end(), door.id) !=
        changes.opened_doors.end()) {
      door.open = true;
    }
  }
}

}  // namespace pavilion::scenarios
