// `pavilion map derive` on the shipped worlds (thesis §4.3, §6.3.1): faces at the
// beam height become exactly one map line each, glass and low objects become
// ghost points, columns points, the retro-reflective column a beacon; stations
// come from the places and every edge keeps the robot radius from every
// obstacle. The shipped map files equal a fresh derivation.
#include "scenarios/maps/map_derivation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenarios/config/data_paths.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/maps/map_file.h"
#include "sim/world/world.h"
#include "tests/support/robot_map_compare.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::ExpectSameMap;

using Vec2 = Eigen::Vector2d;

constexpr double kBeamHeightM = 0.5;
constexpr double kLowHeightM = 0.2;
constexpr double kRobotRadiusM = 0.35;
constexpr double kCoverToleranceM = 1e-3;  // "within 1 mm"

std::unique_ptr<sim::World> LoadWorld(const std::string& name) {
  return std::make_unique<sim::World>(LoadWorldFile(ResolveWorldPath(name)), sim::WorldOptions{});
}

MapDerivationOptions Exact() {
  MapDerivationOptions o;
  o.noise_sigma_m = 0.0;
  return o;
}

// A map line (segment, multi-segment line or infinite line) with its members.
struct LineView {
  std::string id;
  core::Line line;
  std::vector<std::pair<Vec2, Vec2>> members;  // empty for an infinite line
};

std::vector<LineView> Lines(const core::RobotMap& m) {
  std::vector<LineView> out;
  for (const auto& l : m.lines) out.push_back({l.id, l.line, {}});
  for (const auto& s : m.segments) {
    out.push_back({s.id, s.line, {{s.first_endpoint.position_m, s.second_endpoint.position_m}}});
  }
  for (const auto& ms : m.multi_segment_lines) {
    LineView v{ms.id, ms.line, {}};
    for (const auto& [a, b] : ms.segments) v.members.emplace_back(a.position_m, b.position_m);
    out.push_back(v);
  }
  return out;
}

double Along(const core::Line& l, const Vec2& p) {
  return -std::sin(l.alpha_rad) * p.x() + std::cos(l.alpha_rad) * p.y();
}

// How many map lines cover the face a-b (solid on its left): both ends within
// 1 mm of the line, the line seen from the face's free side (eq. B.4), and the
// face inside one member.
int Covering(const std::vector<LineView>& lines, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const Vec2 into_solid = Vec2(-ab.y(), ab.x()).normalized();
  int n = 0;
  for (const LineView& v : lines) {
    if (std::abs(v.line.SignedDistance(a)) > kCoverToleranceM ||
        std::abs(v.line.SignedDistance(b)) > kCoverToleranceM ||
        v.line.normal().dot(into_solid) < 0.999) {
      continue;
    }
    const double s0 = std::min(Along(v.line, a), Along(v.line, b));
    const double s1 = std::max(Along(v.line, a), Along(v.line, b));
    bool inside = v.members.empty();
    for (const auto& [p, q] : v.members) {
      inside = inside || (Along(v.line, p) - kCoverToleranceM <= s0 &&
                          s1 <= Along(v.line, q) + kCoverToleranceM);
    }
    n += inside;
  }
  return n;
}

// Map lines through both ends of a-b within 1 mm, whatever their side.
int OnLine(const std::vector<LineView>& lines, const Vec2& a, const Vec2& b) {
  int n = 0;
  for (const LineView& v : lines) {
    n += std::abs(v.line.SignedDistance(a)) <= kCoverToleranceM &&
         std::abs(v.line.SignedDistance(b)) <= kCoverToleranceM;
  }
  return n;
}

bool InPolygon(const std::vector<Vec2>& poly, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
        p.x() < (poly[j].x() - poly[i].x()) * (p.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) +
                    poly[i].x()) {
      in = !in;
    }
  }
  return in;
}

