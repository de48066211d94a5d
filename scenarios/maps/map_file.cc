#include "scenarios/maps/map_file.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>

#include "scenarios/output/output_files.h"

namespace pavilion::scenarios {
namespace {

// Coordinates beyond this are almost certainly a unit mistake (m), as in world files.
constexpr double kMaxCoordinateM = 1e4;
// alpha is stored in (-pi, pi]; a file may round pi up or down by this much.
constexpr double kAlphaSlackRad = 1e-9;

const std::vector<std::string> kFeatureTypes = {"line", "segment", "multi_segment_line", "point",
                                                "beacon"};
const std::vector<std::string> kNodeTypes = {"station", "via"};

// Map names are [a-z0-9_]+; ids also allow upper-case letters and '-' (as world ids).
bool IsName(const std::string& s, bool id) {
  if (s.empty() || s == "null" || s == "Null" || s == "NULL") return false;  // YAML null

  for (const char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
                    (id && ((c >= 'A' && c <= 'Z') || c == '-'));
    if (!ok) return false;
  }
  return true;
}

std::optional<std::string> Id(YamlDocument* doc, MapReader& r, std::set<std::string>* used,
                              const std::string& kind) {
  auto id = r.RequiredString("id");
  if (!id) return std::nullopt;
  if (!IsName(*id, true)) {
    doc->Error(r.Child("id"), r.PathOf("id"), "must use letters, digits, '_' or '-'");
    return std::nullopt;
  }
  if (!used->insert(*id).second) {
    doc->Error(r.Child("id"), r.PathOf("id"),
               "duplicate id: '" + *id + "' is already used by another " + kind);
    return std::nullopt;
  }
  return id;
}

// [var_1, cov_12, var_2] of a positive-definite 2x2 covariance.
std::optional<Eigen::Matrix2d> Covariance(YamlDocument* doc, MapReader& r, const std::string& key) {
  auto v = r.Numbers(key, 3, true);
  if (!v) return std::nullopt;
  Eigen::Matrix2d c;
  c << (*v)[0], (*v)[1], (*v)[1], (*v)[2];
  if (!core::IsPositiveDefinite(c)) {
    doc->Error(r.Child(key), r.PathOf(key),
               "covariance is not positive definite: expected [var_1, cov_12, var_2] with "
               "var_1 > 0, var_2 > 0 and cov_12^2 < var_1 * var_2");
    return std::nullopt;
  }
  return c;
}

std::optional<Eigen::Vector2d> Position(YamlDocument* doc, MapReader& r, const std::string& key) {
  auto v = r.Numbers(key, 2, true);
  if (!v) return std::nullopt;
  if (std::abs((*v)[0]) > kMaxCoordinateM || std::abs((*v)[1]) > kMaxCoordinateM) {
    doc->Error(r.Child(key), r.PathOf(key), "coordinate beyond ±10 km; units are metres");
    return std::nullopt;
  }
  return Eigen::Vector2d((*v)[0], (*v)[1]);
}

std::optional<core::Point2Uncertain> UncertainPoint(YamlDocument* doc, MapReader& r,
                                                    const std::string& key,
                                                    const std::string& cov_key) {
  auto p = Position(doc, r, key);
  auto c = Covariance(doc, r, cov_key);
  if (!p || !c) return std::nullopt;
  return core::Point2Uncertain{*p, *c};
}

// alpha, r and cov of a line (eq. B.1 with the visibility sign of eq. B.4).
std::optional<core::Line> ReadLine(YamlDocument* doc, MapReader& r) {
  auto alpha = r.RequiredNumber("alpha", -std::numbers::pi - kAlphaSlackRad,
                                std::numbers::pi + kAlphaSlackRad);
  auto dist = r.RequiredNumber("r", -kMaxCoordinateM, kMaxCoordinateM);
  auto cov = Covariance(doc, r, "cov");
  if (dist && *dist == 0.0) {
    doc->Error(r.Child("r"), r.PathOf("r"),
               "must not be 0: the sign of r says from which side the line is seen (eq. B.4); "
               "a line through the map origin has none");
    return std::nullopt;
  }
  if (!alpha || !dist || !cov) return std::nullopt;
  return core::Line{core::NormalizeAngle(*alpha), *dist, *cov};
}

// Position along the line's direction (-sin alpha, cos alpha).
double Along(const core::Line& line, const Eigen::Vector2d& p) {
  return -std::sin(line.alpha_rad) * p.x() + std::cos(line.alpha_rad) * p.y();
}

bool OnLine(YamlDocument* doc, MapReader& r, const core::Line& line, const core::Point2Uncertain& p,
            const std::string& key) {
  const double off = line.SignedDistance(p.position_m);
  if (std::abs(off) <= core::kMapEndpointToleranceM) return true;
  doc->Error(r.Child(key), r.PathOf(key),
             "endpoint lies " + std::to_string(std::abs(off)) +
                 " m off the line (alpha, r); at most 0.001 m allowed");
  return false;
}

// One member of a segment or multi-segment line: from/to with covariances, on
// `line` and running along its direction.
std::optional<std::pair<core::Point2Uncertain, core::Point2Uncertain>> Endpoints(
    YamlDocument* doc, MapReader& r, const std::optional<core::Line>& line) {
  auto a = UncertainPoint(doc, r, "from", "from_cov");
  auto b = UncertainPoint(doc, r, "to", "to_cov");
  if (!a || !b || !line) return std::nullopt;
  if (!OnLine(doc, r, *line, *a, "from") || !OnLine(doc, r, *line, *b, "to")) return std::nullopt;
  if (!(Along(*line, a->position_m) < Along(*line, b->position_m))) {
    doc->Error(r.Child("to"), r.PathOf("to"),
               "'to' must lie after 'from' along the line's direction (-sin alpha, cos alpha)");
    return std::nullopt;
  }
  return std::make_pair(*a, *b);
}

void ReadFeature(YamlDocument* doc, MapReader& r, std::set<std::string>* ids, core::RobotMap* map) {
  const std::string type = r.Choice("type", kFeatureTypes, "", true);
  const auto id = Id(doc, r, ids, "feature");
  if (type == "line") {
    auto line = ReadLine(doc, r);
    if (id && line) map->lines.push_back({*id, *line});
  } else if (type == "segment") {
    auto line = ReadLine(doc, r);
    auto ends = Endpoints(doc, r, line);
    if (id && line && ends) map->segments.push_back({*id, *line, ends->first, ends->second});
  } else if (type == "multi_segment_line") {
    auto line = ReadLine(doc, r);
    core::MapMultiSegmentLine m;
    bool ok = id && line;
    YAML::Node list = r.Child("segments", true);
    if (list.IsDefined()) {
      if (!list.IsSequence() || list.size() == 0) {
        doc->Error(list, r.PathOf("segments"), "expected a list of at least one segment");
        ok = false;
      } else {
        double last = -std::numeric_limits<double>::infinity();
        for (std::size_t i = 0; i < list.size(); ++i) {
          MapReader s(doc, list[i], IndexPath(r.PathOf("segments"), i));
          if (!s.valid()) {
            ok = false;
            continue;
          }
          auto ends = Endpoints(doc, s, line);
          s.Finish();
          if (!ends) {
            ok = false;
            continue;
          }
          const double from = Along(*line, ends->first.position_m);
          if (from < last - core::kMapEndpointToleranceM) {
            doc->Error(list[i], IndexPath(r.PathOf("segments"), i),
                       "segments must be listed in order along the line's direction "
                       "(-sin alpha, cos alpha) without overlapping");
            ok = false;
          }
          last = Along(*line, ends->second.position_m);
          m.segments.push_back(*ends);
        }
      }
    } else {
      ok = false;
    }
    if (ok) {
      m.id = *id;
      m.line = *line;
      map->multi_segment_lines.push_back(std::move(m));
    }
  } else if (type == "point") {
    auto p = UncertainPoint(doc, r, "position", "cov");
    const double radius = r.Number("radius", 0.0, 0.0, 1e3);
    if (id && p) map->points.push_back({*id, *p, radius});
  } else if (type == "beacon") {
    auto p = UncertainPoint(doc, r, "position", "cov");
    const double radius = r.Number("radius", 0.0, 0.0, 1e3);
    if (id && p) map->beacons.push_back({*id, *p, radius});
  }
  // An unknown type was reported by Choice(); its other keys are not checked.
  if (type.empty()) {
    for (const auto& kv : r.node()) r.Child(kv.first.Scalar());
  }
}

void ReadNode(YamlDocument* doc, MapReader& r, std::set<std::string>* ids, core::RobotMap* map) {
  const auto id = Id(doc, r, ids, "node");
  const std::string type = r.Choice("type", kNodeTypes, "via", true);
  auto pose = r.Numbers("pose", 3, true);
  if (pose && (std::abs((*pose)[0]) > kMaxCoordinateM || std::abs((*pose)[1]) > kMaxCoordinateM)) {
    doc->Error(r.Child("pose"), r.PathOf("pose"), "coordinate beyond ±10 km; units are metres");
    pose.reset();
  }
  if (id && pose) {
    map->nodes.push_back({*id, core::Pose2{(*pose)[0], (*pose)[1], (*pose)[2]}, type == "station"});
  }
}

void ReadEdge(YamlDocument* doc, MapReader& r, const std::set<std::string>& nodes,
              std::set<std::pair<std::string, std::string>>* seen, core::RobotMap* map) {
  auto known = [&](const std::string& key) -> std::optional<std::string> {
    auto name = r.RequiredString(key);
    if (name && !nodes.contains(*name)) {
      doc->Error(r.Child(key), r.PathOf(key), "unknown node '" + *name + "'");
      return std::nullopt;
    }
    return name;
  };
  const auto from = known("from");
  const auto to = known("to");
  const std::optional<double> read = r.RequiredNumber("weight", 0.0, 1e6);
  const double weight = read.value_or(-1.0);
  if (read && weight <= 0.0) doc->Error(r.Child("weight"), r.PathOf("weight"), "must be > 0");
  if (!from || !to || weight <= 0.0) return;
  if (*from == *to) {
    doc->Error(r.Child("to"), r.PathOf("to"), "an edge must join two different nodes");
    return;
  }
  if (!seen->insert(std::minmax(*from, *to)).second) {
    doc->Error(r.node(), r.PathOf("from"),
               "duplicate edge " + *from + " - " + *to + " (edges are undirected)");
    return;
  }
  map->edges.push_back({*from, *to, weight});
}

// --- writing ---

// Shortest decimal text that reads back to exactly `v` (and "0" for -0).
std::string Num(double v) {
  if (v == 0.0) return "0";
  char buf[64];
  const auto result = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, result.ptr);
}

// Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on chained `+`.
std::string Vec(const Eigen::Vector2d& v) {
  std::string out = "[";
  out.append(Num(v.x())).append(", ").append(Num(v.y())).append("]");
  return out;
}

std::string Cov(const Eigen::Matrix2d& c) {
  std::string out = "[";
  out.append(Num(c(0, 0))).append(", ").append(Num(c(0, 1))).append(", ");
  out.append(Num(c(1, 1))).append("]");
  return out;
}

// A YAML double-quoted scalar.
std::string Quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char hex[8];
          std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned>(c));
          out += hex;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

