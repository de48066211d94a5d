#include "scenarios/config/world_loader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "sim/world/triangle_mesh.h"
#include "sim/world/wall_geometry.h"

namespace pavilion::scenarios {
namespace {

// Coordinates beyond this are almost certainly a unit mistake (m).
constexpr double kMaxCoordinateM = 1e4;
constexpr double kMaxSizeM = 1e3;

const std::vector<std::string> kLaserChoices = {"normal", "retro_reflective", "dark", "specular",
                                                "transparent"};

core::LaserResponse ParseLaser(const std::string& s) {
  if (s == "retro_reflective") return core::LaserResponse::kRetroReflective;
  if (s == "dark") return core::LaserResponse::kDark;
  if (s == "specular") return core::LaserResponse::kSpecular;
  if (s == "transparent") return core::LaserResponse::kTransparent;
  return core::LaserResponse::kNormal;
}

// True when `s` is non-empty and made of lower-case letters, digits and '_'
// (and, when `id` is set, also upper-case letters and '-').
bool IsName(const std::string& s, bool id) {
  if (s.empty()) return false;
  for (const char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
                    (id && ((c >= 'A' && c <= 'Z') || c == '-'));
    if (!ok) return false;
  }
  return true;
}

bool InBounds(const std::vector<double>& v, double bound) {
  for (double x : v) {
    if (std::abs(x) > bound) return false;
  }
  return true;
}

// Reads the fields every element shares and checks id uniqueness and material.
class ElementContext {
 public:
  ElementContext(YamlDocument* doc, const sim::WorldDescription* world) : doc_(doc), world_(world) {
    ids_.insert("floor");  // reserved for the floor element
  }

  std::string Id(MapReader& r) {
    auto id = r.RequiredString("id");
    if (!id) return "";
    if (!IsName(*id, true)) {
      doc_->Error(r.Child("id"), r.PathOf("id"), "must use letters, digits, '_' or '-'");
    } else if (!ids_.insert(*id).second) {
      doc_->Error(r.Child("id"), r.PathOf("id"),
                  "'" + *id + "' is already used by another element (or reserved)");
    }
    return *id;
  }

  std::string MaterialRef(MapReader& r) {
    auto m = r.RequiredString("material");
    if (!m) return "";
    if (!world_->materials.contains(*m)) {
      doc_->Error(r.Child("material"), r.PathOf("material"), "unknown material '" + *m + "'");
    }
    return *m;
  }

