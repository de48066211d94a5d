#include "core/features/line_fit.h"

#include <cmath>
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

Line Finish(double alpha, double r, double s_aa, double s_rr, double s_ar) {
  // r >= 0 convention (eq. B.4, the line is visible from the sensor): flipping
  // (alpha, r) -> (alpha + pi, -r) negates the r row and column of the covariance.
  if (r < 0.0) {
    r = -r;
    alpha += std::numbers::pi;
    s_ar = -s_ar;
  }
  Line line;
  line.alpha_rad = NormalizeAngle(alpha);
  line.r_m = r;
  line.covariance << s_aa, s_ar, s_ar, s_rr;
  return line;
}

// atan2 to within 1e-7 rad (Abramowitz & Stegun 4.4.49: a degree-15 odd
// polynomial for atan on [-1, 1], then octant reduction; 4e-8 measured).
double FastAtan2(double y, double x) {
  const double ax = std::abs(x);
  const double ay = std::abs(y);
  if (ax == 0.0 && ay == 0.0) return std::atan2(y, x);  // signed zeros as std::atan2
  const bool swap = ay > ax;
  const double t = swap ? ax / ay : ay / ax;
  const double t2 = t * t;
  double a = -0.0040540580;
  a = a * t2 + 0.0218612288;
  a = a * t2 - 0.0559098861;
  a = a * t2 + 0.0964200441;
  a = a * t2 - 0.1390853351;
  a = a * t2 + 0.1994653599;
  a = a * t2 - 0.3332985605;
  a = a * t2 + 0.9999993329;
  a *= t;
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
  if (Degenerate(c)) return std::nullopt;
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
  return Finish(alpha, r, s_aa, s_rr, s_ar);
}

PrefixLineFits::PrefixLineFits(std::span<const FitPoint> points) {
  prefix_.resize(points.size() + 1);
  prefix_[0].fill(0.0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const FitPoint& p = points[i];
    const double w = p.weight;
    const double x = p.range_m * p.cos_bearing;
    const double y = p.range_m * p.sin_bearing;
    const double g[4] = {
        p.sin_bearing, p.cos_bearing, p.range_m * 2.0 * p.sin_bearing * p.cos_bearing,
        p.range_m * (p.cos_bearing * p.cos_bearing - p.sin_bearing * p.sin_bearing)};
    std::array<double, kMoments> m = {
        w, w * x, w * y, w * x * x, w * y * y, w * x * y, w * p.range_m * p.range_m};
    int k = 7;
    for (int a = 0; a < 4; ++a) {
      for (int b = a; b < 4; ++b) m[k++] = w * g[a] * g[b];
    }
    for (int j = 0; j < kMoments; ++j) prefix_[i + 1][j] = prefix_[i][j] + m[j];
  }
}

std::optional<Line> PrefixLineFits::Fit(int begin, int end, Precision precision) const {
  if (end - begin < 2) return std::nullopt;
  Moments s;
  for (int j = 0; j < kMoments; ++j) s[j] = prefix_[end][j] - prefix_[begin][j];
  return FitMoments(s, precision);
}

std::optional<Line> PrefixLineFits::FitMembers(std::span<const int> members) const {
  if (members.size() < 2) return std::nullopt;
  Moments s;
  s.fill(0.0);
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= members.size(); ++k) {
    if (k < members.size() && members[k] == members[k - 1] + 1) continue;
    const auto& hi = prefix_[members[k - 1] + 1];
    const auto& lo = prefix_[members[begin]];
    for (int j = 0; j < kMoments; ++j) s[j] += hi[j] - lo[j];
    begin = k;
  }
  return FitMoments(s, Precision::kExact);
}

std::optional<Line> PrefixLineFits::FitMoments(const Moments& s, Precision precision) {
  FitCore c;
  c.sum_w = s[0];
  c.xw = s[1] / c.sum_w;
  c.yw = s[2] / c.sum_w;
  c.sum_wrho2 = s[6];
  // Second moments about the weighted mean.
  const double cxx = s[3] - c.sum_w * c.xw * c.xw;
  const double cyy = s[4] - c.sum_w * c.yw * c.yw;
  const double cxy = s[5] - c.sum_w * c.xw * c.yw;
  c.num = -2.0 * cxy;  // eq. 3.4, N
  c.den = cyy - cxx;   // eq. 3.4, D
  c.scatter = cxx + cyy;
  if (Degenerate(c)) return std::nullopt;
  const double nd2 = c.num * c.num + c.den * c.den;
  const double alpha =
      0.5 * (precision == Precision::kExact ? std::atan2(c.num, c.den) : FastAtan2(c.num, c.den));
  // cos and sin of alpha from those of 2 alpha = atan2(N, D) by the half-angle
  // formulas (alpha in (-pi/2, pi/2], so cos alpha >= 0), without trigonometry.
  const double norm = std::sqrt(nd2);
  const double c2 = c.den / norm;
  const double s2 = c.num / norm;
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
  const double a[4] = {(c.den * c.xw + c.num * c.yw) / nd2, (c.den * c.yw - c.num * c.xw) / nd2,
                       -c.den / nd2, c.num / nd2};
  const double k = c.yw * ca - c.xw * sa;
  const double b[4] = {sa / c.sum_w + k * a[0], ca / c.sum_w + k * a[1], k * a[2], k * a[3]};
  double m[4][4];
  int idx = 7;
  for (int i = 0; i < 4; ++i) {
    for (int j = i; j < 4; ++j) m[i][j] = m[j][i] = s[idx++];
  }
  double ma[4], mb[4];
  for (int i = 0; i < 4; ++i) {
    ma[i] = m[i][0] * a[0] + m[i][1] * a[1] + m[i][2] * a[2] + m[i][3] * a[3];
    mb[i] = m[i][0] * b[0] + m[i][1] * b[1] + m[i][2] * b[2] + m[i][3] * b[3];
  }
  const double s_aa = a[0] * ma[0] + a[1] * ma[1] + a[2] * ma[2] + a[3] * ma[3];
  const double s_rr = b[0] * mb[0] + b[1] * mb[1] + b[2] * mb[2] + b[3] * mb[3];
  const double s_ar = b[0] * ma[0] + b[1] * ma[1] + b[2] * ma[2] + b[3] * ma[3];
  return Finish(alpha, r, s_aa, s_rr, s_ar);
}

}  // namespace pavilion::core
