#include "sim/render/scene_triangles.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "sim/render/top_down_view.h"
#include "sim/world/triangle_mesh.h"
#include "sim/world/wall_geometry.h"

namespace pavilion::sim {
namespace {

using Rgba = std::array<double, 4>;

// Lighting (chosen, see FaceShade): ambient plus two directional lights, each
// given by the azimuth and elevation of the direction towards it.
constexpr double kAmbient = 0.35;
constexpr double kKeyStrength = 0.5;
constexpr double kKeyAzimuthDeg = 240.0;
constexpr double kKeyElevationDeg = 30.0;
constexpr double kFillStrength = 0.2;
constexpr double kFillAzimuthDeg = 310.0;
constexpr double kFillElevationDeg = 30.0;

// Curved surfaces as polygons: a static cylinder's inscribed polygon stays
// within kSilhouetteTolM of the circle (0.1 px at 2 m for focal lengths up to
// 1000 px), with at least kMinStaticSegments sides. Moving parts use fixed
// counts (chosen: smooth enough to read as round, cheap per frame).
constexpr double kSilhouetteTolM = 0.2e-3;
constexpr int kMinStaticSegments = 48;
constexpr int kMaxStaticSegments = 512;
constexpr int kLegSegments = 12;
constexpr int kTorsoSegments = 16;
constexpr int kHeadSegments = 12;
constexpr int kWheelSegments = 16;
constexpr int kMarkerSegments = 16;  // r 2 cm: within 0.4 mm of the circle
constexpr int kSphereSlices = 16;
constexpr int kSphereStacks = 8;

// A person (chosen): the torso an elliptical prism from the hip to the
// shoulders, as deep as kTorsoDepthRatio of its width (the laser's torso of
// sim/world/crowd_coupling.cc), the head an upright cylinder above it.
constexpr double kTorsoDepthRatio = 0.6;
constexpr double kHeadHeightM = 0.25;
constexpr double kHeadRadiusM = 0.09;
// Robot wheels (no material in the model): dark rubber.
constexpr Rgba kWheelRgba{0.12, 0.12, 0.12, 1.0};

Eigen::Vector3d TowardsLight(double azimuth_deg, double elevation_deg) {
  const double az = azimuth_deg * std::numbers::pi / 180.0;
  const double el = elevation_deg * std::numbers::pi / 180.0;
  return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

const Eigen::Vector3d kTowardsKey = TowardsLight(kKeyAzimuthDeg, kKeyElevationDeg);
const Eigen::Vector3d kTowardsFill = TowardsLight(kFillAzimuthDeg, kFillElevationDeg);

Rgba RgbaOf(const std::array<std::uint8_t, 3>& rgb) {
  return {rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0, 1.0};
}

// cos and sin of k 2π / segments, k = 0 .. segments - 1 (per thread: renderers
// may build their scenes concurrently).
const std::vector<Eigen::Vector2d>& UnitCircle(int segments) {
  thread_local std::map<int, std::vector<Eigen::Vector2d>> cache;
  std::vector<Eigen::Vector2d>& ring = cache[segments];
  if (ring.empty()) {
    for (int k = 0; k < segments; ++k) {
      const double t = 2.0 * std::numbers::pi * k / segments;
      ring.emplace_back(std::cos(t), std::sin(t));
    }
  }
  return ring;
}

// Collects shaded triangles into the list their colour belongs to. Each face
// is shaded once, by its own normal.
class TriangleSink {
 public:
  explicit TriangleSink(TriangleLists* out) : out_(out) {}

  void Triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                const Rgba& rgba, bool two_sided = false) {
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double len = n.norm();
    if (!(len > 0.0)) return;  // degenerate
    const std::array<std::uint8_t, 4> colour = ShadedColour(rgba, n / len);
    std::vector<ShadedVertex>& list = ListFor(colour, two_sided);
    for (const Eigen::Vector3d* p : {&a, &b, &c}) Put(list, *p, colour);
  }

  // The planar quadrilateral a b c d, counter-clockwise seen from outside.
  void Quad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
            const Eigen::Vector3d& d, const Rgba& rgba) {
    const Eigen::Vector3d n = (c - a).cross(d - b);
    const double len = n.norm();
    if (!(len > 0.0)) return;
    const std::array<std::uint8_t, 4> colour = ShadedColour(rgba, n / len);
    std::vector<ShadedVertex>& list = ListFor(colour, false);
    for (const Eigen::Vector3d* p : {&a, &b, &c, &a, &c, &d}) Put(list, *p, colour);
  }

