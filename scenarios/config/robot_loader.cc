#include "scenarios/config/robot_loader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>
#include <sstream>

#include "core/geometry/polygon.h"
#include "scenarios/config/options_reader.h"
#include "scenarios/config/world_loader.h"
#include "sim/robot/urdf_robot.h"

namespace pavilion::scenarios {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
// Bounds that catch unit mistakes (metres, radians per second, newton metres).
constexpr double kMaxRobotSizeM = 10.0;
constexpr double kMaxTorqueNm = 1e4;
constexpr double kMaxWheelSpeedRadps = 1e3;
constexpr double kMaxWheelAccelRadps2 = 1e5;
// Calibrated odometry may differ from the URDF's nominal values, but not by this factor.
constexpr double kMaxCalibrationFactor = 2.0;
// A level scanner mount: roll and pitch below this (rad).
constexpr double kLevelToleranceRad = 1e-6;
constexpr std::size_t kMaxBumperZones = 32;  // core::BumperReading's bit mask

bool IsName(const std::string& s) {
  if (s.empty()) return false;
  for (const char c : s) {
    if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_')) return false;
  }
  return true;
}

std::string Fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// A name unique among `used`, made of [a-z0-9_].
std::string UniqueName(YamlDocument* doc, MapReader& r, const std::string& key,
                       std::set<std::string>* used) {
  auto name = r.RequiredString(key);
  if (!name) return "";
  if (!IsName(*name)) {
    doc->Error(r.Child(key), r.PathOf(key), "must be lower-case letters, digits and '_'");
  } else if (!used->insert(*name).second) {
    doc->Error(r.Child(key), r.PathOf(key), "'" + *name + "' is used twice");
  }
  return *name;
}

// Names the robot file gives to URDF elements, and where.
struct UrdfNameNodes {
  sim::UrdfDriveNames names;
  YAML::Node urdf, base_link, left_joint, right_joint, chassis_link;
  std::vector<YAML::Node> casters;
  bool complete = true;  // every required name was read
};

class RobotReader {
 public:
  explicit RobotReader(YamlDocument* doc) : doc_(doc) {}

  sim::RobotConfig Read() {
    sim::RobotConfig c;
    c.source_file = doc_->path();
    if (!doc_->ok()) return c;  // unreadable or malformed: nothing to walk
    MapReader top(doc_, doc_->root(), "");
    if (!top.valid()) return c;
    if (auto kind = top.RequiredString("kind"); kind && *kind != "robot") {
      doc_->Error(top.Child("kind"), "kind", "expected 'robot', got '" + *kind + "'");
    }
    std::string name;
    if (auto n = top.RequiredString("name")) {
      if (!IsName(*n)) {
        doc_->Error(top.Child("name"), "name", "must be lower-case letters, digits and '_'");
      }
      name = *n;
    }
    top.String("description", "");

    // The URDF first: the sensors below name its links.
    UrdfNameNodes names = ReadNames(top);
    MapReader drive(doc_, top.Child("drive", true), "drive");
    MapReader chassis(doc_, top.Child("chassis", true), "chassis");
    ReadDriveNames(drive, chassis, &names);
    if (auto urdf = LoadUrdf(names)) {
      c.description = std::move(*urdf);
      have_urdf_ = true;
    }
    c.description.model = name;
    ReadDrive(drive, &c.description);
    drive.Finish();
    if (YAML::Node mats = top.Child("materials", true); mats.IsDefined()) {
      ReadMaterialMap(doc_, mats, "materials", &c.description.materials);
    }
    ReadChassis(chassis, &c.description);
    chassis.Finish();
    c.encoders = ReadEncoders(top);
    c.systematic = ReadSystematic(top);
    c.odometry = ReadOdometry(top, c.description);
    ReadLasers(top, c);
    ReadBumpers(top, &c.bumpers);
    ReadMarkers(top, &c.description);
    ReadSuspension(top, &c.description);
    ReadCameras(top, c);
    top.Finish();
    return c;
  }

