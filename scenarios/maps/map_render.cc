#include "scenarios/maps/map_render.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "scenarios/output/canvas.h"
#include "sim/render/top_down_view.h"

namespace pavilion::scenarios {
namespace {

using Vec2 = Eigen::Vector2d;

// Colours of the map items (docs/map_format.md, "Rendering").
constexpr Rgb kLineColour{20, 60, 170};       // segments, multi-segment lines
constexpr Rgb kInfiniteColour{90, 120, 210};  // infinite lines
constexpr Rgb kPointColour{0, 130, 60};       // columns
constexpr Rgb kVerticalEdgeColour{0, 0, 0};   // vertical edges: black crosses (thesis Fig. 4.2)
constexpr double kCrossHalfPx = 4.0;          // a vertical edge's cross: half its arm length
constexpr Rgb kBeaconColour{235, 170, 0};
constexpr Rgb kEdgeColour{240, 150, 90};
constexpr Rgb kViaColour{110, 110, 130};
constexpr Rgb kStationColour{210, 30, 30};
constexpr Rgb kGhostColour{200, 0, 200};
constexpr Rgb kBlack{0, 0, 0};
// How light the world underneath is drawn: 0 unchanged, 1 white.
constexpr double kWorldFade = 0.6;
constexpr double kTickPx = 7.0;  // visibility tick length

// A segment with a tick from its middle towards the side it is seen from.
void DrawSegment(Canvas* canvas, const core::Line& line, const Vec2& a, const Vec2& b) {
  canvas->Line(a, b, kLineColour, 2.0);
  const Vec2 mid = canvas->ToPx(0.5 * (a + b));
  const Vec2 n = line.normal();
  const Vec2 visible_px(-n.x(), n.y());  // -n in pixel axes (y down)
  canvas->LinePx(mid, mid + kTickPx * visible_px, kLineColour, 1.5);
}

struct Extent {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  void Add(const Vec2& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool empty() const { return !(lo.x() <= hi.x()); }
};

Extent MapExtent(const core::RobotMap& map) {
  Extent e;
  for (const auto& s : map.segments) {
    e.Add(s.first_endpoint.position_m);
    e.Add(s.second_endpoint.position_m);
  }
  for (const auto& m : map.multi_segment_lines) {
    for (const auto& [a, b] : m.segments) {
      e.Add(a.position_m);
      e.Add(b.position_m);
    }
  }
  for (const auto& p : map.points) {
    e.Add(p.point.position_m.array() - p.radius_m);
    e.Add(p.point.position_m.array() + p.radius_m);
  }
  for (const auto& b : map.beacons) e.Add(b.point.position_m);
  for (const auto& n : map.nodes) e.Add(n.pose.translation());
  for (const auto& g : map.ghost_points) e.Add(g.position_m);
  for (const auto& l : map.lines) e.Add(l.line.r_m * l.line.normal());  // foot of the normal
  return e;
}

// The picture's area lo-hi (m) and its background: the world from above,
// faded to grey, or white around the map's extent.
core::RgbImage Background(const core::RobotMap& map, const sim::World* world, int width,
                          double margin, Vec2* lo, Vec2* hi) {
  core::RgbImage image;
  if (world != nullptr) {
    const auto& floor = world->description().floor;
    *lo = floor.min_m.array() - margin;
    *hi = floor.max_m.array() + margin;
    sim::TopDownOptions view;
    view.width_px = width;
    view.margin_m = margin;
    view.section_height_m = map.beam_height_m;
    view.draw_places = false;
    image = sim::RenderTopDown(*world, {}, view);
    for (std::size_t i = 0; i + 2 < image.pixels.size(); i += 3) {
      const double grey =
          0.299 * image.pixels[i] + 0.587 * image.pixels[i + 1] + 0.114 * image.pixels[i + 2];
      const auto v =
          static_cast<std::uint8_t>(std::lround(255.0 - (255.0 - grey) * (1.0 - kWorldFade)));
      image.pixels[i] = image.pixels[i + 1] = image.pixels[i + 2] = v;
    }
  } else {
    Extent e = MapExtent(map);
    if (e.empty()) e.Add(Vec2::Zero());
    const Vec2 centre = 0.5 * (e.lo + e.hi);
    const Vec2 half = (0.5 * (e.hi - e.lo)).cwiseMax(Vec2(0.5, 0.5));
    *lo = centre - half - Vec2(margin, margin);
    *hi = centre + half + Vec2(margin, margin);
  }
  return image;
}

// Infinite lines: across the drawn area lo-hi, ticked every 80 px.
void DrawInfiniteLines(const core::RobotMap& map, const Vec2& lo, const Vec2& hi, Canvas* canvas) {
  for (const auto& l : map.lines) {
    const Vec2 n = l.line.normal(), dir(-n.y(), n.x());
    const Vec2 foot = l.line.r_m * n;
    const double reach = (hi - lo).norm() + foot.norm();
    const Vec2 a = foot - reach * dir, b = foot + reach * dir;
    canvas->Line(a, b, kInfiniteColour, 1.0);
    const double step_m = 80.0 / canvas->scale();
    for (double s = -reach; s <= reach; s += step_m) {
      const Vec2 p = canvas->ToPx(foot + s * dir);
      canvas->LinePx(p, p + kTickPx * Vec2(-n.x(), n.y()), kInfiniteColour, 1.0);
    }
  }
}

// Edges, then ghost points as crosses.
void DrawEdgesAndGhosts(const core::RobotMap& map, Canvas* canvas) {
  for (const auto& e : map.edges) {
    const core::MapNode* from = nullptr;
    const core::MapNode* to = nullptr;
    for (const auto& n : map.nodes) {
      if (n.id == e.from) from = &n;
      if (n.id == e.to) to = &n;
    }
    if (from != nullptr && to != nullptr) {
      canvas->Line(from->pose.translation(), to->pose.translation(), kEdgeColour, 1.0);
    }
  }
  for (const auto& g : map.ghost_points) {
    const Vec2 q = canvas->ToPx(g.position_m);
    canvas->LinePx(q - Vec2(2.5, 2.5), q + Vec2(2.5, 2.5), kGhostColour, 1.0);
    canvas->LinePx(q - Vec2(2.5, -2.5), q + Vec2(2.5, -2.5), kGhostColour, 1.0);
  }
}

// Segments and multi-segment lines with their visibility ticks, points, beacons.
void DrawFeatures(const core::RobotMap& map, Canvas* canvas) {
  for (const auto& s : map.segments) {
    DrawSegment(canvas, s.line, s.first_endpoint.position_m, s.second_endpoint.position_m);
  }
  for (const auto& m : map.multi_segment_lines) {
    for (const auto& [a, b] : m.segments) DrawSegment(canvas, m.line, a.position_m, b.position_m);
  }
  for (const auto& p : map.points) {
    const Vec2 q = canvas->ToPx(p.point.position_m);
    if (p.radius_m == 0.0) {
      canvas->CrossPx(q, kCrossHalfPx, kVerticalEdgeColour, 1.5);
      continue;
    }
    canvas->RingPx(q, std::max(3.0, p.radius_m * canvas->scale()), kPointColour, 2.0);
    canvas->DiscPx(q, 2.0, kPointColour);
  }
  for (const auto& b : map.beacons) {
    canvas->DiamondPx(canvas->ToPx(b.point.position_m), 7.0, kBeaconColour, kBlack);
  }
}

// Stations as squares with their heading, via nodes as discs.
void DrawNodes(const core::RobotMap& map, Canvas* canvas) {
  for (const auto& n : map.nodes) {
    const Vec2 q = canvas->ToPx(n.pose.translation());
    if (n.station) {
      canvas->SquarePx(q, 4.0, kStationColour);
      const Vec2 heading(std::cos(n.pose.theta_rad), -std::sin(n.pose.theta_rad));
      canvas->LinePx(q, q + 11.0 * heading, kStationColour, 2.0);
    } else {
      canvas->DiscPx(q, 3.0, kViaColour);
    }
  }
}

}  // namespace

std::vector<LegendEntry> MapLegend(const core::RobotMap& map) {
  const auto any_point = [&](bool edge) {
    return std::any_of(map.points.begin(), map.points.end(),
                       [&](const core::MapPoint& p) { return (p.radius_m == 0.0) == edge; });
  };
  const auto any_node = [&](bool station) {
    return std::any_of(map.nodes.begin(), map.nodes.end(),
                       [&](const core::MapNode& n) { return n.station == station; });
  };
  std::vector<LegendEntry> legend;
  const auto add = [&](bool present, LegendEntry e) {
    if (present) legend.push_back(std::move(e));
  };
  add(!map.segments.empty() || !map.multi_segment_lines.empty(),
      {"map line", LegendSymbol::kTickedLine, kLineColour, {}, 2.0});
  add(!map.lines.empty(), {"infinite line", LegendSymbol::kLine, kInfiniteColour, {}, 1.0});
  add(any_point(true), {"vertical edge", LegendSymbol::kCross, kVerticalEdgeColour});
  add(any_point(false), {"column", LegendSymbol::kRing, kPointColour, {}, 2.0});
  add(!map.beacons.empty(), {"beacon", LegendSymbol::kDiamond, kBlack, kBeaconColour});
  add(any_node(true), {"station", LegendSymbol::kSquare, kStationColour, kStationColour});
  add(any_node(false), {"via node", LegendSymbol::kDisc, kViaColour, kViaColour});
  add(!map.edges.empty(), {"graph edge", LegendSymbol::kLine, kEdgeColour, {}, 1.0});
  add(!map.ghost_points.empty(), {"ghost point", LegendSymbol::kDiagonalCross, kGhostColour});
  return legend;
}

core::RgbImage RenderRobotMap(const core::RobotMap& map, const sim::World* world,
                              const MapRenderOptions& options) {
  const int width = std::clamp(options.width_px, 50, 8000);
  const double margin = std::max(0.0, options.margin_m);
  Vec2 lo, hi;
  core::RgbImage image = Background(map, world, width, margin, &lo, &hi);
  const double scale = width / (hi.x() - lo.x());
  const int height = std::max(1, static_cast<int>(std::lround((hi.y() - lo.y()) * scale)));
  if (image.width != width || image.height != height) {
    image = core::RgbImage(width, height, 255, 255, 255);
  }
  Canvas canvas(&image, {lo.x(), hi.y()}, scale);
  DrawInfiniteLines(map, lo, hi, &canvas);
  DrawEdgesAndGhosts(map, &canvas);
  DrawFeatures(map, &canvas);
  DrawNodes(map, &canvas);
  AnnotateFigure(&image, scale, MapLegend(map));
  return image;
}

}  // namespace pavilion::scenarios