  // A horizontal convex polygon at height z facing up (its outline
  // counter-clockwise from above) or down (the same outline, reversed).
  void Cap(const std::vector<Eigen::Vector2d>& outline, double z, bool up, const Rgba& rgba) {
    const std::array<std::uint8_t, 4> colour = ShadedColour(rgba, {0.0, 0.0, up ? 1.0 : -1.0});
    std::vector<ShadedVertex>& list = ListFor(colour, false);
    const std::size_t n = outline.size();
    const auto at = [&](std::size_t i) {
      const Eigen::Vector2d& p = outline[up ? i : n - 1 - i];
      return Eigen::Vector3d(p.x(), p.y(), z);
    };
    for (std::size_t i = 1; i + 1 < n; ++i) {
      Put(list, at(0), colour);
      Put(list, at(i), colour);
      Put(list, at(i + 1), colour);
    }
  }

  // The vertical side over the segment a -> b of an outline that has its solid
  // on the left.
  void Side(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double z0, double z1,
            const Rgba& rgba) {
    Quad({a.x(), a.y(), z0}, {b.x(), b.y(), z0}, {b.x(), b.y(), z1}, {a.x(), a.y(), z1}, rgba);
  }

  // A vertical prism over a convex counter-clockwise outline; the bottom face
  // only when it can be seen (above the floor) and `bottom`.
  void Prism(const std::vector<Eigen::Vector2d>& outline, double z0, double z1, const Rgba& rgba,
             bool bottom = true) {
    const std::size_t n = outline.size();
    for (std::size_t i = 0; i < n; ++i) Side(outline[i], outline[(i + 1) % n], z0, z1, rgba);
    Cap(outline, z1, true, rgba);
    if (bottom && z0 > 0.0) Cap(outline, z0, false, rgba);
  }

  // A cylinder of `segments` sides from the centre `p0` to `p1`, its end
  // discs only if `caps`.
  void Tube(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double radius, int segments,
            const Rgba& rgba, bool caps) {
    const Eigen::Vector3d w = (p1 - p0).normalized();
    const Eigen::Vector3d u = w.unitOrthogonal();
    const Eigen::Vector3d v = w.cross(u);  // (u, v, w) right-handed: rings turn about w
    const std::vector<Eigen::Vector2d>& unit = UnitCircle(segments);
    ring_.clear();
    for (const Eigen::Vector2d& c : unit) ring_.push_back(radius * (c.x() * u + c.y() * v));
    for (int k = 0; k < segments; ++k) {
      const Eigen::Vector3d& r0 = ring_[k];
      const Eigen::Vector3d& r1 = ring_[(k + 1) % segments];
      Quad(p0 + r0, p0 + r1, p1 + r1, p1 + r0, rgba);
    }
    if (!caps) return;
    for (int k = 1; k + 1 < segments; ++k) {
      Triangle(p1 + ring_[0], p1 + ring_[k], p1 + ring_[k + 1], rgba);
      Triangle(p0 + ring_[0], p0 + ring_[k + 1], p0 + ring_[k], rgba);
    }
  }

  void Sphere(const Eigen::Vector3d& centre, double radius, const Rgba& rgba) {
    const auto at = [&](int stack, int slice) {
      const double phi = std::numbers::pi * stack / kSphereStacks - 0.5 * std::numbers::pi;
      const double theta = 2.0 * std::numbers::pi * slice / kSphereSlices;
      return Eigen::Vector3d(centre + radius * Eigen::Vector3d(std::cos(phi) * std::cos(theta),
                                                               std::cos(phi) * std::sin(theta),
                                                               std::sin(phi)));
    };
    for (int i = 0; i < kSphereStacks; ++i) {
      for (int k = 0; k < kSphereSlices; ++k) {
        Triangle(at(i, k), at(i, k + 1), at(i + 1, k + 1), rgba);
        Triangle(at(i, k), at(i + 1, k + 1), at(i + 1, k), rgba);
      }
    }
  }