 private:
  UrdfNameNodes ReadNames(MapReader& top) {
    UrdfNameNodes n;
    n.urdf = top.Child("urdf", true);
    if (auto base = top.String("base_link", n.names.base_link); !base.empty()) {
      n.names.base_link = base;
      n.base_link = top.Child("base_link");
    }
    YAML::Node casters = top.Child("casters");
    if (casters.IsDefined() && !casters.IsNull()) {
      if (!casters.IsSequence()) {
        doc_->Error(casters, "casters", "expected a list of URDF link names");
        n.complete = false;
      } else {
        for (std::size_t i = 0; i < casters.size(); ++i) {
          if (!casters[i].IsScalar() || casters[i].Scalar().empty()) {
            doc_->Error(casters[i], IndexPath("casters", i), "expected a URDF link name");
            n.complete = false;
            continue;
          }
          n.names.caster_links.push_back(casters[i].Scalar());
          n.casters.push_back(casters[i]);
        }
      }
    }
    return n;
  }

  void ReadDriveNames(MapReader& drive, MapReader& chassis, UrdfNameNodes* n) {
    auto left = drive.RequiredString("left_joint");
    auto right = drive.RequiredString("right_joint");
    auto link = chassis.RequiredString("link");
    if (left) n->names.left_wheel_joint = *left;
    if (right) n->names.right_wheel_joint = *right;
    if (link) n->names.chassis_link = *link;
    n->left_joint = drive.Child("left_joint");
    n->right_joint = drive.Child("right_joint");
    n->chassis_link = chassis.Child("link");
    n->complete = n->complete && left && right && link && drive.valid() && chassis.valid();
  }

  // The URDF named by `urdf`, or nullopt after reporting why not.
  std::optional<sim::RobotDescription> LoadUrdf(const UrdfNameNodes& n) {
    if (!n.urdf.IsDefined()) return std::nullopt;
    if (!n.urdf.IsScalar() || n.urdf.Scalar().empty()) {
      doc_->Error(n.urdf, "urdf", "expected the path of a URDF file");
      return std::nullopt;
    }
    namespace fs = std::filesystem;
    fs::path p(n.urdf.Scalar());
    if (p.is_relative()) p = fs::path(doc_->path()).parent_path() / p;
    const std::string path = p.lexically_normal().string();
    if (!fs::is_regular_file(p)) {
      doc_->Error(n.urdf, "urdf", "URDF file not found: " + path);
      return std::nullopt;
    }
    if (!n.complete) return std::nullopt;  // names missing: their errors are reported
    try {
      return sim::LoadUrdfRobot(path, n.names);
    } catch (const sim::UrdfError& e) {
      using Name = sim::UrdfError::Name;
      switch (e.unresolved_name()) {
        case Name::kBaseLink:
          doc_->Error(n.base_link.IsDefined() ? n.base_link : n.urdf,
                      n.base_link.IsDefined() ? "base_link" : "urdf", e.what());
          break;
        case Name::kLeftWheelJoint:
          doc_->Error(n.left_joint, "drive.left_joint", e.what());
          break;
        case Name::kRightWheelJoint:
          doc_->Error(n.right_joint, "drive.right_joint", e.what());
          break;
        case Name::kChassisLink:
          doc_->Error(n.chassis_link, "chassis.link", e.what());
          break;
        case Name::kCasterLink:
          doc_->Error(n.casters.at(e.caster_index()), IndexPath("casters", e.caster_index()),
                      e.what());
          break;
        case Name::kNone:
          doc_->Error(n.urdf, "urdf", e.what());
          break;
      }
    } catch (const std::exception& e) {
      doc_->Error(n.urdf, "urdf", e.what());
    }
    return std::nullopt;
  }

