#include "sim/robot/urdf_robot.h"

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <numbers>
#include <set>
#include <sstream>

#include "core/geometry/polygon.h"
#include "sim/world/triangle_mesh.h"

namespace pavilion::sim {
namespace {

namespace fs = std::filesystem;

// Geometric consistency tolerance: wheels symmetric, axles and casters on the
// floor, wheel collision centred on its joint (m).
constexpr double kPlacementToleranceM = 1e-3;
// How far a wheel axis may deviate from the base's +y axis (unit-vector components).
constexpr double kAxisTolerance = 1e-6;
// Vertices of the polygon circumscribing a cylinder or sphere in the footprint.
constexpr int kCircleVertices = 32;
// Collision shapes' tops and bottoms closer than this are one slab boundary of
// the chassis (m); also the corner tolerance when merging equal slabs.
constexpr double kSameHeightM = 1e-9;

// Where elements of the XML text are, and what urdfdom hides (a joint's
// missing <axis> is replaced by (1, 0, 0)).
struct XmlIndex {
  std::map<std::string, int> link_line;
  std::map<std::string, int> joint_line;
  std::set<std::string> joints_with_axis;
};

class Context {
 public:
  explicit Context(std::string path) : path_(std::move(path)) {}
  const std::string& path() const { return path_; }
  XmlIndex& index() { return index_; }
  const XmlIndex& index() const { return index_; }

  // "path:line: link 'name': "
  std::string AtLink(const std::string& name) const { return At(index_.link_line, "link", name); }
  std::string AtJoint(const std::string& name) const {
    return At(index_.joint_line, "joint", name);
  }
  std::string AtFile() const { return path_ + ": "; }

  [[noreturn]] void Fail(const std::string& message, UrdfError::Name name = UrdfError::Name::kNone,
                         int caster = -1) const {
    throw UrdfError(message, name, caster);
  }

 private:
  std::string At(const std::map<std::string, int>& lines, const char* kind,
                 const std::string& name) const {
    // Appends piece by piece: GCC 12 warns falsely (-Wrestrict) on chained `+`.
    std::string out = path_;
    if (auto it = lines.find(name); it != lines.end()) {
      out.append(":").append(std::to_string(it->second));
    }
    out.append(": ").append(kind).append(" '").append(name).append("': ");
    return out;
  }

  std::string path_;
  XmlIndex index_;
};

std::string Fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string Fmt(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

// Reads the XML once with tinyxml for line numbers and the checks urdfdom cannot
// make (absent <axis>; joints naming links that do not exist, with their line).
std::string ReadAndIndex(Context* ctx) {
  std::ifstream in(ctx->path(), std::ios::binary);
  if (!in) ctx->Fail(ctx->AtFile() + "cannot open file");
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();

  TiXmlDocument doc;
  doc.Parse(xml.c_str());
  if (doc.Error()) {
    ctx->Fail(ctx->path() + ":" + std::to_string(std::max(doc.ErrorRow(), 1)) +
              ": malformed XML: " + doc.ErrorDesc());
  }
  const TiXmlElement* robot = doc.RootElement();
  if (robot == nullptr || std::string(robot->Value()) != "robot") {
    ctx->Fail(ctx->AtFile() + "the root element must be <robot>");
  }
  XmlIndex& index = ctx->index();
  for (const TiXmlElement* e = robot->FirstChildElement("link"); e != nullptr;
       e = e->NextSiblingElement("link")) {
    if (const char* name = e->Attribute("name")) index.link_line[name] = e->Row();
  }
  for (const TiXmlElement* e = robot->FirstChildElement("joint"); e != nullptr;
       e = e->NextSiblingElement("joint")) {
    const char* name = e->Attribute("name");
    if (name == nullptr) continue;  // urdfdom reports it
    index.joint_line[name] = e->Row();
    if (e->FirstChildElement("axis") != nullptr) index.joints_with_axis.insert(name);
    for (const char* role : {"parent", "child"}) {
      const TiXmlElement* ref = e->FirstChildElement(role);
      const char* link = ref != nullptr ? ref->Attribute("link") : nullptr;
      if (link == nullptr) {
        ctx->Fail(ctx->AtJoint(name) + "has no <" + role + " link=\"...\"/>");
      }
      if (!index.link_line.contains(link)) {
        ctx->Fail(ctx->AtJoint(name) + role + " link '" + link + "' does not exist");
      }
    }
  }
  return xml;
}

// Collects urdfdom's error messages instead of printing them.
class CapturingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors.push_back(text);
  }
  std::vector<std::string> errors;
};

urdf::ModelInterfaceSharedPtr ParseModel(const Context& ctx, const std::string& xml) {
  // console_bridge's handler is process-wide: one parse at a time.
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  CapturingHandler handler;
  console_bridge::OutputHandler* previous = console_bridge::getOutputHandler();
  console_bridge::useOutputHandler(&handler);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    handler.errors.push_back(e.what());
  }
  console_bridge::useOutputHandler(previous);
  if (!model) {
    ctx.Fail(
        ctx.AtFile() + "not a valid URDF: " +
        (handler.errors.empty() ? std::string("urdfdom rejected it") : handler.errors.front()));
  }
  return model;
}