 private:
  YamlDocument* doc_;
  const sim::WorldDescription* world_;
  std::set<std::string> ids_;
};

std::optional<Eigen::Vector2d> Point2(YamlDocument* doc, const YAML::Node& n,
                                      const std::string& path) {
  auto v = ReadNumbers(doc, n, path, 2);
  if (!v) return std::nullopt;
  if (!InBounds(*v, kMaxCoordinateM)) {
    doc->Error(n, path, "coordinate beyond ±10 km; units are metres");
    return std::nullopt;
  }
  return Eigen::Vector2d((*v)[0], (*v)[1]);
}

std::optional<core::Polygon2> Polygon(YamlDocument* doc, const YAML::Node& n,
                                      const std::string& path) {
  if (!n.IsSequence() || n.size() < 3) {
    doc->Error(n, path, "expected a list of at least 3 [x, y] points");
    return std::nullopt;
  }
  core::Polygon2 poly;
  for (std::size_t i = 0; i < n.size(); ++i) {
    auto p = Point2(doc, n[i], IndexPath(path, i));
    if (!p) return std::nullopt;
    poly.push_back(*p);
  }
  if (!core::IsSimple(poly) || std::abs(core::SignedArea(poly)) < 1e-9) {
    doc->Error(n, path, "polygon must be simple (edges must not cross) with non-zero area");
    return std::nullopt;
  }
  return poly;
}

void ReadFloor(YamlDocument* doc, MapReader& top, ElementContext& ctx, sim::WorldDescription* w) {
  MapReader r(doc, top.Child("floor", true), "floor");
  if (!r.valid()) return;
  auto lo = r.Child("min", true);
  auto hi = r.Child("max", true);
  auto min = lo.IsDefined() ? Point2(doc, lo, "floor.min") : std::nullopt;
  auto max = hi.IsDefined() ? Point2(doc, hi, "floor.max") : std::nullopt;
  if (min && max) {
    if (!((*max - *min).minCoeff() > 0.0)) {
      doc->Error(hi, "floor.max", "must be greater than floor.min in x and y");
    }
    w->floor.min_m = *min;
    w->floor.max_m = *max;
  }
  w->floor.material = ctx.MaterialRef(r);
  r.Finish();
}

void ReadWall(YamlDocument* doc, MapReader& r, ElementContext& ctx, sim::WorldDescription* w) {
  sim::Wall wall;
  wall.id = ctx.Id(r);
  YAML::Node pts = r.Child("points", true);
  if (pts.IsDefined()) {
    if (!pts.IsSequence() || pts.size() < 2) {
      doc->Error(pts, r.PathOf("points"), "expected a list of at least 2 [x, y] points");
    } else {
      for (std::size_t i = 0; i < pts.size(); ++i) {
        if (auto p = Point2(doc, pts[i], IndexPath(r.PathOf("points"), i)))
          wall.points_m.push_back(*p);
      }
    }
  }
  wall.closed = r.Bool("closed", false);
  wall.thickness_m = r.RequiredNumber("thickness", 1e-3, kMaxSizeM).value_or(0.2);
  wall.height_m = r.RequiredNumber("height", 1e-3, kMaxSizeM).value_or(2.5);
  wall.base_z_m = r.Number("z", 0.0, -kMaxSizeM, kMaxSizeM);
  wall.material = ctx.MaterialRef(r);
  if (wall.points_m.size() >= 2 && wall.points_m.size() == pts.size()) {
    bool distinct = true;
    const std::size_t n = wall.points_m.size();
    for (std::size_t i = 0; i + 1 < n + (wall.closed ? 1 : 0); ++i) {
      if ((wall.points_m[i] - wall.points_m[(i + 1) % n]).norm() < 1e-6) distinct = false;
    }
    if (!distinct) {
      doc->Error(pts, r.PathOf("points"), "consecutive points must differ");
    } else if (wall.closed && n < 3) {
      doc->Error(pts, r.PathOf("points"), "a closed wall needs at least 3 points");
    } else if (sim::MaxMitreRatio(wall) > sim::kMaxMitreRatio) {
      doc->Error(pts, r.PathOf("points"),
                 "turns too sharply at a joint (mitre longer than " +
                     std::to_string(static_cast<int>(sim::kMaxMitreRatio)) +
                     " half thicknesses); split it into two walls");
    }
  }
  w->walls.push_back(wall);
}

std::optional<core::Pose2> Pose(YamlDocument* doc, MapReader& r, const std::string& key,
                                bool required) {
  auto v = r.Numbers(key, 3, required);
  if (!v) return std::nullopt;
  if (!InBounds({(*v)[0], (*v)[1]}, kMaxCoordinateM)) {
    doc->Error(r.Child(key), r.PathOf(key), "coordinate beyond ±10 km; units are metres");
    return std::nullopt;
  }
  return core::Pose2{(*v)[0], (*v)[1], (*v)[2]};
}

std::optional<Eigen::Vector3d> PositiveSize(YamlDocument* doc, MapReader& r,
                                            const std::string& key) {
  auto v = r.Numbers(key, 3, true);
  if (!v) return std::nullopt;
  for (double x : *v) {
    if (!(x > 0.0 && x <= kMaxSizeM)) {
      doc->Error(r.Child(key), r.PathOf(key), "every size must be in (0, 1000] m");
      return std::nullopt;
    }
  }
  return Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]);
}

void ReadBox(YamlDocument* doc, MapReader& r, ElementContext& ctx, sim::WorldDescription* w) {
  sim::Box box;
  box.id = ctx.Id(r);
  box.pose = Pose(doc, r, "pose", true).value_or(core::Pose2{});
  box.size_m = PositiveSize(doc, r, "size").value_or(Eigen::Vector3d(1, 1, 1));
  box.base_z_m = r.Number("z", 0.0, -kMaxSizeM, kMaxSizeM);
  box.material = ctx.MaterialRef(r);
  w->boxes.push_back(box);
}