  void ReadDrive(MapReader& r, sim::RobotDescription* d) {
    d->max_wheel_torque_nm =
        r.RequiredNumber("max_wheel_torque_nm", 1e-3, kMaxTorqueNm).value_or(1.0);
    d->max_wheel_speed_radps =
        r.RequiredNumber("max_wheel_speed_radps", 1e-3, kMaxWheelSpeedRadps).value_or(1.0);
    d->max_wheel_accel_radps2 =
        r.RequiredNumber("max_wheel_accel_radps2", 1e-3, kMaxWheelAccelRadps2).value_or(1.0);
  }

  // True when `name` is a material of the robot file; reports it otherwise.
  bool KnownMaterial(MapReader& r, const std::string& key, const std::string& name,
                     const sim::RobotDescription& d) {
    if (d.materials.contains(name)) return true;
    doc_->Error(r.Child(key), r.PathOf(key),
                "unknown material '" + name + "' (define it under `materials`)");
    return false;
  }

  void ReadChassis(MapReader& r, sim::RobotDescription* d) {
    if (auto m = r.RequiredString("material")) {
      d->material = *m;
      KnownMaterial(r, "material", *m, *d);
    }
    YAML::Node fp = r.Child("footprint");
    if (!fp.IsDefined()) return;  // the convex hull of the URDF's collision geometry
    const std::string path = r.PathOf("footprint");
    if (!fp.IsSequence() || fp.size() < 3) {
      doc_->Error(fp, path, "expected a list of at least 3 [x, y] points");
      return;
    }
    core::Polygon2 poly;
    for (std::size_t i = 0; i < fp.size(); ++i) {
      auto v = ReadNumbers(doc_, fp[i], IndexPath(path, i), 2);
      if (!v) return;
      if (std::abs((*v)[0]) > kMaxRobotSizeM || std::abs((*v)[1]) > kMaxRobotSizeM) {
        doc_->Error(fp[i], IndexPath(path, i), "beyond ±10 m of the base link; units are metres");
        return;
      }
      poly.emplace_back((*v)[0], (*v)[1]);
    }
    if (core::SignedArea(poly) < 0.0) std::reverse(poly.begin(), poly.end());
    bool convex = core::SignedArea(poly) > 1e-6;
    for (std::size_t i = 0; convex && i < poly.size(); ++i) {
      const Eigen::Vector2d a = poly[(i + 1) % poly.size()] - poly[i];
      const Eigen::Vector2d b = poly[(i + 2) % poly.size()] - poly[(i + 1) % poly.size()];
      convex = a.x() * b.y() - a.y() * b.x() > 0.0;
    }
    if (!convex) {
      doc_->Error(fp, path, "must be a convex polygon with distinct, non-collinear corners");
      return;
    }
    if (!core::Contains(poly, Eigen::Vector2d::Zero())) {
      doc_->Error(fp, path, "must contain the base link's origin (0, 0)");
      return;
    }
    d->footprint_m = poly;
  }

  sim::EncoderOptions ReadEncoders(MapReader& top) {
    sim::EncoderOptions e;
    MapReader r(doc_, top.Child("encoders", true), "encoders");
    if (!r.valid()) return e;
    RequireKeys(r, {"ticks_per_revolution"});
    using Encoders = sim::EncoderOptions;
    ReadOptions(r, &e,
                {{"ticks_per_revolution", &Encoders::ticks_per_revolution},
                 {"rate_hz", &Encoders::rate_hz},
                 {"k_left_m", &Encoders::k_left_m},
                 {"k_right_m", &Encoders::k_right_m},
                 {"noise", &Encoders::noise}});
    r.Finish();
    return e;
  }

  sim::SystematicErrors ReadSystematic(MapReader& top) {
    sim::SystematicErrors s;
    YAML::Node node = top.Child("systematic");
    if (!node.IsDefined()) return s;
    MapReader r(doc_, node, "systematic");
    ReadOptions(r, &s,
                {{"wheel_radius_ratio", &sim::SystematicErrors::wheel_radius_ratio},
                 {"wheelbase_factor", &sim::SystematicErrors::wheelbase_factor},
                 {"mean_radius_factor", &sim::SystematicErrors::mean_radius_factor}});
    r.Finish();
    return s;
  }