Eigen::Isometry3d ToIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return t;
}

MountSpec ToMount(const std::string& link, const Eigen::Isometry3d& base_from_link) {
  const Eigen::Matrix3d& r = base_from_link.linear();
  MountSpec m;
  m.link = link;
  m.z_m = base_from_link.translation().z();
  // URDF rpy: R = Rz(yaw)·Ry(pitch)·Rx(roll).
  m.pitch_rad = std::atan2(-r(2, 0), std::hypot(r(2, 1), r(2, 2)));
  double yaw = 0.0;
  if (std::hypot(r(0, 0), r(1, 0)) > 1e-9) {
    yaw = std::atan2(r(1, 0), r(0, 0));
    m.roll_rad = std::atan2(r(2, 1), r(2, 2));
  } else {  // pointing straight up or down: only yaw ± roll is defined; take roll = 0
    yaw = std::atan2(-r(0, 1), r(1, 1));
  }
  m.pose = core::Pose2{base_from_link.translation().x(), base_from_link.translation().y(), yaw};
  return m;
}

std::string ResolveMesh(const Context& ctx, const std::string& link, const std::string& filename) {
  std::string name = filename;
  if (name.starts_with("file://")) name = name.substr(7);
  if (name.find("://") != std::string::npos) {
    ctx.Fail(ctx.AtLink(link) + "mesh '" + filename +
             "': only plain paths (relative to the URDF's folder) are supported");
  }
  fs::path p(name);
  if (p.is_relative()) p = fs::path(ctx.path()).parent_path() / p;
  p = p.lexically_normal();
  if (!fs::is_regular_file(p)) {
    ctx.Fail(ctx.AtLink(link) + "mesh file not found: " + p.string());
  }
  return p.string();
}