void ReadCylinder(YamlDocument* doc, MapReader& r, ElementContext& ctx, sim::WorldDescription* w) {
  sim::Cylinder c;
  c.id = ctx.Id(r);
  YAML::Node pos = r.Child("position", true);
  if (pos.IsDefined()) {
    if (auto p = Point2(doc, pos, r.PathOf("position"))) c.position_m = *p;
  }
  c.radius_m = r.RequiredNumber("radius", 1e-3, kMaxSizeM).value_or(0.5);
  c.height_m = r.RequiredNumber("height", 1e-3, kMaxSizeM).value_or(1.0);
  c.base_z_m = r.Number("z", 0.0, -kMaxSizeM, kMaxSizeM);
  c.material = ctx.MaterialRef(r);
  w->cylinders.push_back(c);
}

void ReadMesh(YamlDocument* doc, MapReader& r, ElementContext& ctx, sim::WorldDescription* w) {
  namespace fs = std::filesystem;
  sim::Mesh m;
  m.id = ctx.Id(r);
  if (auto file = r.RequiredString("file")) {
    fs::path p(*file);
    if (p.is_relative()) p = fs::path(doc->path()).parent_path() / p;
    m.file = p.lexically_normal().string();
    if (!fs::is_regular_file(p)) {
      doc->Error(r.Child("file"), r.PathOf("file"), "mesh file not found: " + m.file);
    } else {
      try {
        sim::LoadTriangleMesh(m.file);
      } catch (const std::exception& e) {
        doc->Error(r.Child("file"), r.PathOf("file"), e.what());
      }
    }
  }
  if (auto pose = r.Numbers("pose", 4, true)) {
    m.position_m = {(*pose)[0], (*pose)[1], (*pose)[2]};
    m.yaw_rad = (*pose)[3];
  }
  YAML::Node scale = r.Child("scale");
  if (scale.IsDefined()) {
    std::optional<std::vector<double>> s;
    if (scale.IsSequence()) {
      s = ReadNumbers(doc, scale, r.PathOf("scale"), 3);
    } else if (auto x = ReadNumber(doc, scale, r.PathOf("scale"))) {
      s = std::vector<double>{*x, *x, *x};
    }
    if (s) {
      if (*std::min_element(s->begin(), s->end()) <= 0.0) {
        doc->Error(scale, r.PathOf("scale"), "must be > 0");
      } else {
        m.scale = {(*s)[0], (*s)[1], (*s)[2]};
      }
    }
  }
  m.material = ctx.MaterialRef(r);
  w->meshes.push_back(m);
}

void ReadDoor(YamlDocument* doc, MapReader& r, ElementContext& ctx, sim::WorldDescription* w) {
  sim::Door d;
  d.id = ctx.Id(r);
  YAML::Node hinge = r.Child("hinge", true);
  if (hinge.IsDefined()) {
    if (auto p = Point2(doc, hinge, r.PathOf("hinge"))) d.hinge_m = *p;
  }
  d.closed_yaw_rad = r.RequiredNumber("closed_yaw", -10.0, 10.0).value_or(0.0);
  d.open_yaw_rad = r.RequiredNumber("open_yaw", -10.0, 10.0).value_or(0.0);
  d.width_m = r.RequiredNumber("width", 1e-3, kMaxSizeM).value_or(0.9);
  d.thickness_m = r.RequiredNumber("thickness", 1e-3, kMaxSizeM).value_or(0.04);
  d.height_m = r.RequiredNumber("height", 1e-3, kMaxSizeM).value_or(2.0);
  d.open = r.Choice("state", {"open", "closed"}, "closed", true) == "open";
  d.material = ctx.MaterialRef(r);
  w->doors.push_back(d);
}

// A station: flagged so or named station_* or dock_* (as map derivation decides).
bool IsStation(const std::string& name, const sim::Place& place) {
  return place.station || name.starts_with("station_") || name.starts_with("dock_");
}