  core::EncoderOdometryOptions ReadOdometry(MapReader& top, const sim::RobotDescription& d) {
    core::EncoderOdometryOptions o;
    MapReader r(doc_, top.Child("odometry", true), "odometry");
    if (!r.valid()) return o;
    RequireKeys(
        r, {"left_wheel_radius_m", "right_wheel_radius_m", "wheelbase_m", "k_left_m", "k_right_m"});
    using Odometry = core::EncoderOdometryOptions;
    const bool valid = ReadOptions(r, &o,
                                   {{"left_wheel_radius_m", &Odometry::left_wheel_radius_m},
                                    {"right_wheel_radius_m", &Odometry::right_wheel_radius_m},
                                    {"wheelbase_m", &Odometry::wheelbase_m},
                                    {"k_left_m", &Odometry::k_left_m},
                                    {"k_right_m", &Odometry::k_right_m},
                                    {"k_turn_m", &Odometry::k_turn_m}});
    // Each calibrated length against the URDF's nominal one (unit mistakes).
    auto near_nominal = [&](const std::string& key, double nominal, double value) {
      if (value > nominal * kMaxCalibrationFactor || value < nominal / kMaxCalibrationFactor) {
        doc_->Error(r.Child(key), r.PathOf(key),
                    "differs from the URDF's nominal " + Fmt(nominal) +
                        " m by more than a factor of 2 (units are metres)");
      }
    };
    if (valid && have_urdf_) {
      near_nominal("left_wheel_radius_m", d.left_wheel.radius_m, o.left_wheel_radius_m);
      near_nominal("right_wheel_radius_m", d.right_wheel.radius_m, o.right_wheel_radius_m);
      near_nominal("wheelbase_m", d.wheelbase_m(), o.wheelbase_m);
    }
    r.Finish();
    return o;
  }

  // The mount of a link fixed to the base, or nullptr after reporting it.
  const sim::MountSpec* Mount(MapReader& r, const sim::RobotDescription& d) {
    auto link = r.RequiredString("link");
    if (!link || !have_urdf_) return nullptr;
    for (const sim::MountSpec& m : d.mounts) {
      if (m.link == *link) return &m;
    }
    std::string known;
    for (const sim::MountSpec& m : d.mounts) known += (known.empty() ? "" : ", ") + m.link;
    doc_->Error(r.Child("link"), r.PathOf("link"),
                "unknown link '" + *link + "': not a link fixed to the base in " + d.urdf_file +
                    " (those are: " + known + ")");
    return nullptr;
  }

  void ReadLasers(MapReader& top, sim::RobotConfig& c) {
    std::set<std::string> ids;
    ForEachMapping(doc_, top, "lasers", false, [&](MapReader& r, std::size_t) {
      sim::LaserMount laser;
      laser.id = UniqueName(doc_, r, "id", &ids);
      if (const sim::MountSpec* m = Mount(r, c.description)) {
        laser.link = m->link;
        laser.robot_from_sensor = m->pose;
        laser.z_m = m->z_m;
        if (std::abs(m->roll_rad) > kLevelToleranceRad ||
            std::abs(m->pitch_rad) > kLevelToleranceRad) {
          doc_->Error(r.Child("link"), r.PathOf("link"),
                      "link '" + m->link + "' is not level (roll and pitch must be 0): a scan " +
                          "plane is horizontal");
        }
      }
      const std::string profile =
          r.Choice("profile", {"sick_lms200", "acuity_accurange", "custom"}, "sick_lms200");
      laser.options = sim::LaserScannerOptions::Profile(profile);
      ReadLaserOverrides(r, &laser.options);
      c.lasers.push_back(laser);
    });
  }