// A collision element as a shape in the base frame; validates its sizes.
CollisionShape ToShape(const Context& ctx, const std::string& link,
                       const Eigen::Isometry3d& base_from_link, const urdf::Collision& collision) {
  if (!collision.geometry) ctx.Fail(ctx.AtLink(link) + "<collision> has no geometry");
  CollisionShape s;
  s.link = link;
  s.base_from_shape = base_from_link * ToIsometry(collision.origin);
  const urdf::Geometry& g = *collision.geometry;
  auto positive = [&](double v, const std::string& what) {
    if (!(v > 0.0) || !std::isfinite(v)) {
      ctx.Fail(ctx.AtLink(link) + what + " must be > 0, got " + Fmt(v));
    }
  };
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& box = static_cast<const urdf::Box&>(g);
      s.type = CollisionShape::Type::kBox;
      s.box_size_m = {box.dim.x, box.dim.y, box.dim.z};
      for (int i = 0; i < 3; ++i) positive(s.box_size_m[i], "box size");
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& cyl = static_cast<const urdf::Cylinder&>(g);
      s.type = CollisionShape::Type::kCylinder;
      s.radius_m = cyl.radius;
      s.length_m = cyl.length;
      positive(s.radius_m, "cylinder radius");
      positive(s.length_m, "cylinder length");
      break;
    }
    case urdf::Geometry::SPHERE: {
      s.type = CollisionShape::Type::kSphere;
      s.radius_m = static_cast<const urdf::Sphere&>(g).radius;
      positive(s.radius_m, "sphere radius");
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& mesh = static_cast<const urdf::Mesh&>(g);
      s.type = CollisionShape::Type::kMesh;
      s.mesh_file = ResolveMesh(ctx, link, mesh.filename);
      s.mesh_scale = {mesh.scale.x, mesh.scale.y, mesh.scale.z};
      for (int i = 0; i < 3; ++i) positive(s.mesh_scale[i], "mesh scale");
      try {
        LoadTriangleMesh(s.mesh_file);
      } catch (const std::exception& e) {
        ctx.Fail(ctx.AtLink(link) + e.what());
      }
      break;
    }
  }
  return s;
}

// Points whose convex hull contains the shape (circles circumscribed), base frame.
void AppendHullPoints(const CollisionShape& s, std::vector<Eigen::Vector3d>* out) {
  const Eigen::Isometry3d& t = s.base_from_shape;
  auto circle = [&](const Eigen::Vector3d& centre, const Eigen::Vector3d& u,
                    const Eigen::Vector3d& v, double r) {
    const double rc = r / std::cos(std::numbers::pi / kCircleVertices);
    for (int i = 0; i < kCircleVertices; ++i) {
      const double a = 2.0 * std::numbers::pi * i / kCircleVertices;
      out->push_back(centre + rc * (std::cos(a) * u + std::sin(a) * v));
    }
  };
  switch (s.type) {
    case CollisionShape::Type::kBox:
      for (int i = 0; i < 8; ++i) {
        const Eigen::Vector3d corner(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
        out->push_back(t * corner.cwiseProduct(s.box_size_m));
      }
      break;
    case CollisionShape::Type::kCylinder: {
      const Eigen::Vector3d u = t.linear().col(0), v = t.linear().col(1), w = t.linear().col(2);
      for (double end : {-0.5, 0.5}) {
        circle(t.translation() + end * s.length_m * w, u, v, s.radius_m);
      }
      break;
    }
    case CollisionShape::Type::kSphere: {
      const Eigen::Vector3d c = t.translation();
      circle(c, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), s.radius_m);
      out->push_back(c - s.radius_m * Eigen::Vector3d::UnitZ());
      out->push_back(c + s.radius_m * Eigen::Vector3d::UnitZ());
      break;
    }
    case CollisionShape::Type::kMesh:
      for (const Eigen::Vector3d& p : LoadTriangleMesh(s.mesh_file)->vertices) {
        out->push_back(t * p.cwiseProduct(s.mesh_scale));
      }
      break;
  }
}

// A link reached from base_link through fixed joints, with its pose.
struct RigidLink {
  urdf::LinkConstSharedPtr link;
  Eigen::Isometry3d base_from_link;
};

struct WheelLink {
  urdf::JointConstSharedPtr joint;
  urdf::LinkConstSharedPtr link;
  Eigen::Isometry3d base_from_link;
};

double CheckedMass(const Context& ctx, const urdf::Link& link) {
  if (!link.inertial) return 0.0;
  const urdf::Inertial& in = *link.inertial;
  if (!(in.mass >= 0.0) || !std::isfinite(in.mass)) {
    ctx.Fail(ctx.AtLink(link.name) + "mass must be a finite number >= 0, got " + Fmt(in.mass));
  }
  for (double d : {in.ixx, in.iyy, in.izz}) {
    if (!(d >= 0.0) || !std::isfinite(d)) {
      ctx.Fail(ctx.AtLink(link.name) + "inertia ixx, iyy, izz must be finite and >= 0");
    }
  }
  return in.mass;
}

