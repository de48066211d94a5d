#include "core/features/scene_description.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "core/features/multi_segment_line.h"
#include "core/types/pose2.h"

// Reading of §3.5 (the PDF text extraction garbles the formulas):
//
// (3.24) lambda_Ei = s_i^T d_i / |d_i|: s_i is the unit normal (cos a_i, sin a_i)
//        rotated by +pi/2 (counterclockwise scan) or -pi/2 (clockwise), i.e. the
//        direction in which the beam sweeps along S_i; d_i is along the line,
//        so lambda is +1 or -1.
// (3.25) d_i = E_i - C_i,i+1. For the pair (S_i, S_i+1), E_i is the last
//        endpoint of S_i and E_i+1 the first endpoint of S_i+1 (the adjacent
//        endpoints). lambda = -1: the sweep over E_i heads towards C.
// (3.26) [x; y] = 1 / sin(a_i+1 - a_i) [sin a_i+1, -sin a_i; -cos a_i+1, cos a_i]
//        [r_i; r_i+1], the intersection of the two Hessian lines.
// (3.31)-(3.36) are read as a priority chain, each symbol excluding all
//        earlier ones (the "and not X" of each rule):
//        G <=> l_Si = l_Si+1 and d_EiEi+1 > w_r
//        H <=> lambda_i = lambda_i+1
//        O <=> lambda_i = 1 or r_C > R_S
//        A <=> d_EiEi+1 > w_r
//        c <=> 0 < da < pi or da < -pi, da = a_i+1 - a_i, a in (-pi, pi]
//        e <=> otherwise.
//        l_Si = l_Si+1 is decided by the chi^2 test of eq. 3.16 at alpha.
// Cases the thesis leaves open, decided here:
//  - same supporting line and d_EiEi+1 <= w_r: no symbol (a crack narrower
//    than the robot is no topological key point, and C is undefined);
//  - (anti)parallel, distinct lines (|sin da| ~ 0): C lies at infinity, so
//    r_C = inf > R_S; in the limit of almost parallel lines lambda_i =
//    lambda_i+1 for equal directions (-> H, a depth jump between parallel
//    walls) and lambda_i = -lambda_i+1 for opposite ones (-> O, e.g. a
//    corridor ahead), whichever side C tends to;
//  - E_i at C (|d_i| < 1 nm): the beam passed over the corner,
//    lambda_i = -1, lambda_i+1 = +1;
//  - clockwise scans mirror the scene, so da changes sign in the c/e test.
// (3.37) w_i = max(|C_li|, |C_li+1|), |C| the determinant: "the weight is given
//        by the more uncertain line". The determinant is a probability mass
//        (an uncertainty), yet eq. 3.39 calls sum(w_i v_i)/sum(w_i) the vector
//        of highest confidence and the text calls w_i a confidence measure
//        ("the least individual confidence of its constituting segments"). We
//        therefore keep the selected determinant (SceneSymbol::determinant)
//        and use its inverse as the confidence weight w_i, so that v_h leans
//        towards well-determined features and v_l towards uncertain ones, as
//        §3.5 describes their use.
// (3.38) gaps: the determinant is |C_li|, the first segment's line.
// (3.39) v_h = sum(w_i v_i) / sum(w_i); (3.40) v_l = sum(v_i / w_i) / sum(1 / w_i).
//        Both are weighted means of unit vectors, not renormalized.

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kParallelSin = 1e-9;
constexpr double kMinDeterminant = 1e-300;
// |d_i| below this counts as E_i = C (rounding of eq. 3.26), m.
constexpr double kAtIntersection_m = 1e-9;

// The same line with r >= 0 (the sensor-frame convention of ExtractLines).
Line NonNegative(const Line& line) {
  if (line.r_m >= 0.0) return line;
  Line flipped = line;
  flipped.alpha_rad = NormalizeAngle(line.alpha_rad + kPi);
  flipped.r_m = -line.r_m;
  flipped.covariance(0, 1) = -line.covariance(0, 1);
  flipped.covariance(1, 0) = -line.covariance(1, 0);
  return flipped;
}

Eigen::Vector2d ScanDirection(const Line& line, bool counterclockwise) {
  const double sign = counterclockwise ? 1.0 : -1.0;
  return sign * Eigen::Vector2d(-std::sin(line.alpha_rad), std::cos(line.alpha_rad));
}