Vec2 OutwardNormal(const Vec2& a, const Vec2& b) {
  const Vec2 ab = (b - a).normalized();
  return {ab.y(), -ab.x()};
}

double PointSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

// Smallest distance from an edge to any static section primitive at the beam
// and the low height (laser-visible or not), sampled every centimetre.
double EdgeClearance(const sim::World& world, const Vec2& a, const Vec2& b) {
  double best = 1e9;
  for (const double z : {kBeamHeightM, kLowHeightM}) {
    const core::PlanarSection s = world.SectionAt(z);
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / 0.01)));
    for (int k = 0; k <= steps; ++k) {
      const Vec2 p = a + (b - a) * (static_cast<double>(k) / steps);
      for (const auto& seg : s.segments) best = std::min(best, PointSegment(p, seg.a_m, seg.b_m));
      for (const auto& c : s.circles) best = std::min(best, (p - c.center_m).norm() - c.radius_m);
    }
  }
  return best;
}

void ExpectEdgesCollisionFree(const sim::World& world, const core::RobotMap& map) {
  std::map<std::string, Vec2> at;
  for (const auto& n : map.nodes) at[n.id] = n.pose.translation();
  for (const auto& e : map.edges) {
    const Vec2 a = at.at(e.from), b = at.at(e.to);
    // Sampling every 1 cm can miss the closest point by at most 5 mm.
    EXPECT_GE(EdgeClearance(world, a, b), kRobotRadiusM - 0.005) << e.from << " - " << e.to;
    EXPECT_NEAR(e.weight, (a - b).norm(), 1e-5);
  }
}

// Number of connected parts of the graph.
int GraphParts(const core::RobotMap& map) {
  std::map<std::string, std::vector<std::string>> adjacent;
  for (const auto& e : map.edges) {
    adjacent[e.from].push_back(e.to);
    adjacent[e.to].push_back(e.from);
  }
  std::set<std::string> seen;
  int parts = 0;
  for (const auto& n : map.nodes) {
    if (seen.contains(n.id)) continue;
    ++parts;
    std::deque<std::string> queue = {n.id};
    seen.insert(n.id);
    while (!queue.empty()) {
      const std::string id = queue.front();
      queue.pop_front();
      for (const auto& next : adjacent[id]) {
        if (seen.insert(next).second) queue.push_back(next);
      }
    }
  }
  return parts;
}

const core::MapPoint* FindPoint(const core::RobotMap& m, const std::string& id) {
  for (const auto& p : m.points) {
    if (p.id == id) return &p;
  }
  return nullptr;
}

// The expo_hall world and its map derived without tape-measure noise.
struct ExpoHall {
  std::unique_ptr<sim::World> world = LoadWorld("expo_hall");
  core::RobotMap map = DeriveRobotMap(*world, Exact());
};

// The distance from `p` to the nearest ghost point of `map`.
double NearestGhost(const core::RobotMap& map, const Vec2& p) {
  double nearest = 1e9;
  for (const auto& g : map.ghost_points) nearest = std::min(nearest, (g.position_m - p).norm());
  return nearest;
}