void ReadPlaces(YamlDocument* doc, MapReader& top, sim::WorldDescription* w) {
  YAML::Node n = top.Child("places");
  if (!n.IsDefined() || n.IsNull()) return;
  if (!n.IsMap()) {
    doc->Error(n, "places", "expected a mapping of place names");
    return;
  }
  for (const auto& kv : n) {
    const std::string name = kv.first.Scalar();
    MapReader r(doc, kv.second, "places." + name);
    if (!r.valid()) continue;
    sim::Place place;
    if (r.Has("pose")) place.pose = Pose(doc, r, "pose", true);
    if (r.Has("area")) place.area = Polygon(doc, r.Child("area"), r.PathOf("area"));
    if (!r.Has("pose") && !r.Has("area")) {
      doc->Error(kv.second, "places." + name, "a place needs a pose or an area");
    }
    place.station = r.Bool("station", false);
    if (place.station && !place.pose) {
      doc->Error(r.Child("station"), r.PathOf("station"), "a station needs a pose");
    }
    if (r.Has("attraction")) {
      // A relative weight: any finite number >= 0 (0: never visited).
      const YAML::Node node = r.Child("attraction");
      if (auto a = ReadNumber(doc, node, r.PathOf("attraction"))) {
        if (*a >= 0.0) {
          place.attraction = *a;
        } else {
          doc->Error(node, r.PathOf("attraction"),
                     "must be >= 0 (a relative weight; 0: never visited)");
        }
      }
      if (!IsStation(name, place)) {
        doc->Error(r.Child("attraction"), r.PathOf("attraction"),
                   "only a station draws visitors (station: true, or a name station_* or dock_*)");
      }
    }
    r.Finish();
    w->places[name] = place;
  }
}

}  // namespace

void ReadMaterialMap(YamlDocument* doc, const YAML::Node& n, const std::string& path,
                     std::map<std::string, sim::Material>* out) {
  if (!n.IsMap() || n.size() == 0) {
    doc->Error(n, path, "expected a mapping of material names to properties");
    return;
  }
  for (const auto& kv : n) {
    const std::string name = kv.first.Scalar();
    MapReader r(doc, kv.second, path + "." + name);
    sim::Material m;
    m.friction = r.Number("friction", m.friction, 0.0, 10.0);
    m.restitution = r.Number("restitution", m.restitution, 0.0, 1.0);
    if (auto c = r.Numbers("color", 0, false)) {
      if ((c->size() != 3 && c->size() != 4) || !InBounds(*c, 1.0) ||
          *std::min_element(c->begin(), c->end()) < 0.0) {
        doc->Error(r.Child("color"), r.PathOf("color"), "expected 3 or 4 numbers in [0, 1]");
      } else {
        for (std::size_t i = 0; i < c->size(); ++i) m.rgba[i] = (*c)[i];
      }
    }
    m.laser = ParseLaser(r.Choice("laser", kLaserChoices, "normal"));
    r.Finish();
    (*out)[name] = m;
  }
}

sim::WorldDescription ReadWorld(YamlDocument* doc) {
  sim::WorldDescription w;
  w.source_file = doc->path();
  if (!doc->ok()) return w;  // unreadable or malformed: nothing to walk
  MapReader top(doc, doc->root(), "");
  if (!top.valid()) return w;
  if (auto kind = top.RequiredString("kind"); kind && *kind != "world") {
    doc->Error(top.Child("kind"), "kind", "expected 'world', got '" + *kind + "'");
  }
  if (auto name = top.RequiredString("name")) {
    if (!IsName(*name, false)) {
      doc->Error(top.Child("name"), "name", "must be lower-case letters, digits and '_'");
    }
    w.name = *name;
  }
  w.description = top.String("description", "");
  if (YAML::Node mats = top.Child("materials", true); mats.IsDefined()) {
    ReadMaterialMap(doc, mats, "materials", &w.materials);
  }
  ElementContext ctx(doc, &w);
  ReadFloor(doc, top, ctx, &w);
  ForEachMapping(doc, top, "walls", false,
                 [&](MapReader& r, std::size_t) { ReadWall(doc, r, ctx, &w); });
  ForEachMapping(doc, top, "boxes", false,
                 [&](MapReader& r, std::size_t) { ReadBox(doc, r, ctx, &w); });
  ForEachMapping(doc, top, "cylinders", false,
                 [&](MapReader& r, std::size_t) { ReadCylinder(doc, r, ctx, &w); });
  ForEachMapping(doc, top, "meshes", false,
                 [&](MapReader& r, std::size_t) { ReadMesh(doc, r, ctx, &w); });
  ForEachMapping(doc, top, "doors", false,
                 [&](MapReader& r, std::size_t) { ReadDoor(doc, r, ctx, &w); });
  ReadPlaces(doc, top, &w);
  top.Finish();
  return w;
}

sim::WorldDescription LoadWorldFile(const std::string& path) {
  YamlDocument doc(path);
  sim::WorldDescription w = ReadWorld(&doc);
  doc.ThrowIfErrors();
  return w;
}

}  // namespace pavilion::scenarios