Eigen::Vector2d UnitOrX(const Eigen::Vector2d& v) {
  const double n = v.norm();
  return n > 0.0 && std::isfinite(n) ? Eigen::Vector2d(v / n) : Eigen::Vector2d::UnitX();
}

double SafeDeterminant(const Eigen::Matrix2d& c) {
  const double det = c.determinant();
  return std::isfinite(det) ? std::max(det, kMinDeterminant) : det;
}

struct Keyed {
  double key;
  SceneSymbol symbol;
};

// Classifies the pair (S_i, S_i+1); false when no symbol applies.
bool ClassifyPair(const Segment& first, const Segment& second, const SceneOptions& options,
                  double gate, SceneSymbol* out) {
  const Line li = NonNegative(first.line);
  const Line lj = NonNegative(second.line);
  const Eigen::Vector2d e_i = first.last_endpoint.position_m;
  const Eigen::Vector2d e_j = second.first_endpoint.position_m;
  const double d_ee = (e_j - e_i).norm();
  const Eigen::Vector2d midpoint = 0.5 * (e_i + e_j);
  SceneSymbol& s = *out;
  const double inf = std::numeric_limits<double>::infinity();
  s.intersection_m = Eigen::Vector2d::Constant(inf);

  // Eq. 3.31, gap: same supporting line (chi^2 test, eq. 3.16) and d > w_r.
  if (LineMahalanobis2(li, lj) <= gate) {
    if (!(d_ee > options.robot_size_m)) return false;
    s.symbol = 'G';
    s.determinant = SafeDeterminant(li.covariance);  // eq. 3.38
    s.location_m = midpoint;
    return true;
  }

  const double da = lj.alpha_rad - li.alpha_rad;
  const double sin_da = std::sin(da);
  double r_c = inf;
  double lambda_i = -1.0;
  double lambda_j = 1.0;
  if (std::abs(sin_da) < kParallelSin) {
    // C at infinity; the limit of almost parallel lines (see the note at the top of this file).
    lambda_j = std::cos(da) > 0.0 ? -1.0 : 1.0;
  } else {
    // Eq. 3.26.
    Eigen::Matrix2d m;
    m << std::sin(lj.alpha_rad), -std::sin(li.alpha_rad), -std::cos(lj.alpha_rad),
        std::cos(li.alpha_rad);
    const Eigen::Vector2d c = m * Eigen::Vector2d(li.r_m, lj.r_m) / sin_da;
    s.intersection_m = c;
    r_c = c.norm();
    // Eqs. 3.24-3.25.
    const Eigen::Vector2d d_i = e_i - c;
    const Eigen::Vector2d d_j = e_j - c;
    const double pi_ = ScanDirection(li, options.counterclockwise).dot(d_i);
    const double pj = ScanDirection(lj, options.counterclockwise).dot(d_j);
    if (d_i.norm() > kAtIntersection_m) lambda_i = pi_ >= 0.0 ? 1.0 : -1.0;
    if (d_j.norm() > kAtIntersection_m) lambda_j = pj >= 0.0 ? 1.0 : -1.0;
  }
  s.lambda_first = lambda_i;
  s.lambda_second = lambda_j;
  s.determinant = std::max(SafeDeterminant(li.covariance), SafeDeterminant(lj.covariance));
  s.location_m = midpoint;

  if (lambda_i == lambda_j) {  // eq. 3.32
    s.symbol = 'H';
  } else if (lambda_i == 1.0 || r_c > options.perception_radius_m) {  // eq. 3.33
    s.symbol = 'O';
  } else if (d_ee > options.robot_size_m) {  // eq. 3.34
    s.symbol = 'A';
  } else {
    // Eqs. 3.35-3.36; a clockwise scan mirrors the scene.
    const double delta = options.counterclockwise ? da : -da;
    const bool concave = (delta > 0.0 && delta < kPi) || delta < -kPi;
    s.symbol = concave ? 'c' : 'e';
    s.location_m = s.intersection_m;
  }
  return true;
}

}  // namespace