// Expo.02 hall (Fig. 6.2: "44 segments on 44 lines"): every wall face seen from
// the circulation area is covered by exactly one line within 1 mm (outer faces
// by none), and glass is absent and marked by ghost points.
TEST(MapDerivationTest, ExpoHallFollowsItsSection) {
  const ExpoHall expo;
  const core::RobotMap& map = expo.map;
  const std::vector<LineView> lines = Lines(map);
  EXPECT_EQ(map.segments.size() + map.multi_segment_lines.size(), 44u);

  const sim::WorldDescription& d = expo.world->description();
  std::vector<Vec2> hall;  // wall centrelines, gaps closed
  for (const auto& w : d.walls) {
    if (w.id == "wall_east" || w.id == "wall_west") {
      hall.insert(hall.end(), w.points_m.begin(), w.points_m.end());
    }
  }
  const core::PlanarSection beam = expo.world->SectionAt(kBeamHeightM);
  int inner = 0, outer = 0, glass = 0;
  for (const auto& s : beam.segments) {
    const auto& e = beam.elements[s.element];
    if (e.id.starts_with("wall_")) {
      const bool cap = (s.b_m - s.a_m).norm() < 0.25;  // end caps at the entrance and exit
      const bool faces_hall =
          InPolygon(hall, 0.5 * (s.a_m + s.b_m) + 0.05 * OutwardNormal(s.a_m, s.b_m));
      const int expected = cap || faces_hall ? 1 : 0;
      EXPECT_EQ(Covering(lines, s.a_m, s.b_m), expected)
          << e.id << " face " << s.a_m.transpose() << " -> " << s.b_m.transpose();
      (expected ? inner : outer)++;
    }
    if (e.laser == core::LaserResponse::kTransparent) {
      ++glass;
      EXPECT_EQ(OnLine(lines, s.a_m, s.b_m), 0) << e.id;
      EXPECT_LT(NearestGhost(map, 0.5 * (s.a_m + s.b_m)), 0.2) << "no ghost point on " << e.id;
    }
  }
  EXPECT_EQ(inner, 16);  // 12 inner faces and 4 end caps
  EXPECT_GT(outer, 0);
  EXPECT_GT(glass, 0);
}

// Expo.02 hall: objects below the beam (benches, docks, plinths) carry ghost
// points, and the entrance is closed by a row of them (§6.3.1).
TEST(MapDerivationTest, ExpoHallGhostPointsMarkWhatTheLaserMisses) {
  const ExpoHall expo;
  const core::RobotMap& map = expo.map;
  const core::PlanarSection beam = expo.world->SectionAt(kBeamHeightM);
  const core::PlanarSection low = expo.world->SectionAt(kLowHeightM);
  std::set<int> at_beam;
  for (const auto& s : beam.segments) at_beam.insert(s.element);
  for (const auto& s : low.segments) {
    if (at_beam.contains(s.element)) continue;
    EXPECT_LT(NearestGhost(map, 0.5 * (s.a_m + s.b_m)), 0.2)
        << "no ghost point on " << low.elements[s.element].id;
  }
  int entrance = 0;
  for (const auto& g : map.ghost_points) {
    entrance += std::abs(g.position_m.y() + 2.5) < 0.05 && g.position_m.x() > -13.2 &&
                g.position_m.x() < -11.0;
  }
  EXPECT_GE(entrance, 8);
}

// Expo.02 hall: columns are points with their radius; the retro-reflective
// column a beacon with its radius.
TEST(MapDerivationTest, ExpoHallColumnsArePointsAndTheRetroColumnABeacon) {
  const ExpoHall expo;
  const core::RobotMap& map = expo.map;
  for (const auto& c : expo.world->description().cylinders) {
    if (c.id == "column_2") {
      ASSERT_EQ(map.beacons.size(), 1u);
      EXPECT_EQ(map.beacons[0].id, "column_2");
      EXPECT_LT((map.beacons[0].point.position_m - c.position_m).norm(), 1e-6);
      EXPECT_DOUBLE_EQ(map.beacons[0].radius_m, c.radius_m);
      EXPECT_EQ(FindPoint(map, c.id), nullptr);
      continue;
    }
    const core::MapPoint* p = FindPoint(map, c.id);
    ASSERT_NE(p, nullptr) << c.id;
    EXPECT_LT((p->point.position_m - c.position_m).norm(), 1e-6);
    EXPECT_NEAR(p->radius_m, c.radius_m, 1e-6);
  }
  EXPECT_EQ(map.points.size(), 4u);
}