WheelSpec ReadWheel(const Context& ctx, const WheelLink& w, const char* side) {
  const std::string& jname = w.joint->name;
  if (w.joint->type != urdf::Joint::CONTINUOUS) {
    ctx.Fail(ctx.AtJoint(jname) + "the " + side + " wheel joint must be of type continuous");
  }
  if (!ctx.index().joints_with_axis.contains(jname)) {
    ctx.Fail(ctx.AtJoint(jname) +
             "continuous joint has no <axis>; a wheel joint needs <axis xyz=\"0 1 0\"/>");
  }
  const Eigen::Vector3d axis_in_base =
      w.base_from_link.linear() *
      Eigen::Vector3d(w.joint->axis.x, w.joint->axis.y, w.joint->axis.z).normalized();
  if ((axis_in_base - Eigen::Vector3d::UnitY()).norm() > kAxisTolerance) {
    ctx.Fail(ctx.AtJoint(jname) + "axis must be along +y of the base link (so that a positive " +
             "wheel speed drives forward), but it is " + Fmt(axis_in_base) + " there");
  }
  const urdf::Link& link = *w.link;
  if (!link.child_joints.empty()) {
    ctx.Fail(ctx.AtLink(link.name) + "nothing may be attached to a wheel (joint '" +
             link.child_joints.front()->name + "')");
  }
  if (link.collision_array.empty() || !link.collision_array.front()) {
    ctx.Fail(ctx.AtLink(link.name) + "wheel has no collision geometry (a cylinder or sphere)");
  }
  if (link.collision_array.size() > 1) {
    ctx.Fail(ctx.AtLink(link.name) + "a wheel needs exactly one <collision>");
  }
  const CollisionShape shape = ToShape(ctx, link.name, w.base_from_link, *link.collision_array[0]);
  WheelSpec spec;
  spec.joint = jname;
  if (shape.type == CollisionShape::Type::kCylinder) {
    const Eigen::Vector3d cyl_axis = shape.base_from_shape.linear().col(2);
    if (std::abs(std::abs(cyl_axis.y()) - 1.0) > kAxisTolerance) {
      ctx.Fail(ctx.AtLink(link.name) +
               "the wheel cylinder's axis (its z) must lie along the wheel axis (y); give its "
               "<collision> <origin rpy=\"1.5708 0 0\"/>");
    }
    spec.radius_m = shape.radius_m;
    spec.width_m = shape.length_m;
  } else if (shape.type == CollisionShape::Type::kSphere) {
    spec.radius_m = shape.radius_m;
    spec.width_m = 2.0 * shape.radius_m;
  } else {
    ctx.Fail(ctx.AtLink(link.name) + "wheel collision must be a cylinder or a sphere");
  }
  const Eigen::Vector3d axle = w.base_from_link.translation();
  if ((shape.base_from_shape.translation() - axle).norm() > kPlacementToleranceM) {
    ctx.Fail(ctx.AtLink(link.name) + "wheel collision must be centred on joint '" + jname + "'");
  }
  if (std::abs(axle.z() - spec.radius_m) > kPlacementToleranceM) {
    ctx.Fail(ctx.AtJoint(jname) + "axle height " + Fmt(axle.z()) + " m differs from the wheel " +
             "radius " + Fmt(spec.radius_m) + " m: the base link's origin must be on the floor");
  }
  spec.mass_kg = CheckedMass(ctx, link);
  if (!(spec.mass_kg > 0.0)) {
    ctx.Fail(ctx.AtLink(link.name) + "wheel needs an <inertial> with mass > 0");
  }
  spec.position_m = axle.head<2>();
  return spec;
}