 private:
  std::vector<ShadedVertex>& ListFor(const std::array<std::uint8_t, 4>& colour, bool two_sided) {
    return colour[3] < 255 ? out_->translucent : two_sided ? out_->two_sided : out_->opaque;
  }

  static void Put(std::vector<ShadedVertex>& list, const Eigen::Vector3d& p,
                  const std::array<std::uint8_t, 4>& colour) {
    list.push_back(
        {static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()), colour});
  }

  TriangleLists* out_;
  std::vector<Eigen::Vector3d> ring_;  // Tube's scratch
};

// Sides of a static cylinder of this radius (see kSilhouetteTolM).
int StaticSegments(double radius_m) {
  if (radius_m <= kSilhouetteTolM) return kMinStaticSegments;
  const int n =
      static_cast<int>(std::ceil(std::numbers::pi / std::acos(1.0 - kSilhouetteTolM / radius_m)));
  return std::clamp(n, kMinStaticSegments, kMaxStaticSegments);
}

std::vector<Eigen::Vector2d> Circle(const Eigen::Vector2d& centre, double radius, int segments) {
  std::vector<Eigen::Vector2d> ring;
  for (const Eigen::Vector2d& c : UnitCircle(segments)) ring.push_back(centre + radius * c);
  return ring;
}

void AppendBox(const Box& box, const Rgba& rgba, TriangleSink* sink) {
  const Quad q = BoxFootprint(box);
  sink->Prism({q.begin(), q.end()}, box.base_z_m, box.base_z_m + box.size_m.z(), rgba);
}

void AppendWall(const Wall& wall, const Rgba& rgba, TriangleSink* sink) {
  const double z0 = wall.base_z_m, z1 = wall.base_z_m + wall.height_m;
  for (const auto& [a, b] : WallOutline(wall)) sink->Side(a, b, z0, z1, rgba);
  for (const Quad& q : WallFootprint(wall)) {
    const std::vector<Eigen::Vector2d> outline(q.begin(), q.end());
    sink->Cap(outline, z1, true, rgba);
    if (z0 > 0.0) sink->Cap(outline, z0, false, rgba);
  }
}

void AppendMesh(const Mesh& mesh, const Rgba& rgba, TriangleSink* sink) {
  const std::shared_ptr<const TriangleMesh> shape = LoadTriangleMesh(mesh.file);
  const std::vector<Eigen::Vector3d> v = PlacedVertices(mesh);
  for (const std::array<int, 3>& t : shape->triangles) {
    sink->Triangle(v[t[0]], v[t[1]], v[t[2]], rgba, /*two_sided=*/true);
  }
}

// A person standing on the floor: two legs from the feet to the hip (each
// leg's cut at any height as LegCentres gives it), the torso and the head.
void AppendPerson(const crowd::PersonState& p, const PersonColours& colours, TriangleSink* sink) {
  const crowd::PersonShape& s = p.shape;
  const std::array<Eigen::Vector2d, 2> feet = p.LegCentres(0.0);
  const std::array<Eigen::Vector2d, 2> hips = p.LegCentres(s.hip_height_m);
  for (int k = 0; k < 2; ++k) {
    sink->Tube({feet[k].x(), feet[k].y(), 0.0}, {hips[k].x(), hips[k].y(), s.hip_height_m},
               s.leg_radius_m, kLegSegments, RgbaOf(colours.legs), /*caps=*/false);
  }
  const Eigen::Vector2d forward(std::cos(p.heading_rad), std::sin(p.heading_rad));
  const Eigen::Vector2d left(-forward.y(), forward.x());
  std::vector<Eigen::Vector2d> torso;
  for (int k = 0; k < kTorsoSegments; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kTorsoSegments;
    torso.push_back(p.position_m + kTorsoDepthRatio * s.radius_m * std::cos(a) * forward +
                    s.radius_m * std::sin(a) * left);
  }
  const double shoulder_m = std::max(s.hip_height_m, s.height_m - kHeadHeightM);
  sink->Prism(torso, s.hip_height_m, shoulder_m, RgbaOf(colours.body));
  sink->Prism(Circle(p.position_m, std::min(kHeadRadiusM, s.radius_m), kHeadSegments), shoulder_m,
              s.height_m, RgbaOf(colours.outline), /*bottom=*/false);  // on the torso
}

