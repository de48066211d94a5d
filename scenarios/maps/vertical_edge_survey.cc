#include "scenarios/maps/vertical_edge_survey.h"

#include <cmath>
#include <numbers>
#include <set>
#include <stdexcept>
#include <utility>

namespace pavilion::scenarios {
namespace {

using Vec2 = Eigen::Vector2d;

// Corners of the two cuts closer than this are one vertical edge (m).
constexpr double kSameCornerM = 1e-3;

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

bool Excluded(const core::PlanarSection& s, int element, const std::set<std::string>& doors) {
  const core::SectionElement& e = s.elements[static_cast<std::size_t>(element)];
  return e.dynamic || doors.count(e.id) > 0;
}

// Candidate corners of a cut: the vertices of the solids' outlines and the
// points where outlines of different elements cross (the concave corner
// where one wall runs into another is a vertex of neither), with the element
// the first face belongs to.
std::vector<std::pair<Vec2, int>> Candidates(const core::PlanarSection& s,
                                             const std::set<std::string>& doors) {
  std::vector<std::pair<Vec2, int>> out;
  const auto& segs = s.segments;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    if (Excluded(s, segs[i].element, doors)) continue;
    out.emplace_back(segs[i].b_m, segs[i].element);
    const Vec2 d1 = segs[i].b_m - segs[i].a_m;
    for (std::size_t j = i + 1; j < segs.size(); ++j) {
      if (segs[j].element == segs[i].element || Excluded(s, segs[j].element, doors)) continue;
      const Vec2 d2 = segs[j].b_m - segs[j].a_m;
      const double den = Cross(d1, d2);
      if (std::abs(den) < 1e-12) continue;
      const Vec2 w = segs[j].a_m - segs[i].a_m;
      const double t = Cross(w, d2) / den;
      const double u = Cross(w, d1) / den;
      if (t > 1e-9 && t < 1.0 - 1e-9 && u > 1e-9 && u < 1.0 - 1e-9) {
        out.emplace_back(segs[i].a_m + t * d1, segs[i].element);
      }
    }
  }
  return out;
}

// A cut with each element's segments and bounding box, to tell quickly
// whether a point lies inside a solid.
class Cut {
 public:
  Cut(const core::PlanarSection& s, const std::set<std::string>& doors) : s_(s) {
    segments_.resize(s.elements.size());
    lo_.assign(s.elements.size(), Vec2::Constant(1e300));
    hi_.assign(s.elements.size(), Vec2::Constant(-1e300));
    for (const core::SectionSegment& seg : s.segments) {
      const auto e = static_cast<std::size_t>(seg.element);
      if (Excluded(s, seg.element, doors)) continue;
      segments_[e].push_back(&seg);
      lo_[e] = lo_[e].cwiseMin(seg.a_m).cwiseMin(seg.b_m);
      hi_[e] = hi_[e].cwiseMax(seg.a_m).cwiseMax(seg.b_m);
    }
  }

  const core::PlanarSection& section() const { return s_; }

  // Inside a circle, or inside an element's closed outline (odd crossing
  // count of a ray towards +x).
  bool InsideSolid(const Vec2& p) const {
    for (const core::SectionCircle& c : s_.circles) {
      if ((p - c.center_m).norm() < c.radius_m) return true;
    }
    for (std::size_t e = 0; e < segments_.size(); ++e) {
      if (segments_[e].empty() || (p.array() < lo_[e].array()).any() ||
          (p.array() > hi_[e].array()).any()) {
        continue;
      }
      int crossings = 0;
      for (const core::SectionSegment* seg : segments_[e]) {
        const Vec2& a = seg->a_m;
        const Vec2& b = seg->b_m;
        if ((a.y() > p.y()) == (b.y() > p.y())) continue;
        const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
        if (x > p.x()) ++crossings;
      }
      if (crossings % 2 == 1) return true;
    }
    return false;
  }