// Fails unless the links and joints the caller names exist (the base link
// being the root of the tree).
void CheckDriveNames(const Context& ctx, const urdf::ModelInterface& model,
                     const UrdfDriveNames& names) {
  using Name = UrdfError::Name;
  if (!model.getLink(names.base_link)) {
    ctx.Fail(ctx.AtFile() + "base link '" + names.base_link + "' does not exist", Name::kBaseLink);
  }
  if (model.getRoot()->name != names.base_link) {
    ctx.Fail(ctx.AtLink(names.base_link) +
                 "the base link must be the root of the URDF tree (the root is '" +
                 model.getRoot()->name + "')",
             Name::kBaseLink);
  }
  if (!model.getJoint(names.left_wheel_joint)) {
    ctx.Fail(ctx.AtFile() + "joint '" + names.left_wheel_joint + "' does not exist",
             Name::kLeftWheelJoint);
  }
  if (!model.getJoint(names.right_wheel_joint)) {
    ctx.Fail(ctx.AtFile() + "joint '" + names.right_wheel_joint + "' does not exist",
             Name::kRightWheelJoint);
  }
  if (names.left_wheel_joint == names.right_wheel_joint) {
    ctx.Fail(ctx.AtJoint(names.right_wheel_joint) + "is named as both the left and right wheel",
             Name::kRightWheelJoint);
  }
  if (!model.getLink(names.chassis_link)) {
    ctx.Fail(ctx.AtFile() + "chassis link '" + names.chassis_link + "' does not exist",
             Name::kChassisLink);
  }
  for (std::size_t i = 0; i < names.caster_links.size(); ++i) {
    if (!model.getLink(names.caster_links[i])) {
      ctx.Fail(ctx.AtFile() + "caster link '" + names.caster_links[i] + "' does not exist",
               Name::kCasterLink, static_cast<int>(i));
    }
  }
}

// Walks the tree from the root: fixed joints chain the rigid assembly (its
// links sorted by name, a deterministic order whatever the XML order), the
// wheel joints end it; any other moving joint fails.
void WalkRigidAssembly(const Context& ctx, const urdf::ModelInterface& model,
                       const UrdfDriveNames& names, std::vector<RigidLink>* rigid_out,
                       std::map<std::string, WheelLink>* wheels_out) {
  std::vector<RigidLink>& rigid = *rigid_out;
  std::map<std::string, WheelLink>& wheels = *wheels_out;  // by joint name
  std::vector<RigidLink> stack{{model.getRoot(), Eigen::Isometry3d::Identity()}};
  while (!stack.empty()) {
    const RigidLink current = stack.back();
    stack.pop_back();
    rigid.push_back(current);
    for (const urdf::JointSharedPtr& joint : current.link->child_joints) {
      const Eigen::Isometry3d base_from_child =
          current.base_from_link * ToIsometry(joint->parent_to_joint_origin_transform);
      const urdf::LinkConstSharedPtr child = model.getLink(joint->child_link_name);
      if (joint->name == names.left_wheel_joint || joint->name == names.right_wheel_joint) {
        wheels[joint->name] = {joint, child, base_from_child};
      } else if (joint->type == urdf::Joint::FIXED) {
        stack.push_back({child, base_from_child});
      } else {
        ctx.Fail(ctx.AtJoint(joint->name) +
                 "only the two drive wheel joints may move; make this joint fixed");
      }
    }
  }
  std::sort(rigid.begin(), rigid.end(), [](const RigidLink& a, const RigidLink& b) {
    return a.link->name < b.link->name;  // deterministic order, whatever the XML order
  });
}

const RigidLink* FindRigid(const std::vector<RigidLink>& rigid, const std::string& name) {
  for (const RigidLink& r : rigid) {
    if (r.link->name == name) return &r;
  }
  return nullptr;
}