void AppendBody(const BodySpec& spec, const BodyState& state, const Rgba& rgba,
                TriangleSink* sink) {
  const Eigen::Vector2d c = state.pose.translation();
  const double half = spec.shape.HalfHeight();
  switch (spec.shape.type) {
    case BodyShapeType::kBox: {
      Box box;
      box.pose = state.pose;
      box.size_m = spec.shape.box_size_m;
      box.base_z_m = state.z_m - half;
      AppendBox(box, rgba, sink);
      break;
    }
    case BodyShapeType::kCylinder:
      sink->Prism(Circle(c, spec.shape.radius_m, kMinStaticSegments), state.z_m - half,
                  state.z_m + half, rgba);
      break;
    case BodyShapeType::kSphere:
      sink->Sphere({c.x(), c.y(), state.z_m}, spec.shape.radius_m, rgba);
      break;
  }
}

// The base colour of the crowd's people: their material's, or kPersonRgb.
std::array<std::uint8_t, 3> PeopleRgb(const WorldDescription& d, const RenderScene& scene) {
  if (scene.people_material.empty() || !d.materials.contains(scene.people_material)) {
    return kPersonRgb;
  }
  const Rgba& c = d.materials.at(scene.people_material).rgba;
  const auto byte = [](double v) {
    return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
  };
  return {byte(c[0]), byte(c[1]), byte(c[2])};
}

// A robot's material: its own, or the world's of that name.
const Rgba& RobotMaterialRgba(const RobotDescription& model, const WorldDescription& d,
                              const std::string& name) {
  const auto it = model.materials.find(name);
  return it != model.materials.end() ? it->second.rgba : d.MaterialNamed(name).rgba;
}

void AppendRobot(const RobotDescription& model, const core::Pose2& pose, const WorldDescription& d,
                 TriangleSink* sink) {
  const Rgba& chassis = RobotMaterialRgba(model, d, model.material);
  for (const ChassisPrism& prism : model.ChassisPrisms()) {
    std::vector<Eigen::Vector2d> outline;
    for (const Eigen::Vector2d& p : prism.outline_m) outline.push_back(pose * p);
    sink->Prism(outline, prism.z0_m, prism.z1_m, chassis);
  }
  for (const WheelSpec* w : {&model.left_wheel, &model.right_wheel}) {
    const Eigen::Vector2d axle(0.0, 0.5 * w->width_m);
    const Eigen::Vector2d a = pose * (w->position_m + axle), b = pose * (w->position_m - axle);
    sink->Tube({a.x(), a.y(), w->radius_m}, {b.x(), b.y(), w->radius_m}, w->radius_m,
               kWheelSegments, kWheelRgba, /*caps=*/true);
  }
  for (const MarkerSpec& m : model.markers) {
    sink->Prism(Circle(pose * m.position_m, m.radius_m, kMarkerSegments), m.base_z_m,
                m.base_z_m + m.height_m, RobotMaterialRgba(model, d, m.material));
  }
}

// FNV-1a over raw bytes.
class Digest {
 public:
  void Add(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ull;
  }
  void Add(double v) { Add(&v, sizeof v); }
  void Add(const std::string& s) {
    Add(static_cast<double>(s.size()));
    Add(s.data(), s.size());
  }
  void Add(const Eigen::Vector2d& v) { Add(v.data(), sizeof(double) * 2); }
  void Add(const Eigen::Vector3d& v) { Add(v.data(), sizeof(double) * 3); }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ull;
};

}  // namespace

void TriangleLists::Clear() {
  opaque.clear();
  two_sided.clear();
  translucent.clear();
}

std::size_t TriangleLists::triangle_count() const {
  return (opaque.size() + two_sided.size() + translucent.size()) / 3;
}

double FaceShade(const Eigen::Vector3d& normal_in_world) {
  const double shade = kAmbient + kKeyStrength * std::max(0.0, normal_in_world.dot(kTowardsKey)) +
                       kFillStrength * std::max(0.0, normal_in_world.dot(kTowardsFill));
  return std::min(shade, 1.0);
}