void SceneOptions::Validate() const {
  if (!(perception_radius_m > 0.0)) {
    throw std::invalid_argument("SceneOptions.perception_radius_m must be > 0");
  }
  if (!(robot_size_m >= 0.0) || !std::isfinite(robot_size_m)) {
    throw std::invalid_argument("SceneOptions.robot_size_m must be finite and >= 0");
  }
  if (!(significance > 0.0 && significance < 1.0)) {
    throw std::invalid_argument("SceneOptions.significance must be in (0, 1)");
  }
}

SceneDescription DescribeScene(const std::vector<Segment>& segments,
                               const std::vector<Beacon>& beacons, const SceneOptions& options) {
  options.Validate();
  const double gate = -2.0 * std::log(1.0 - options.significance);  // chi^2(2) quantile
  std::vector<Keyed> keyed;
  const int n = static_cast<int>(segments.size());
  const int pairs = options.closed && n >= 2 ? n : n - 1;
  for (int i = 0; i < pairs; ++i) {
    const int j = (i + 1) % n;
    const Segment& a = segments[static_cast<size_t>(i)];
    const Segment& b = segments[static_cast<size_t>(j)];
    SceneSymbol symbol;
    if (!ClassifyPair(a, b, options, gate, &symbol)) continue;
    symbol.first_segment = i;
    symbol.second_segment = j;
    // Position in the scan: between the two segments' adjacent readings.
    const double key = j > i ? 0.5 * (a.last_index + b.first_index) : a.last_index + 0.5;
    keyed.push_back({key, symbol});
  }
  if (options.include_beacons) {
    for (int k = 0; k < static_cast<int>(beacons.size()); ++k) {
      const Beacon& beacon = beacons[static_cast<size_t>(k)];
      SceneSymbol symbol;
      symbol.symbol = 'B';
      symbol.beacon = k;
      symbol.determinant = SafeDeterminant(beacon.polar_covariance);
      symbol.location_m = beacon.Cartesian().position_m;
      symbol.intersection_m = symbol.location_m;
      keyed.push_back({0.5 * (beacon.first_index + beacon.last_index), symbol});
    }
  }
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const Keyed& x, const Keyed& y) { return x.key < y.key; });

  SceneDescription scene;
  double sum_w = 0.0;
  double sum_inv_w = 0.0;
  Eigen::Vector2d sum_wv = Eigen::Vector2d::Zero();
  Eigen::Vector2d sum_v_over_w = Eigen::Vector2d::Zero();
  for (Keyed& k : keyed) {
    SceneSymbol& s = k.symbol;
    s.direction = UnitOrX(s.location_m);
    s.weight = 1.0 / s.determinant;  // confidence, see the note on eq. 3.37
    sum_w += s.weight;
    sum_inv_w += s.determinant;
    sum_wv += s.weight * s.direction;        // eq. 3.39
    sum_v_over_w += s.direction / s.weight;  // eq. 3.40
    scene.symbols.push_back(s.symbol);
    scene.elements.push_back(s);
  }
  if (sum_w > 0.0 && std::isfinite(sum_w)) scene.highest_confidence = sum_wv / sum_w;
  if (sum_inv_w > 0.0 && std::isfinite(sum_inv_w)) {
    scene.least_confidence = sum_v_over_w / sum_inv_w;
  }
  return scene;
}

std::string SceneDescription::ToString() const {
  std::ostringstream out;
  out << '"' << symbols << '"' << '\n';
  double sum_w = 0.0;
  for (const SceneSymbol& s : elements) sum_w += s.weight;
  char buffer[160];
  for (const SceneSymbol& s : elements) {
    std::snprintf(buffer, sizeof(buffer), "  %c  w=%.3f  bearing=%7.2f deg  |C|=%.3e\n", s.symbol,
                  sum_w > 0.0 ? s.weight / sum_w : 0.0,
                  std::atan2(s.direction.y(), s.direction.x()) * 180.0 / kPi, s.determinant);
    out << buffer;
  }
  std::snprintf(buffer, sizeof(buffer), "  v_h=(%.3f, %.3f)  v_l=(%.3f, %.3f)\n",
                highest_confidence.x(), highest_confidence.y(), least_confidence.x(),
                least_confidence.y());
  out << buffer;
  return out.str();
}

}  // namespace pavilion::core