// The two drive wheels, nominally identical and symmetric about the base's x axis.
void ReadWheels(const Context& ctx, const std::map<std::string, WheelLink>& wheels,
                const UrdfDriveNames& names, RobotDescription* out) {
  RobotDescription& d = *out;
  for (const std::string& joint : {names.left_wheel_joint, names.right_wheel_joint}) {
    if (!wheels.contains(joint)) {
      ctx.Fail(ctx.AtJoint(joint) + "a wheel joint's parent must be fixed to the base link");
    }
  }
  d.left_wheel = ReadWheel(ctx, wheels.at(names.left_wheel_joint), "left");
  d.right_wheel = ReadWheel(ctx, wheels.at(names.right_wheel_joint), "right");
  const Eigen::Vector2d& l = d.left_wheel.position_m;
  const Eigen::Vector2d& r = d.right_wheel.position_m;
  if (!(l.y() > 0.0 && r.y() < 0.0)) {
    ctx.Fail(ctx.AtJoint(names.left_wheel_joint) + "the left wheel must be at y > 0 and the " +
             "right wheel ('" + names.right_wheel_joint + "') at y < 0");
  }
  if (std::abs(l.x() - r.x()) > kPlacementToleranceM ||
      std::abs(l.y() + r.y()) > kPlacementToleranceM) {
    ctx.Fail(ctx.AtJoint(names.left_wheel_joint) + "the wheels are not symmetric about the " +
             "base link's x axis (left at " + Fmt(l.x()) + ", " + Fmt(l.y()) + "; right at " +
             Fmt(r.x()) + ", " + Fmt(r.y()) +
             "): the base link's origin must be midway between the wheels");
  }
  if (std::abs(d.left_wheel.radius_m - d.right_wheel.radius_m) > 1e-9 ||
      std::abs(d.left_wheel.width_m - d.right_wheel.width_m) > 1e-9) {
    ctx.Fail(ctx.AtJoint(names.right_wheel_joint) +
             "the nominal wheels must be identical (radius " + Fmt(d.left_wheel.radius_m) + " vs " +
             Fmt(d.right_wheel.radius_m) +
             " m); give a built-in difference as a systematic error in robot.yaml");
  }
}

// The chassis link: fixed to the base link, with mass.
void CheckChassis(const Context& ctx, const std::vector<RigidLink>& rigid,
                  const UrdfDriveNames& names) {
  using Name = UrdfError::Name;
  const RigidLink* chassis = FindRigid(rigid, names.chassis_link);
  if (chassis == nullptr) {
    ctx.Fail(ctx.AtLink(names.chassis_link) + "the chassis must be fixed to the base link",
             Name::kChassisLink);
  }
  if (!chassis->link->inertial || !(CheckedMass(ctx, *chassis->link) > 0.0)) {
    ctx.Fail(ctx.AtLink(names.chassis_link) +
             "the chassis needs an <inertial> with mass > 0, got " +
             (chassis->link->inertial ? Fmt(chassis->link->inertial->mass) + " kg" : "none"));
  }
}

// The casters: spheres on the floor, fixed to the base link. Returns their names.
std::set<std::string> ReadCasters(const Context& ctx, const std::vector<RigidLink>& rigid,
                                  const UrdfDriveNames& names, RobotDescription* out) {
  using Name = UrdfError::Name;
  RobotDescription& d = *out;
  std::set<std::string> caster_names;
  for (std::size_t i = 0; i < names.caster_links.size(); ++i) {
    const std::string& name = names.caster_links[i];
    const RigidLink* caster = FindRigid(rigid, name);
    if (caster == nullptr) {
      ctx.Fail(ctx.AtLink(name) + "a caster must be fixed to the base link", Name::kCasterLink,
               static_cast<int>(i));
    }
    if (!caster_names.insert(name).second) {
      ctx.Fail(ctx.AtLink(name) + "is named as a caster twice", Name::kCasterLink,
               static_cast<int>(i));
    }
    const auto& collisions = caster->link->collision_array;
    if (collisions.size() != 1 || !collisions[0]->geometry ||
        collisions[0]->geometry->type != urdf::Geometry::SPHERE) {
      ctx.Fail(ctx.AtLink(name) + "a caster needs exactly one <collision>, a sphere");
    }
    const CollisionShape s = ToShape(ctx, name, caster->base_from_link, *collisions[0]);
    const Eigen::Vector3d c = s.base_from_shape.translation();
    if (std::abs(c.z() - s.radius_m) > kPlacementToleranceM) {
      ctx.Fail(ctx.AtLink(name) + "the caster sphere must touch the floor (centre at z = " +
               Fmt(c.z()) + " m, radius " + Fmt(s.radius_m) + " m)");
    }
    d.casters.push_back(CasterSpec{name, c.head<2>(), s.radius_m});
  }

  return caster_names;
}