// Expo.02 hall: the 25 station places are the stations, at their poses, in
// one collision-free graph.
TEST(MapDerivationTest, ExpoHallStationsJoinOneCollisionFreeGraph) {
  const ExpoHall expo;
  const core::RobotMap& map = expo.map;
  const sim::WorldDescription& d = expo.world->description();
  int station_places = 0;
  for (const auto& [name, place] : d.places) {
    station_places += name.starts_with("station_") || name.starts_with("dock_");
  }
  int stations = 0;
  for (const auto& n : map.nodes) {
    if (!n.station) continue;
    ++stations;
    ASSERT_TRUE(d.places.contains(n.id));
    EXPECT_LT((d.places.at(n.id).pose->translation() - n.pose.translation()).norm(), 1e-6);
  }
  EXPECT_EQ(station_places, 25);
  EXPECT_EQ(stations, station_places);

  ExpectEdgesCollisionFree(*expo.world, map);
  EXPECT_EQ(GraphParts(map), 1);
}

// Small-map SLAM room (§7.6.1: "a 52-step map with 17 lines"): 6 inner wall
// faces, 4 faces of each free object and 3 of the one against the wall.
TEST(MapDerivationTest, SmallLabHasSeventeenLines) {
  const auto world = LoadWorld("small_lab");
  const core::RobotMap map = DeriveRobotMap(*world, Exact());
  const std::vector<LineView> lines = Lines(map);
  EXPECT_EQ(map.segments.size(), 17u);
  EXPECT_TRUE(map.multi_segment_lines.empty());
  const sim::WorldDescription& d = world->description();
  const std::vector<Vec2>& room = d.walls.front().points_m;  // closed centreline
  const core::PlanarSection beam = world->SectionAt(kBeamHeightM);
  std::map<std::string, int> covered;
  double object_3_back_x = -1e9;
  for (const auto& s : beam.segments) {
    const auto& id = beam.elements[s.element].id;
    if (id == "object_3")
      object_3_back_x = std::max(object_3_back_x, 0.5 * (s.a_m.x() + s.b_m.x()));
  }
  for (const auto& s : beam.segments) {
    const auto& id = beam.elements[s.element].id;
    const int n = Covering(lines, s.a_m, s.b_m);
    EXPECT_LE(n, 1);
    if (id == "room") {
      const bool faces_room =
          InPolygon(room, 0.5 * (s.a_m + s.b_m) + 0.05 * OutwardNormal(s.a_m, s.b_m));
      EXPECT_EQ(n, faces_room ? 1 : 0);
    } else if (id == "object_3" && 0.5 * (s.a_m.x() + s.b_m.x()) == object_3_back_x) {
      EXPECT_EQ(n, 0) << "the back of object_3 faces the wall 1 cm away";
    } else {
      EXPECT_EQ(n, 1) << id;
    }
    covered[id] += n;
  }
  EXPECT_EQ(covered["room"], 6);
  EXPECT_EQ(covered["object_1"], 4);
  EXPECT_EQ(covered["object_2"], 4);
  EXPECT_EQ(covered["object_3"], 3);
  ExpectEdgesCollisionFree(*world, map);
}