std::array<std::uint8_t, 4> ShadedColour(const std::array<double, 4>& rgba,
                                         const Eigen::Vector3d& normal_in_world) {
  const double shade = FaceShade(normal_in_world);
  const auto byte = [](double v) {  // rounded half up (v >= 0)
    return static_cast<std::uint8_t>(255.0 * std::clamp(v, 0.0, 1.0) + 0.5);
  };
  return {byte(rgba[0] * shade), byte(rgba[1] * shade), byte(rgba[2] * shade), byte(rgba[3])};
}

void AppendStaticScene(const WorldDescription& d, TriangleLists* out) {
  TriangleSink sink(out);
  const auto rgba = [&](const std::string& material) { return d.MaterialNamed(material).rgba; };
  const Eigen::Vector2d lo = d.floor.min_m, hi = d.floor.max_m;
  sink.Cap({lo, {hi.x(), lo.y()}, hi, {lo.x(), hi.y()}}, 0.0, true, rgba(d.floor.material));
  for (const Wall& w : d.walls) AppendWall(w, rgba(w.material), &sink);
  for (const Box& b : d.boxes) AppendBox(b, rgba(b.material), &sink);
  for (const Cylinder& c : d.cylinders) {
    sink.Prism(Circle(c.position_m, c.radius_m, StaticSegments(c.radius_m)), c.base_z_m,
               c.base_z_m + c.height_m, rgba(c.material));
  }
  for (const Mesh& m : d.meshes) AppendMesh(m, rgba(m.material), &sink);
}

std::uint64_t StaticSceneDigest(const WorldDescription& d) {
  Digest h;
  for (const auto& [name, m] : d.materials) {
    h.Add(name);
    h.Add(m.rgba.data(), sizeof m.rgba);
  }
  h.Add(d.floor.min_m);
  h.Add(d.floor.max_m);
  h.Add(d.floor.material);
  for (const Wall& w : d.walls) {
    for (const Eigen::Vector2d& p : w.points_m) h.Add(p);
    h.Add(w.closed ? 1.0 : 0.0);
    for (const double v : {w.thickness_m, w.height_m, w.base_z_m}) h.Add(v);
    h.Add(w.material);
  }
  for (const Box& b : d.boxes) {
    for (const double v : {b.pose.x_m, b.pose.y_m, b.pose.theta_rad, b.base_z_m}) h.Add(v);
    h.Add(b.size_m);
    h.Add(b.material);
  }
  for (const Cylinder& c : d.cylinders) {
    h.Add(c.position_m);
    for (const double v : {c.radius_m, c.height_m, c.base_z_m}) h.Add(v);
    h.Add(c.material);
  }
  for (const Mesh& m : d.meshes) {
    h.Add(m.file);
    h.Add(m.position_m);
    h.Add(m.yaw_rad);
    h.Add(m.scale);
    h.Add(m.material);
  }
  // Counts separate the lists (a wall's points from the next wall's).
  for (const std::size_t n : {d.walls.size(), d.boxes.size(), d.cylinders.size(), d.meshes.size()})
    h.Add(static_cast<double>(n));
  return h.value();
}

void AppendDynamicScene(const World& world, const RenderScene& scene, TriangleLists* out) {
  TriangleSink sink(out);
  const WorldDescription& d = world.description();
  for (const Door& door : d.doors)
    AppendBox(door.AsBox(), d.MaterialNamed(door.material).rgba, &sink);
  for (int b = 0; b < world.body_count(); ++b) {
    const BodySpec& spec = world.body_spec(b);
    AppendBody(spec, world.body_state(b), d.MaterialNamed(spec.material).rgba, &sink);
  }
  if (const crowd::Crowd* crowd = world.crowd()) {
    const PersonColours colours = PersonColours::From(PeopleRgb(d, scene));
    for (const crowd::PersonState& p : crowd->people()) {
      if (p.present) AppendPerson(p, colours, &sink);
    }
  }
  for (int r = 0; r < world.robot_count(); ++r) {
    if (r == scene.hide_robot) continue;
    AppendRobot(world.robot_model(r), world.robot_state(r).pose, d, &sink);
  }
}

}  // namespace pavilion::sim
