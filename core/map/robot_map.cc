#include "core/map/robot_map.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <utility>

namespace pavilion::core {
namespace {

[[noreturn]] void Fail(const std::string& what, const std::string& id, const std::string& field,
                       const std::string& message) {
  throw std::invalid_argument(what + " '" + id + "': " + field + ": " + message);
}

bool Finite(const Eigen::Vector2d& v) { return v.allFinite(); }

void CheckCovariance(const Eigen::Matrix2d& c, const std::string& what, const std::string& id,
                     const std::string& field) {
  if (!IsPositiveDefinite(c)) Fail(what, id, field, "covariance is not positive definite");
}

void CheckLine(const Line& line, const std::string& what, const std::string& id) {
  if (!std::isfinite(line.alpha_rad) || !std::isfinite(line.r_m)) {
    Fail(what, id, "alpha/r", "must be finite");
  }
  if (!(line.alpha_rad > -std::numbers::pi && line.alpha_rad <= std::numbers::pi)) {
    Fail(what, id, "alpha", "must be in (-pi, pi]");
  }
  // Eq. B.4: the sign of r says from which side the line is seen; r = 0 (a line
  // through the map origin) leaves it undefined.
  if (line.r_m == 0.0) Fail(what, id, "r", "must not be 0 (visibility is the sign of r)");
  CheckCovariance(line.covariance, what, id, "cov");
}

void CheckPoint(const Point2Uncertain& p, const std::string& what, const std::string& id,
                const std::string& field) {
  if (!Finite(p.position_m)) Fail(what, id, field, "must be finite");
  CheckCovariance(p.covariance, what, id, field + "_cov");
}

void CheckOnLine(const Line& line, const Point2Uncertain& p, const std::string& what,
                 const std::string& id, const std::string& field) {
  if (std::abs(line.SignedDistance(p.position_m)) > kMapEndpointToleranceM) {
    Fail(what, id, field, "endpoint lies off its line by more than 1 mm");
  }
}

// Position along the line's direction (-sin alpha, cos alpha).
double Along(const Line& line, const Eigen::Vector2d& p) {
  return -std::sin(line.alpha_rad) * p.x() + std::cos(line.alpha_rad) * p.y();
}

}  // namespace

bool IsPositiveDefinite(const Eigen::Matrix2d& c) {
  if (!c.allFinite()) return false;
  if (c(0, 1) != c(1, 0)) return false;
  return c(0, 0) > 0.0 && c(1, 1) > 0.0 && c(0, 0) * c(1, 1) - c(0, 1) * c(1, 0) > 0.0;
}

namespace {

void CheckSegment(const MapSegment& s) {
  CheckLine(s.line, "segment", s.id);
  CheckPoint(s.first_endpoint, "segment", s.id, "from");
  CheckPoint(s.second_endpoint, "segment", s.id, "to");
  CheckOnLine(s.line, s.first_endpoint, "segment", s.id, "from");
  CheckOnLine(s.line, s.second_endpoint, "segment", s.id, "to");
  if (!(Along(s.line, s.first_endpoint.position_m) < Along(s.line, s.second_endpoint.position_m))) {
    Fail("segment", s.id, "to", "must lie after 'from' along the line's direction");
  }
}

void CheckMultiSegmentLine(const MapMultiSegmentLine& m) {
  CheckLine(m.line, "multi_segment_line", m.id);
  if (m.segments.empty()) Fail("multi_segment_line", m.id, "segments", "must not be empty");
  double last = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m.segments.size(); ++i) {
    const std::string field = "segments[" + std::to_string(i) + "]";
    const auto& [a, b] = m.segments[i];
    CheckPoint(a, "multi_segment_line", m.id, field + ".from");
    CheckPoint(b, "multi_segment_line", m.id, field + ".to");
    CheckOnLine(m.line, a, "multi_segment_line", m.id, field + ".from");
    CheckOnLine(m.line, b, "multi_segment_line", m.id, field + ".to");
    const double sa = Along(m.line, a.position_m), sb = Along(m.line, b.position_m);
    if (!(sa < sb) || sa < last - kMapEndpointToleranceM) {
      Fail("multi_segment_line", m.id, field,
           "segments must run along the line's direction (-sin alpha, cos alpha), in order");
    }
    last = sb;
  }
}

// Lines, segments, multi-segment lines, points and beacons, with ids unique among them.
void CheckFeatures(const RobotMap& map) {
  std::set<std::string> feature_ids;
  auto unique_feature = [&](const std::string& what, const std::string& id) {
    if (id.empty()) Fail(what, id, "id", "must not be empty");
    if (!feature_ids.insert(id).second) Fail(what, id, "id", "is used by another feature");
  };
  for (const MapLine& l : map.lines) {
    unique_feature("line", l.id);
    CheckLine(l.line, "line", l.id);
  }
  for (const MapSegment& s : map.segments) {
    unique_feature("segment", s.id);
    CheckSegment(s);
  }
  for (const MapMultiSegmentLine& m : map.multi_segment_lines) {
    unique_feature("multi_segment_line", m.id);
    CheckMultiSegmentLine(m);
  }
  for (const MapPoint& p : map.points) {
    unique_feature("point", p.id);
    CheckPoint(p.point, "point", p.id, "position");
    if (!(std::isfinite(p.radius_m) && p.radius_m >= 0.0)) {
      Fail("point", p.id, "radius", "must be finite and >= 0");
    }
  }
  for (const MapBeacon& b : map.beacons) {
    unique_feature("beacon", b.id);
    CheckPoint(b.point, "beacon", b.id, "position");
    if (!(std::isfinite(b.radius_m) && b.radius_m >= 0.0)) {
      Fail("beacon", b.id, "radius", "must be finite and >= 0");
    }
  }
}

// Nodes with unique ids and finite poses; undirected edges between two known nodes.
void CheckTopology(const RobotMap& map) {
  std::set<std::string> node_ids;
  for (const MapNode& n : map.nodes) {
    if (n.id.empty()) Fail("node", n.id, "id", "must not be empty");
    if (!node_ids.insert(n.id).second) Fail("node", n.id, "id", "is used by another node");
    if (!std::isfinite(n.pose.x_m) || !std::isfinite(n.pose.y_m) ||
        !std::isfinite(n.pose.theta_rad)) {
      Fail("node", n.id, "pose", "must be finite");
    }
  }
  std::set<std::pair<std::string, std::string>> edges;
  for (const MapEdge& e : map.edges) {
    const std::string id = e.from + "-" + e.to;
    if (!node_ids.contains(e.from)) Fail("edge", id, "from", "unknown node '" + e.from + "'");
    if (!node_ids.contains(e.to)) Fail("edge", id, "to", "unknown node '" + e.to + "'");
    if (e.from == e.to) Fail("edge", id, "to", "an edge must join two different nodes");
    if (!(std::isfinite(e.weight) && e.weight > 0.0)) {
      Fail("edge", id, "weight", "must be finite and > 0");
    }
    if (!edges.insert(std::minmax(e.from, e.to)).second) {
      Fail("edge", id, "from/to", "duplicate edge (edges are undirected)");
    }
  }
}

void CheckGhostPoints(const RobotMap& map) {
  std::set<std::string> ghost_ids;
  for (const MapGhostPoint& g : map.ghost_points) {
    if (g.id.empty()) Fail("ghost point", g.id, "id", "must not be empty");
    if (!ghost_ids.insert(g.id).second) {
      Fail("ghost point", g.id, "id", "is used by another ghost point");
    }
    if (!Finite(g.position_m)) Fail("ghost point", g.id, "position", "must be finite");
  }
}

}  // namespace

void ValidateRobotMap(const RobotMap& map) {
  if (!(std::isfinite(map.beam_height_m) && map.beam_height_m > 0.0)) {
    throw std::invalid_argument("map: beam_height: must be finite and > 0");
  }
  CheckFeatures(map);
  CheckTopology(map);
  CheckGhostPoints(map);
}

}  // namespace pavilion::core