// Mass, centre of mass and inertia of the rigid assembly.
void ReadMassProperties(const Context& ctx, const std::vector<RigidLink>& rigid,
                        RobotDescription* out) {
  RobotDescription& d = *out;
  double mass = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (const RigidLink& rl : rigid) {
    const double m = CheckedMass(ctx, *rl.link);
    if (m > 0.0) {
      moment += m * (rl.base_from_link * ToIsometry(rl.link->inertial->origin)).translation();
      mass += m;
    }
  }
  d.chassis_mass_kg = mass;
  d.chassis_com_m = moment / mass;
  d.chassis_inertia_kgm2.setZero();
  for (const RigidLink& rl : rigid) {
    if (!rl.link->inertial || !(rl.link->inertial->mass > 0.0)) continue;
    const urdf::Inertial& in = *rl.link->inertial;
    const Eigen::Isometry3d base_from_inertial = rl.base_from_link * ToIsometry(in.origin);
    Eigen::Matrix3d local;
    local << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    const Eigen::Matrix3d& rot = base_from_inertial.linear();
    const Eigen::Vector3d offset = base_from_inertial.translation() - d.chassis_com_m;
    d.chassis_inertia_kgm2 += rot * local * rot.transpose() +
                              in.mass * (offset.squaredNorm() * Eigen::Matrix3d::Identity() -
                                         offset * offset.transpose());
  }
}

// The chassis as slabs stacked bottom to top: a slab boundary wherever a shape
// (its hull points, `shape_points`) begins or ends; each slab the hull seen from
// above of the shapes reaching into it (exact for upright prisms, boxes and
// cylinders; a conservative prism for anything else), neighbours with the same
// outline merged. Heights below the floor count as the floor.
std::vector<ChassisPrism> StackChassisPrisms(
    const std::vector<std::vector<Eigen::Vector3d>>& shape_points) {
  struct Range {
    double z0, z1;
  };
  std::vector<Range> ranges;
  std::vector<double> heights;
  for (const std::vector<Eigen::Vector3d>& points : shape_points) {
    Range r{points.front().z(), points.front().z()};
    for (const Eigen::Vector3d& p : points) {
      r.z0 = std::min(r.z0, p.z());
      r.z1 = std::max(r.z1, p.z());
    }
    r.z0 = std::max(0.0, r.z0);
    ranges.push_back(r);
    heights.push_back(r.z0);
    heights.push_back(r.z1);
  }
  std::sort(heights.begin(), heights.end());
  heights.erase(std::unique(heights.begin(), heights.end(),
                            [](double a, double b) { return b - a <= kSameHeightM; }),
                heights.end());
  std::vector<ChassisPrism> stack;
  for (std::size_t i = 0; i + 1 < heights.size(); ++i) {
    const double z0 = heights[i], z1 = heights[i + 1];
    std::vector<Eigen::Vector2d> planar;
    for (std::size_t s = 0; s < shape_points.size(); ++s) {
      if (ranges[s].z0 >= z1 - kSameHeightM || ranges[s].z1 <= z0 + kSameHeightM) continue;
      for (const Eigen::Vector3d& p : shape_points[s]) planar.push_back(p.head<2>());
    }
    std::vector<Eigen::Vector2d> outline = core::ConvexHull(std::move(planar));
    if (outline.size() < 3) continue;  // a gap between shapes, or no area
    if (!stack.empty() && std::abs(stack.back().z1_m - z0) <= kSameHeightM &&
        stack.back().outline_m.size() == outline.size() &&
        std::equal(outline.begin(), outline.end(), stack.back().outline_m.begin(),
                   [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
                     return (a - b).norm() <= kSameHeightM;
                   })) {
      stack.back().z1_m = z1;
      continue;
    }
    stack.push_back({std::move(outline), z0, z1});
  }
  return stack;
}