void CheckName(const std::string& what, const std::string& id) {
  if (!IsName(id, true)) {
    throw std::invalid_argument(what + " id '" + id + "' must use letters, digits, '_' or '-'");
  }
}

void AppendLine(std::string* out, const core::Line& l) {
  out->append("    alpha: ").append(Num(l.alpha_rad)).append("\n");
  out->append("    r: ").append(Num(l.r_m)).append("\n");
  out->append("    cov: ").append(Cov(l.covariance)).append("\n");
}

}  // namespace

core::RobotMap ReadRobotMap(YamlDocument* doc) {
  core::RobotMap map;
  if (!doc->ok()) return map;
  MapReader top(doc, doc->root(), "");
  if (!top.valid()) return map;
  if (auto kind = top.RequiredString("kind"); kind && *kind != "map") {
    doc->Error(top.Child("kind"), "kind", "expected 'map', got '" + *kind + "'");
  }
  if (auto name = top.RequiredString("name")) {
    if (!IsName(*name, false)) {
      doc->Error(top.Child("name"), "name", "must be lower-case letters, digits and '_'");
    }
    map.name = *name;
  }
  map.description = top.String("description", "");
  map.beam_height_m = top.RequiredNumber("beam_height", 1e-3, 100.0).value_or(0.5);
  std::set<std::string> feature_ids;
  ForEachMapping(doc, top, "features", false,
                 [&](MapReader& r, std::size_t) { ReadFeature(doc, r, &feature_ids, &map); });
  std::set<std::string> node_ids;
  ForEachMapping(doc, top, "nodes", false,
                 [&](MapReader& r, std::size_t) { ReadNode(doc, r, &node_ids, &map); });
  std::set<std::pair<std::string, std::string>> edges;
  ForEachMapping(doc, top, "edges", false,
                 [&](MapReader& r, std::size_t) { ReadEdge(doc, r, node_ids, &edges, &map); });
  std::set<std::string> ghost_ids;
  ForEachMapping(doc, top, "ghost_points", false, [&](MapReader& r, std::size_t) {
    const auto id = Id(doc, r, &ghost_ids, "ghost point");
    const auto p = Position(doc, r, "position");
    if (id && p) map.ghost_points.push_back({*id, *p});
  });
  top.Finish();
  if (doc->ok()) {
    // Every invariant is checked above with its line; this catches any left over.
    try {
      core::ValidateRobotMap(map);
    } catch (const std::invalid_argument& e) {
      doc->Error(doc->root(), "", e.what());
    }
  }
  return map;
}