  // The profile's values, overridden key by key (angles in degrees), and validated.
  void ReadLaserOverrides(MapReader& r, sim::LaserScannerOptions* o) {
    using Laser = sim::LaserScannerOptions;
    ReadOptions(
        r, o,
        {{"fov_deg", "fov_rad", &Laser::fov_rad, kDegToRad},
         {"beams", &Laser::beams},
         {"first_bearing_deg", "first_bearing_rad", &Laser::first_bearing_rad, kDegToRad},
         {"max_range_m", &Laser::max_range_m},
         {"scan_rate_hz", &Laser::scan_rate_hz},
         {"sweep_s", &Laser::sweep_s},
         {"interlaced_turns", &Laser::interlaced_turns},
         {"timestamp_bias_s", &Laser::timestamp_bias_s},
         {"range_sigma_m", &Laser::range_sigma_m},
         {"range_resolution_m", &Laser::range_resolution_m},
         {"amplitude_model", &Laser::amplitude_model},
         {"min_amplitude", &Laser::min_amplitude},
         {"low_amplitude_sigma_m", &Laser::low_amplitude_sigma_m},
         {"outlier_probability", &Laser::outlier_probability},
         {"dark_dropout_probability", &Laser::dark_dropout_probability},
         {"dark_sigma_factor", &Laser::dark_sigma_factor},
         {"specular_max_incidence_deg", "specular_max_incidence_rad",
          &Laser::specular_max_incidence_rad, kDegToRad},
         {"beam_divergence_deg", "beam_divergence_rad", &Laser::beam_divergence_rad, kDegToRad},
         {"mixed_pixel_min_gap_m", &Laser::mixed_pixel_min_gap_m},
         {"noise", &Laser::noise},
         {"effects", &Laser::effects}});
  }

  void ReadBumpers(MapReader& top, std::vector<sim::BumperZone>* out) {
    std::set<std::string> names;
    YAML::Node list = top.Child("bumpers");
    ForEachMapping(doc_, top, "bumpers", false, [&](MapReader& r, std::size_t) {
      sim::BumperZone z;
      z.name = UniqueName(doc_, r, "name", &names);
      auto from = r.RequiredNumber("from_deg", -360.0, 360.0);
      auto to = r.RequiredNumber("to_deg", -360.0, 360.0);
      if (from && to) {
        if (*from == *to) {
          doc_->Error(r.Child("to_deg"), r.PathOf("to_deg"),
                      "a zone runs counter-clockwise from from_deg to to_deg and must not be "
                      "empty (use to_deg = from_deg + 360 for all around)");
        }
        z.from_rad = *from * kDegToRad;
        z.to_rad = *to * kDegToRad;
      }
      out->push_back(z);
    });
    if (out->size() > kMaxBumperZones) {
      doc_->Error(list, "bumpers", "at most 32 zones (the bumper reading is a 32-bit mask)");
    }
  }

  // Casters on springs: `suspension: [{caster: <link>, stiffness_npm, damping_nspm}]`.
  void ReadSuspension(MapReader& top, sim::RobotDescription* d) {
    std::set<std::string> seen;
    ForEachMapping(doc_, top, "suspension", false, [&](MapReader& r, std::size_t) {
      const std::optional<std::string> link = r.RequiredString("caster");
      const auto stiffness = r.RequiredNumber("stiffness_npm", 1.0, 1e8);
      const double damping = r.Number("damping_nspm", 0.0, 0.0, 1e7);
      if (!link) return;
      auto caster = std::find_if(d->casters.begin(), d->casters.end(),
                                 [&](const sim::CasterSpec& c) { return c.link == *link; });
      if (caster == d->casters.end()) {
        if (have_urdf_) {
          doc_->Error(r.Child("caster"), r.PathOf("caster"),
                      "'" + *link + "' is not one of the robot's `casters`");
        }
        return;
      }
      if (!seen.insert(*link).second) {
        doc_->Error(r.Child("caster"), r.PathOf("caster"),
                    "caster '" + *link + "' is given a suspension twice");
        return;
      }
      caster->stiffness_npm = stiffness.value_or(0.0);
      caster->damping_nspm = damping;
    });
  }