// Mounts and collision shapes of the rigid assembly (casters apart), and the
// footprint, height range and slabs of the chassis they make.
void ReadChassisShape(const Context& ctx, const std::vector<RigidLink>& rigid,
                      const std::set<std::string>& caster_names, const UrdfDriveNames& names,
                      RobotDescription* out) {
  RobotDescription& d = *out;
  std::vector<std::vector<Eigen::Vector3d>> shape_points;
  for (const RigidLink& rl : rigid) {
    d.mounts.push_back(ToMount(rl.link->name, rl.base_from_link));
    if (caster_names.contains(rl.link->name)) continue;
    for (const urdf::CollisionSharedPtr& c : rl.link->collision_array) {
      if (!c) continue;
      d.chassis_shapes.push_back(ToShape(ctx, rl.link->name, rl.base_from_link, *c));
      shape_points.emplace_back();
      AppendHullPoints(d.chassis_shapes.back(), &shape_points.back());
      for (const Eigen::Vector3d& p : shape_points.back()) {
        if (p.z() < -kPlacementToleranceM) {
          ctx.Fail(ctx.AtLink(rl.link->name) +
                   "collision geometry reaches below the floor (z = " + Fmt(p.z()) + " m)");
        }
      }
    }
  }
  if (d.chassis_shapes.empty()) {
    ctx.Fail(ctx.AtLink(names.chassis_link) +
             "the chassis has no collision geometry (nor any link fixed to it)");
  }
  double z_min = shape_points.front().front().z(), z_max = z_min;
  std::vector<Eigen::Vector2d> planar;
  for (const std::vector<Eigen::Vector3d>& points : shape_points) {
    for (const Eigen::Vector3d& p : points) {
      z_min = std::min(z_min, p.z());
      z_max = std::max(z_max, p.z());
      planar.push_back(p.head<2>());
    }
  }
  d.footprint_m = core::ConvexHull(planar);
  if (d.footprint_m.size() < 3) {
    ctx.Fail(ctx.AtLink(names.chassis_link) + "the chassis' collision geometry has no area seen " +
             "from above");
  }
  d.chassis_base_z_m = std::max(0.0, z_min);
  d.chassis_height_m = z_max - d.chassis_base_z_m;
  d.chassis_prisms = StackChassisPrisms(shape_points);
}

}  // namespace

RobotDescription LoadUrdfRobot(const std::string& urdf_path, const UrdfDriveNames& names) {
  Context ctx(urdf_path);
  const std::string xml = ReadAndIndex(&ctx);
  const urdf::ModelInterfaceSharedPtr model = ParseModel(ctx, xml);
  CheckDriveNames(ctx, *model, names);
  std::vector<RigidLink> rigid;
  std::map<std::string, WheelLink> wheels;  // by joint name
  WalkRigidAssembly(ctx, *model, names, &rigid, &wheels);
  RobotDescription d;
  d.urdf_file = urdf_path;
  d.model = model->getName();
  ReadWheels(ctx, wheels, names, &d);
  CheckChassis(ctx, rigid, names);
  const std::set<std::string> caster_names = ReadCasters(ctx, rigid, names, &d);
  ReadMassProperties(ctx, rigid, &d);
  ReadChassisShape(ctx, rigid, caster_names, names, &d);
  return d;
}

}  // namespace pavilion::sim