core::RobotMap LoadMapFile(const std::string& path) {
  YamlDocument doc(path);
  core::RobotMap map = ReadRobotMap(&doc);
  doc.ThrowIfErrors();
  return map;
}

std::string RobotMapToYaml(const core::RobotMap& map) {
  core::ValidateRobotMap(map);
  if (!IsName(map.name, false)) {
    throw std::invalid_argument("map name '" + map.name + "' must be [a-z0-9_]+");
  }
  std::string out;
  out.append("# Robot map (docs/map_format.md): units m and rad, covariances [var_1, cov_12, ")
      .append("var_2].\n");
  out.append("kind: map\n");
  out.append("name: ").append(map.name).append("\n");
  if (!map.description.empty()) {
    out.append("description: ").append(Quoted(map.description)).append("\n");
  }
  out.append("beam_height: ").append(Num(map.beam_height_m)).append("\n");

  const std::size_t feature_count = map.lines.size() + map.segments.size() +
                                    map.multi_segment_lines.size() + map.points.size() +
                                    map.beacons.size();
  out.append(feature_count == 0 ? "features: []\n" : "features:\n");
  for (const core::MapLine& l : map.lines) {
    CheckName("line", l.id);
    out.append("  - type: line\n    id: ").append(l.id).append("\n");
    AppendLine(&out, l.line);
  }
  for (const core::MapSegment& s : map.segments) {
    CheckName("segment", s.id);
    out.append("  - type: segment\n    id: ").append(s.id).append("\n");
    AppendLine(&out, s.line);
    out.append("    from: ").append(Vec(s.first_endpoint.position_m)).append("\n");
    out.append("    from_cov: ").append(Cov(s.first_endpoint.covariance)).append("\n");
    out.append("    to: ").append(Vec(s.second_endpoint.position_m)).append("\n");
    out.append("    to_cov: ").append(Cov(s.second_endpoint.covariance)).append("\n");
  }
  for (const core::MapMultiSegmentLine& m : map.multi_segment_lines) {
    CheckName("multi_segment_line", m.id);
    out.append("  - type: multi_segment_line\n    id: ").append(m.id).append("\n");
    AppendLine(&out, m.line);
    out.append("    segments:\n");
    for (const auto& [a, b] : m.segments) {
      out.append("      - {from: ").append(Vec(a.position_m));
      out.append(", from_cov: ").append(Cov(a.covariance));
      out.append(", to: ").append(Vec(b.position_m));
      out.append(", to_cov: ").append(Cov(b.covariance)).append("}\n");
    }
  }
  for (const core::MapPoint& p : map.points) {
    CheckName("point", p.id);
    out.append("  - type: point\n    id: ").append(p.id).append("\n");
    out.append("    position: ").append(Vec(p.point.position_m)).append("\n");
    out.append("    cov: ").append(Cov(p.point.covariance)).append("\n");
    out.append("    radius: ").append(Num(p.radius_m)).append("\n");
  }
  for (const core::MapBeacon& b : map.beacons) {
    CheckName("beacon", b.id);
    out.append("  - type: beacon\n    id: ").append(b.id).append("\n");
    out.append("    position: ").append(Vec(b.point.position_m)).append("\n");
    out.append("    cov: ").append(Cov(b.point.covariance)).append("\n");
    if (b.radius_m > 0.0) out.append("    radius: ").append(Num(b.radius_m)).append("\n");
  }
  out.append(map.nodes.empty() ? "nodes: []\n" : "nodes:\n");
  for (const core::MapNode& n : map.nodes) {
    CheckName("node", n.id);
    out.append("  - {id: ").append(n.id).append(", type: ");
    out.append(n.station ? "station" : "via").append(", pose: [");
    out.append(Num(n.pose.x_m)).append(", ").append(Num(n.pose.y_m)).append(", ");
    out.append(Num(n.pose.theta_rad)).append("]}\n");
  }
  out.append(map.edges.empty() ? "edges: []\n" : "edges:\n");
  for (const core::MapEdge& e : map.edges) {
    out.append("  - {from: ").append(e.from).append(", to: ").append(e.to);
    out.append(", weight: ").append(Num(e.weight)).append("}\n");
  }
  out.append(map.ghost_points.empty() ? "ghost_points: []\n" : "ghost_points:\n");
  for (const core::MapGhostPoint& g : map.ghost_points) {
    CheckName("ghost point", g.id);
    out.append("  - {id: ").append(g.id).append(", position: ");
    out.append(Vec(g.position_m)).append("}\n");
  }
  return out;
}

void WriteMapFile(const std::string& path, const core::RobotMap& map) {
  WriteFileAtomically(path, RobotMapToYaml(map));
}

}  // namespace pavilion::scenarios
