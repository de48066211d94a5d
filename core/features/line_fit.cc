#include "core/features/line_fit.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

namespace pavilion::core {
namespace {

// The orientation of the fit is undefined when the weighted scatter about the
// mean vanishes relative to the weighted squared ranges (coincident points), or
// when the scatter is isotropic ((D^2 + N^2) vanishes relative to its square).
constexpr double kDegenerateRelativeScatter = 1e-20;
constexpr double kIsotropicRelativeScatter = 1e-24;

// The line and its covariance from the window-level quantities: weighted
// means, N and D of eq. 3.4, and the three sums of eqs. 3.8-3.10.
struct FitCore {
  double sum_w = 0.0, xw = 0.0, yw = 0.0, num = 0.0, den = 0.0, scatter = 0.0, sum_wrho2 = 0.0;
};

// alpha and r (eqs. 3.4-3.5) with the r >= 0 convention applied later.
bool Degenerate(const FitCore& c) {
  const double nd2 = c.num * c.num + c.den * c.den;
  return !(c.scatter > kDegenerateRelativeScatter * c.sum_wrho2) ||
         !(nd2 > kIsotropicRelativeScatter * c.scatter * c.scatter);
}

// Sets `line` (the caller's, so the result is written in place, not copied).
void Finish(double alpha, double r, double s_aa, double s_rr, double s_ar, Line& line) {
  // r >= 0 convention (eq. B.4, the line is visible from the sensor): flipping
  // (alpha, r) -> (alpha + pi, -r) negates the r row and column of the covariance.
  if (r < 0.0) {
    r = -r;
    alpha += std::numbers::pi;
    s_ar = -s_ar;
  }
  // alpha is in (-pi/2, 3pi/2] here: NormalizeAngle's subtraction of 2 pi,
  // inline (exact for alpha > pi, Sterbenz).
  line.alpha_rad = alpha > std::numbers::pi ? alpha - 2.0 * std::numbers::pi : alpha;
  line.r_m = r;
  line.covariance << s_aa, s_ar, s_ar, s_rr;
}

// atan2 to within 1e-7 rad (Abramowitz & Stegun 4.4.49: a degree-15 odd
// polynomial for atan on [-1, 1], then octant reduction; 4e-8 measured).
double FastAtan2(double y, double x) {
  const double ax = std::abs(x);
  const double ay = std::abs(y);
  if (ax == 0.0 && ay == 0.0) return std::atan2(y, x);  // signed zeros as std::atan2
  const bool swap = ay > ax;
  const double t = swap ? ax / ay : ay / ax;
  // Estrin's scheme in t^2: four independent pairs, then two levels.
  const double t2 = t * t;
  const double t4 = t2 * t2;
  const double p01 = 0.9999993329 - 0.3332985605 * t2;
  const double p23 = 0.1994653599 - 0.1390853351 * t2;
  const double p45 = 0.0964200441 - 0.0559098861 * t2;
  const double p67 = 0.0218612288 - 0.0040540580 * t2;
  double a = t * ((p01 + p23 * t4) + (p45 + p67 * t4) * (t4 * t4));
  if (swap) a = 0.5 * std::numbers::pi - a;
  if (x < 0.0) a = std::numbers::pi - a;
  return std::copysign(a, y);
}

}  // namespace

std::optional<FitPoint> PrepareFitPoint(const PolarPoint& p) {
  if (!std::isfinite(p.range_sigma_m) || p.range_sigma_m <= 0.0 || !std::isfinite(p.range_m) ||
      !std::isfinite(p.bearing_rad)) {
    return std::nullopt;
  }
  return FitPoint{p.range_m, std::cos(p.bearing_rad), std::sin(p.bearing_rad),
                  1.0 / (p.range_sigma_m * p.range_sigma_m)};  // eq. 3.11
}

std::optional<Line> FitLine(std::span<const PolarPoint> points) {
  if (points.size() < 2) return std::nullopt;
  std::vector<FitPoint> prepared;
  prepared.reserve(points.size());
  for (const PolarPoint& p : points) {
    const std::optional<FitPoint> f = PrepareFitPoint(p);
    if (!f) return std::nullopt;
    prepared.push_back(*f);
  }
  return FitLinePrepared(prepared);
}

std::optional<Line> FitLinePrepared(std::span<const FitPoint> points) {
  if (points.size() < 2) return std::nullopt;
  FitCore c;
  double sum_wx = 0.0;
  double sum_wy = 0.0;
  for (const FitPoint& p : points) {
    c.sum_w += p.weight;
    sum_wx += p.weight * p.range_m * p.cos_bearing;
    sum_wy += p.weight * p.range_m * p.sin_bearing;
    c.sum_wrho2 += p.weight * p.range_m * p.range_m;
  }
  // Weighted means x_w, y_w (below eq. 3.5).
  c.xw = sum_wx / c.sum_w;
  c.yw = sum_wy / c.sum_w;
  // Numerator N and denominator D of tan(2 alpha), eq. 3.4, about the mean.
  for (const FitPoint& p : points) {
    const double dx = c.xw - p.range_m * p.cos_bearing;
    const double dy = c.yw - p.range_m * p.sin_bearing;
    c.num += -2.0 * p.weight * dy * dx;
    c.den += p.weight * (dy * dy - dx * dx);
    c.scatter += p.weight * (dx * dx + dy * dy);
  }
  std::optional<Line> fit;
  if (Degenerate(c)) return fit;
  const double nd2 = c.num * c.num + c.den * c.den;
  // Eq. 3.4 (atan2 selects the minimum of the perpendicular errors), eq. 3.5.
  const double alpha = 0.5 * std::atan2(c.num, c.den);
  const double ca = std::cos(alpha);
  const double sa = std::sin(alpha);
  const double r = c.xw * ca + c.yw * sa;
  // Partial derivatives with respect to rho_i (eqs. 3.8-3.10). With
  // x_i = rho_i cos(theta_i), y_i = rho_i sin(theta_i):
  //   dN/drho_i = 2 w_i (x_w sin th_i + y_w cos th_i - rho_i sin 2th_i)
  //   dD/drho_i = 2 w_i (x_w cos th_i - y_w sin th_i - rho_i cos 2th_i)
  //   dalpha/drho_i = (D dN - N dD) / (2 (D^2 + N^2))            (eq. 3.8)
  //   dr/drho_i = w_i / sum w cos(th_i - alpha)
  //             + dalpha/drho_i (y_w cos alpha - x_w sin alpha)   (eq. 3.9)
  const double dr_dalpha = c.yw * ca - c.xw * sa;
  double s_aa = 0.0;
  double s_rr = 0.0;
  double s_ar = 0.0;
  for (const FitPoint& p : points) {
    const double w = p.weight;
    const double var = 1.0 / w;
    const double ct = p.cos_bearing;
    const double st = p.sin_bearing;
    const double s2t = 2.0 * st * ct;
    const double c2t = ct * ct - st * st;
    const double dnum = 2.0 * w * (c.xw * st + c.yw * ct - p.range_m * s2t);
    const double dden = 2.0 * w * (c.xw * ct - c.yw * st - p.range_m * c2t);
    const double da = (c.den * dnum - c.num * dden) / (2.0 * nd2);
    const double dr = w / c.sum_w * (ct * ca + st * sa) + da * dr_dalpha;
    s_aa += da * da * var;  // eq. 3.8
    s_rr += dr * dr * var;  // eq. 3.9
    s_ar += da * dr * var;  // eq. 3.10
  }
  Finish(alpha, r, s_aa, s_rr, s_ar, fit.emplace());
  return fit;
}

PrefixLineFits::PrefixLineFits(std::span<const FitPoint> points) { Rebuild(points); }

void PrefixLineFits::Rebuild(std::span<const FitPoint> points) {
  // The table keeps its capacity from scan to scan (a scan's table is ~50 kB).
  prefix_.resize(points.size() + 1);
  // Two passes, each point's moments and then the running sums: one pass
  // keeping the sums in a temporary array stalls on store forwarding.
  prefix_[0].fill(0.0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const FitPoint& p = points[i];
    const double w = p.weight;
    const double x = p.range_m * p.cos_bearing;
    const double y = p.range_m * p.sin_bearing;
    // g = (st, ct, rho s2t, rho c2t), as scalars: an array here is spilled with
    // scalar stores and read back in pairs, which stalls on store forwarding.
    const double g0 = p.sin_bearing;
    const double g1 = p.cos_bearing;
    const double g2 = p.range_m * 2.0 * p.sin_bearing * p.cos_bearing;
    const double g3 = p.range_m * (p.cos_bearing * p.cos_bearing - p.sin_bearing * p.sin_bearing);
    Moments& m = prefix_[i + 1];
    m[0] = w;
    m[1] = w * x;
    m[2] = w * y;
    m[3] = w * x * x;
    m[4] = w * y * y;
    m[5] = w * x * y;
    m[6] = w * p.range_m * p.range_m;
    m[7] = w * g0 * g0;
    m[8] = w * g0 * g1;
    m[9] = w * g0 * g2;
    m[10] = w * g0 * g3;
    m[11] = w * g1 * g1;
    m[12] = w * g1 * g2;
    m[13] = w * g1 * g3;
    m[14] = w * g2 * g2;
    m[15] = w * g2 * g3;
    m[16] = w * g3 * g3;
  }
  Moments sums = prefix_[0];  // running sums, kept in registers
  for (std::size_t i = 1; i <= points.size(); ++i) {
    for (int j = 0; j < kMoments; ++j) prefix_[i][j] = sums[j] += prefix_[i][j];
  }
}

std::optional<Line> PrefixLineFits::Fit(int begin, int end, Precision precision) const {
  if (end - begin < 2) return std::nullopt;
  Moments s;
  for (int j = 0; j < kMoments; ++j) s[j] = prefix_[end][j] - prefix_[begin][j];
  return FitMoments(s, precision);
}

std::optional<Line> PrefixLineFits::FitMembers(std::span<const int> members,
                                               double* residual_sum) const {
  if (members.size() < 2) return std::nullopt;
  Moments s;
  s.fill(0.0);
  const std::size_t n = members.size();
  for (std::size_t begin = 0; begin < n;) {
    // members[k] - k is non-decreasing (ascending indices, no repeats) and
    // constant exactly on a run of consecutive indices: the run starting at
    // `begin` ends at the first k where it grows, found by bisection.
    const auto offset = [&](std::size_t k) {
      return static_cast<long>(members[k]) - static_cast<long>(k);
    };
    std::size_t end = begin + 1;
    std::size_t past = n;  // the run ends in [end, past]
    while (end < past) {
      const std::size_t mid = end + (past - end) / 2;
      if (offset(mid) == offset(begin)) {
        end = mid + 1;
      } else {
        past = mid;
      }
    }
    const Moments& hi = prefix_[members[end - 1] + 1];
    const Moments& lo = prefix_[members[begin]];
    for (int j = 0; j < kMoments; ++j) s[j] += hi[j] - lo[j];
    begin = end;
  }
  return FitMoments(s, Precision::kExact, residual_sum);
}

std::optional<Line> PrefixLineFits::FitMoments(const Moments& s, Precision precision,
                                               double* residual_sum) {
  // Divisions by sum w and by N^2 + D^2 as multiplications by their
  // reciprocals (a few per fit instead of a dozen; differences of 1 ulp).
  std::optional<Line> fit;  // returned by name: written in place (NRVO), not copied
  FitCore c;
  c.sum_w = s[0];
  const double inv_w = 1.0 / c.sum_w;
  c.xw = s[1] * inv_w;
  c.yw = s[2] * inv_w;
  c.sum_wrho2 = s[6];
  // Second moments about the weighted mean.
  const double cxx = s[3] - c.sum_w * c.xw * c.xw;
  const double cyy = s[4] - c.sum_w * c.yw * c.yw;
  const double cxy = s[5] - c.sum_w * c.xw * c.yw;
  c.num = -2.0 * cxy;  // eq. 3.4, N
  c.den = cyy - cxx;   // eq. 3.4, D
  c.scatter = cxx + cyy;
  if (Degenerate(c)) return fit;
  const double nd2 = c.num * c.num + c.den * c.den;
  const double inv_nd2 = 1.0 / nd2;
  if (residual_sum != nullptr) {
    // The smaller eigenvalue of the scatter matrix [cxx cxy; cxy cyy].
    *residual_sum = std::max(0.0, 0.5 * (c.scatter - std::sqrt(nd2)));
  }
  const double alpha =
      0.5 * (precision == Precision::kExact ? std::atan2(c.num, c.den) : FastAtan2(c.num, c.den));
  // cos and sin of alpha from those of 2 alpha = atan2(N, D) by the half-angle
  // formulas (alpha in (-pi/2, pi/2], so cos alpha >= 0), without trigonometry.
  const double inv_norm = std::sqrt(inv_nd2);
  const double c2 = c.den * inv_norm;
  const double s2 = c.num * inv_norm;
  double ca, sa;
  if (c2 >= 0.0) {
    ca = std::sqrt(0.5 * (1.0 + c2));
    sa = s2 / (2.0 * ca);
  } else {
    sa = std::copysign(std::sqrt(0.5 * (1.0 - c2)), s2);
    ca = s2 / (2.0 * sa);
  }
  const double r = c.xw * ca + c.yw * sa;
  // d alpha/d rho_i = w_i a.g_i and d r/d rho_i = w_i b.g_i (see the header), so
  // with var_i = 1/w_i the sums of eqs. 3.8-3.10 are a^T M a, b^T M b, a^T M b.
  // b = k a + u with u = (sin alpha, cos alpha, 0, 0) / sum w (eq. 3.9), so
  // a^T M b = k a^T M a + u^T M a and b^T M b = k^2 a^T M a + 2 k u^T M a + u^T M u.
  const double a[4] = {(c.den * c.xw + c.num * c.yw) * inv_nd2,
                       (c.den * c.yw - c.num * c.xw) * inv_nd2, -c.den * inv_nd2, c.num * inv_nd2};
  const double k = c.yw * ca - c.xw * sa;
  const double u0 = sa * inv_w;
  const double u1 = ca * inv_w;
  // M from its upper triangle s[7..16], row by row.
  const double m00 = s[7], m01 = s[8], m02 = s[9], m03 = s[10];
  const double m11 = s[11], m12 = s[12], m13 = s[13];
  const double m22 = s[14], m23 = s[15], m33 = s[16];
  const double ma0 = m00 * a[0] + m01 * a[1] + m02 * a[2] + m03 * a[3];
  const double ma1 = m01 * a[0] + m11 * a[1] + m12 * a[2] + m13 * a[3];
  const double ma2 = m02 * a[0] + m12 * a[1] + m22 * a[2] + m23 * a[3];
  const double ma3 = m03 * a[0] + m13 * a[1] + m23 * a[2] + m33 * a[3];
  const double s_aa = a[0] * ma0 + a[1] * ma1 + a[2] * ma2 + a[3] * ma3;
  const double uma = u0 * ma0 + u1 * ma1;
  const double umu = u0 * (m00 * u0 + m01 * u1) + u1 * (m01 * u0 + m11 * u1);
  const double s_ar = k * s_aa + uma;
  const double s_rr = k * (k * s_aa + 2.0 * uma) + umu;
  Finish(alpha, r, s_aa, s_rr, s_ar, fit.emplace());
  return fit;
}

}  // namespace pavilion::core