 private:
  const core::PlanarSection& s_;
  std::vector<std::vector<const core::SectionSegment*>> segments_;
  std::vector<Vec2> lo_, hi_;
};

// The free sector around a point of a cut, probed on a circle of `radius`:
// its angular extent (rad) and its mean direction (unit; zero when none).
struct FreeSector {
  double extent_rad = 0.0;
  Vec2 direction = Vec2::Zero();
};

constexpr int kProbes = 72;  // every 5 deg

FreeSector FreeAround(const Cut& cut, const Vec2& p, double radius) {
  FreeSector out;
  int free = 0;
  Vec2 sum = Vec2::Zero();
  for (int k = 0; k < kProbes; ++k) {
    const double a = 2.0 * std::numbers::pi * (k + 0.5) / kProbes;
    const Vec2 u(std::cos(a), std::sin(a));
    if (cut.InsideSolid(p + radius * u)) continue;
    ++free;
    sum += u;
  }
  out.extent_rad = 2.0 * std::numbers::pi * free / kProbes;
  if (sum.norm() > 1e-9) out.direction = sum.normalized();
  return out;
}

// A vertical edge at `p` in one cut: the free sector differs from a flat
// face's half circle by at least the turn (a convex corner leaves 270 deg
// free, a concave one 90 deg) and is not the whole circle.
bool CornerIn(const FreeSector& f, double min_turn) {
  return f.extent_rad > 0.0 && f.extent_rad < 2.0 * std::numbers::pi &&
         std::abs(f.extent_rad - std::numbers::pi) >= min_turn;
}

}  // namespace

void VerticalEdgeSurveyOptions::Validate() const {
  if (!(min_turn_rad > 0.0 && min_turn_rad < std::numbers::pi)) {
    throw std::invalid_argument("VerticalEdgeSurveyOptions.min_turn_rad must be in (0, pi)");
  }
  if (!(low_m > 0.0 && low_m < high_m && high_m <= 10.0)) {
    throw std::invalid_argument(
        "VerticalEdgeSurveyOptions.low_m, high_m must satisfy 0 < low_m < high_m <= 10");
  }
  if (!(probe_m > 0.0 && probe_m <= 0.5)) {
    throw std::invalid_argument("VerticalEdgeSurveyOptions.probe_m must be in (0, 0.5] m");
  }
}

std::vector<SurveyedEdge> SurveyVerticalEdges(const sim::World& world,
                                              const VerticalEdgeSurveyOptions& options) {
  options.Validate();
  std::set<std::string> doors;  // excluded elements
  if (!options.doors) {
    for (const sim::Door& d : world.description().doors) doors.insert(d.id);
  }
  const core::PlanarSection low = world.StaticSectionAt(options.low_m);
  const core::PlanarSection high = world.StaticSectionAt(options.high_m);
  const Cut low_cut(low, doors);
  const Cut high_cut(high, doors);
  std::vector<SurveyedEdge> out;
  for (const auto& [p, element] : Candidates(low, doors)) {
    bool seen = false;  // two faces' shared vertex is listed twice
    for (const SurveyedEdge& e : out) seen = seen || (e.position_m - p).norm() < kSameCornerM;
    if (seen) continue;
    const FreeSector at_low = FreeAround(low_cut, p, options.probe_m);
    if (!CornerIn(at_low, options.min_turn_rad)) continue;
    // The same corner, facing the same way, in the upper cut: the edge spans the band.
    const FreeSector at_high = FreeAround(high_cut, p, options.probe_m);
    if (!CornerIn(at_high, options.min_turn_rad) ||
        std::abs(at_high.extent_rad - at_low.extent_rad) > 1e-9 ||
        at_high.direction.dot(at_low.direction) < std::cos(options.min_turn_rad)) {
      continue;
    }
    out.push_back({p, at_low.direction, low.elements[static_cast<std::size_t>(element)].id});
  }
  return out;
}

}  // namespace pavilion::scenarios