// The institute floor: every map line lies on laser-visible faces and covers
// each at most once, rooms nobody can enter (the stairwell behind its closed
// door) stay unmapped, every place is a node and every edge is collision-free.
TEST(MapDerivationTest, OfficeFloorMapsOnlyWhatRobotsSee) {
  const auto world = LoadWorld("office_floor");
  const core::RobotMap map = DeriveRobotMap(*world, Exact());
  const std::vector<LineView> lines = Lines(map);
  EXPECT_FALSE(map.multi_segment_lines.empty());  // walls broken by doors and partitions
  const core::PlanarSection beam = world->SectionAt(kBeamHeightM);
  for (const auto& s : beam.segments) {
    if (beam.elements[s.element].laser == core::LaserResponse::kTransparent) {
      EXPECT_EQ(OnLine(lines, s.a_m, s.b_m), 0) << beam.elements[s.element].id;
    } else {
      EXPECT_LE(Covering(lines, s.a_m, s.b_m), 1) << beam.elements[s.element].id;
    }
  }
  // Every member lies on an opaque face of the section (nothing invented).
  for (const LineView& v : lines) {
    for (const auto& [a, b] : v.members) {
      const Vec2 mid = 0.5 * (a + b);
      double nearest = 1e9;
      for (const auto& s : beam.segments) {
        if (beam.elements[s.element].laser == core::LaserResponse::kTransparent) continue;
        nearest = std::min(nearest, PointSegment(mid, s.a_m, s.b_m));
      }
      EXPECT_LT(nearest, kCoverToleranceM) << v.id;
      // The stairwell (x 12..15, y 0.1..6) has a closed door and no place.
      EXPECT_FALSE(mid.x() > 12.1 && mid.x() < 14.9 && mid.y() > 0.25 && mid.y() < 5.9) << v.id;
    }
  }
  std::set<std::string> nodes;
  for (const auto& n : map.nodes) nodes.insert(n.id);
  for (const auto& [name, place] : world->description().places) {
    EXPECT_TRUE(nodes.contains(name)) << name;
  }
  EXPECT_EQ(map.ghost_points.empty(), false);  // the glass doors of the seminar room
  ExpectEdgesCollisionFree(*world, map);
  // office_05 and office_10 sit behind closed doors: three parts.
  EXPECT_EQ(GraphParts(map), 3);
}

// Same world and options give the same bytes; another seed other noise.
TEST(MapDerivationTest, DerivationIsDeterministic) {
  const auto world = LoadWorld("expo_hall");
  MapDerivationOptions options;
  const std::string a = RobotMapToYaml(DeriveRobotMap(*world, options));
  const std::string b = RobotMapToYaml(DeriveRobotMap(*world, options));
  EXPECT_EQ(a, b);
  options.seed = 2;
  EXPECT_NE(RobotMapToYaml(DeriveRobotMap(*world, options)), a);
}

// Tape-measure noise and the covariances written with it agree: over many
// seeds, the Mahalanobis distances of the noisy lines (alpha, r) from the exact
// ones follow a chi-square law with 2 degrees of freedom (mean 2, 95 % below
// 5.991), and so do the displacements of the column centres.
TEST(MapDerivationTest, CovariancesMatchTheNoise) {
  const auto lab = LoadWorld("small_lab");
  const core::RobotMap exact = DeriveRobotMap(*lab, Exact());
  std::vector<double> d2;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    MapDerivationOptions options;
    options.seed = seed;
    const core::RobotMap noisy = DeriveRobotMap(*lab, options);
    ASSERT_EQ(noisy.segments.size(), exact.segments.size());
    for (std::size_t i = 0; i < exact.segments.size(); ++i) {
      const core::Line& l = noisy.segments[i].line;
      const Eigen::Vector2d e(core::NormalizeAngle(l.alpha_rad - exact.segments[i].line.alpha_rad),
                              l.r_m - exact.segments[i].line.r_m);
      d2.push_back(e.dot(l.covariance.inverse() * e));
    }
  }
  double mean = 0.0;
  int inside = 0;
  for (double v : d2) {
    mean += v / static_cast<double>(d2.size());
    inside += v < 5.991;
  }
  EXPECT_EQ(d2.size(), 340u);
  EXPECT_NEAR(mean, 2.0, 0.33);  // 3 standard errors of the mean of 340 draws
  EXPECT_NEAR(static_cast<double>(inside) / static_cast<double>(d2.size()), 0.95, 0.036);

  const auto hall = LoadWorld("expo_hall");
  const core::RobotMap hall_exact = DeriveRobotMap(*hall, Exact());
  std::vector<double> p2;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    MapDerivationOptions options;
    options.seed = seed;
    const core::RobotMap noisy = DeriveRobotMap(*hall, options);
    for (std::size_t i = 0; i < hall_exact.points.size(); ++i) {
      const Vec2 e = noisy.points[i].point.position_m - hall_exact.points[i].point.position_m;
      p2.push_back(e.dot(noisy.points[i].point.covariance.inverse() * e));
    }
  }
  double point_mean = 0.0;
  for (double v : p2) point_mean += v / static_cast<double>(p2.size());
  EXPECT_EQ(p2.size(), 80u);
  EXPECT_NEAR(point_mean, 2.0, 0.67);  // 3 standard errors of 80 draws
}