  void ReadMarkers(MapReader& top, sim::RobotDescription* d) {
    std::set<std::string> ids;
    ForEachMapping(doc_, top, "markers", false, [&](MapReader& r, std::size_t) {
      sim::MarkerSpec m;
      m.id = UniqueName(doc_, r, "id", &ids);
      if (r.Has("link") == r.Has("position")) {
        doc_->Error(r.node(), r.PathOf("link"), "give exactly one of `link` and `position`");
        r.Child("link");
        r.Child("position");
      } else if (r.Has("link")) {
        if (const sim::MountSpec* mount = Mount(r, *d)) {
          m.link = mount->link;
          m.position_m = mount->pose.translation();
        }
      } else if (auto p = r.Numbers("position", 2, true)) {
        m.position_m = {(*p)[0], (*p)[1]};
      }
      m.radius_m = r.RequiredNumber("radius_m", 1e-3, 1.0).value_or(m.radius_m);
      if (auto z = r.Numbers("z_range_m", 2, true)) {
        if (!((*z)[0] >= 0.0 && (*z)[1] > (*z)[0] && (*z)[1] <= kMaxRobotSizeM)) {
          doc_->Error(
              r.Child("z_range_m"), r.PathOf("z_range_m"),
              "expected [bottom, top] heights above the floor with 0 <= bottom < top <= 10");
        } else {
          m.base_z_m = (*z)[0];
          m.height_m = (*z)[1] - (*z)[0];
        }
      }
      if (auto mat = r.RequiredString("material")) {
        m.material = *mat;
        if (KnownMaterial(r, "material", *mat, *d) &&
            d->materials.at(*mat).laser != core::LaserResponse::kRetroReflective) {
          doc_->Error(r.Child("material"), r.PathOf("material"),
                      "material '" + *mat + "' must have `laser: retro_reflective` (markers are " +
                          "the reflectors other robots' scanners flag, §6.3.5.1)");
        }
      }
      d->markers.push_back(m);
    });
  }

  void ReadCameras(MapReader& top, sim::RobotConfig& c) {
    std::set<std::string> ids;
    ForEachMapping(doc_, top, "cameras", false, [&](MapReader& r, std::size_t) {
      sim::CameraMount cam;
      cam.id = UniqueName(doc_, r, "id", &ids);
      if (const sim::MountSpec* m = Mount(r, c.description)) {
        cam.link = m->link;
        cam.mount = *m;
      }
      using Camera = sim::CameraMount;
      ReadOptions(r, &cam,
                  {{"width_px", &Camera::width_px},
                   {"height_px", &Camera::height_px},
                   {"hfov_deg", "hfov_rad", &Camera::hfov_rad, kDegToRad},
                   {"rate_hz", &Camera::rate_hz},
                   {"grayscale", &Camera::grayscale},
                   {"radial_k1", &Camera::radial_k1},
                   {"radial_k2", &Camera::radial_k2},
                   {"radial_k3", &Camera::radial_k3},
                   {"radial_k4", &Camera::radial_k4},
                   {"noise_grey", &Camera::noise_grey},
                   {"calibration_sigma_px", &Camera::calibration_sigma_px},
                   {"grabber_delay_ms", "grabber_delay_s", &Camera::grabber_delay_s, 1e-3},
                   {"grabber_delay_sigma_ms", "grabber_delay_sigma_s",
                    &Camera::grabber_delay_sigma_s, 1e-3}});
      c.cameras.push_back(cam);
    });
  }

  YamlDocument* doc_;
  bool have_urdf_ = false;
};

}  // namespace

sim::RobotConfig ReadRobot(YamlDocument* doc) { return RobotReader(doc).Read(); }

sim::RobotConfig LoadRobotFile(const std::string& robot_yaml_path) {
  YamlDocument doc(robot_yaml_path);
  sim::RobotConfig c = ReadRobot(&doc);
  doc.ThrowIfErrors();
  return c;
}

}  // namespace pavilion::scenarios