// The shipped worlds/<name>/map.yaml files parse and equal what
// `pavilion map derive <name>` gives with its defaults (seed 1, 5 mm noise):
// regenerate them with that command when a world changes.
TEST(MapDerivationTest, ShippedMapsEqualAFreshDerivation) {
  for (const std::string name : {"expo_hall", "office_floor", "small_lab"}) {
    SCOPED_TRACE(name);
    const std::string path = DataRoot() + "/worlds/" + name + "/map.yaml";
    const core::RobotMap shipped = LoadMapFile(path);
    const auto world = LoadWorld(name);
    const core::RobotMap fresh = DeriveRobotMap(*world, MapDerivationOptions{});
    EXPECT_EQ(shipped.name, name);
    ExpectSameMap(shipped, fresh, pavilion::testing::kMapFilePrecision);
  }
}

// worlds/office_floor/map_corridor_parallel.yaml equals `pavilion map derive
// office_floor --keep-direction 0 --tolerance-deg 5` (docs/map_format.md).
TEST(MapDerivationTest, ShippedCorridorMapEqualsAFreshDerivation) {
  const core::RobotMap shipped =
      LoadMapFile(DataRoot() + "/worlds/office_floor/map_corridor_parallel.yaml");
  const auto world = LoadWorld("office_floor");
  const core::RobotMap fresh = KeepLinesAlongDirection(
      DeriveRobotMap(*world, MapDerivationOptions{}), 0.0, 5.0 * std::numbers::pi / 180.0);
  ExpectSameMap(shipped, fresh, pavilion::testing::kMapFilePrecision);
}

// Only the lines along the direction (either way round) stay; points and
// beacons go; topology stays; bad arguments throw.
TEST(MapDerivationTest, KeepLinesAlongDirectionKeepsOnlyThoseLines) {
  const auto world = LoadWorld("expo_hall");
  const core::RobotMap full = DeriveRobotMap(*world, Exact());
  ASSERT_FALSE(full.points.empty());
  ASSERT_FALSE(full.beacons.empty());
  constexpr double kToleranceRad = 0.1;
  for (const double direction_rad : {0.0, 0.5 * std::numbers::pi, 2.0}) {
    SCOPED_TRACE(direction_rad);
    // The same filter a half turn round.
    const core::RobotMap kept = KeepLinesAlongDirection(full, direction_rad, kToleranceRad);
    const core::RobotMap flipped =
        KeepLinesAlongDirection(full, direction_rad - std::numbers::pi, kToleranceRad);
    EXPECT_EQ(kept.segments.size(), flipped.segments.size());
    const auto off = [&](const core::Line& l) {
      const double d =
          std::abs(core::NormalizeAngle(l.alpha_rad + 0.5 * std::numbers::pi - direction_rad));
      return std::min(d, std::numbers::pi - d);
    };
    std::size_t expected = 0;
    for (const auto& s : full.segments) expected += off(s.line) <= kToleranceRad;
    EXPECT_EQ(kept.segments.size(), expected);
    for (const auto& s : kept.segments) EXPECT_LE(off(s.line), kToleranceRad) << s.id;
    EXPECT_TRUE(kept.points.empty());
    EXPECT_TRUE(kept.beacons.empty());
    EXPECT_EQ(kept.nodes.size(), full.nodes.size());
    EXPECT_EQ(kept.edges.size(), full.edges.size());
    EXPECT_EQ(kept.ghost_points.size(), full.ghost_points.size());
    EXPECT_NE(kept.description.find("Kept only the lines"), std::string::npos);
    EXPECT_NO_THROW(core::ValidateRobotMap(kept));
  }
  // expo_hall's outline has walls along x and along y.
  EXPECT_GT(KeepLinesAlongDirection(full, 0.0, kToleranceRad).segments.size(), 0u);
  EXPECT_LT(KeepLinesAlongDirection(full, 0.0, kToleranceRad).segments.size(),
            full.segments.size());
  EXPECT_THROW(KeepLinesAlongDirection(full, 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(KeepLinesAlongDirection(full, 0.0, 2.0), std::invalid_argument);
  EXPECT_THROW(KeepLinesAlongDirection(full, std::nan(""), 0.1), std::invalid_argument);
}

// A room without places (every free cell counts as reachable, with a warning):
// its inner faces are mapped, a retro-reflective box becomes a beacon at its
// centre and not lines, a bench below the beam gets ghost points.
TEST(MapDerivationTest, BareRoomWithReflectorAndBench) {
  const std::string path = pavilion::testing::WriteFile(
      pavilion::testing::TestDir(), "world.yaml",
      "kind: world\n"
      "name: bare_room\n"
      "materials:\n"
      "  concrete: {friction: 0.8}\n"
      "  foil: {friction: 0.5, laser: retro_reflective}\n"
      "floor: {min: [-5, -4], max: [5, 4], material: concrete}\n"
      "walls:\n"
      "  - {id: room, points: [[-3, -2], [3, -2], [3, 2], [-3, 2]], closed: true, thickness: 0.2,\n"
      "     height: 2, material: concrete}\n"
      "boxes:\n"
      "  - {id: marker, pose: [1, 0.5, 0], size: [0.1, 0.1, 1], material: foil}\n"
      "  - {id: bench, pose: [-1, -1, 0], size: [1.2, 0.4, 0.4], material: concrete}\n");
  sim::World world(LoadWorldFile(path), {});
  std::vector<std::string> warnings;
  const core::RobotMap map = DeriveRobotMap(world, Exact(), &warnings);
  EXPECT_FALSE(warnings.empty());
  const std::vector<LineView> lines = Lines(map);
  const std::vector<Vec2> room = {{-3, -2}, {3, -2}, {3, 2}, {-3, 2}};
  const core::PlanarSection beam = world.SectionAt(kBeamHeightM);
  int inner = 0;
  for (const auto& s : beam.segments) {
    const std::string& id = beam.elements[s.element].id;
    if (id == "marker") {
      EXPECT_EQ(OnLine(lines, s.a_m, s.b_m), 0);
    } else if (InPolygon(room, 0.5 * (s.a_m + s.b_m) + 0.05 * OutwardNormal(s.a_m, s.b_m))) {
      EXPECT_EQ(Covering(lines, s.a_m, s.b_m), 1);
      ++inner;
    }
  }
  EXPECT_EQ(inner, 4);
  ASSERT_EQ(map.beacons.size(), 1u);
  EXPECT_EQ(map.beacons[0].id, "marker");
  EXPECT_LT((map.beacons[0].point.position_m - Vec2(1, 0.5)).norm(), 1e-6);
  int on_bench = 0;
  for (const auto& g : map.ghost_points) {
    on_bench += std::abs(g.position_m.x() + 1.0) <= 0.6 + 1e-6 &&
                std::abs(g.position_m.y() + 1.0) <= 0.2 + 1e-6;
  }
  EXPECT_GE(on_bench, 10);  // 3.2 m of outline at most 0.25 m apart
  ExpectEdgesCollisionFree(world, map);
}

// Bad options are refused naming the field.
TEST(MapDerivationTest, RejectsBadOptions) {
  MapDerivationOptions o;
  o.low_height_m = 0.6;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = MapDerivationOptions{};
  o.ghost_spacing_m = 0.8;  // robots would fit between ghost points
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = MapDerivationOptions{};
  o.noise_sigma_m = -0.001;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::scenarios
