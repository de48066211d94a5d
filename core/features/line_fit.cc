#include "core/features/line_fit.h"

#include <cmath>
#include <numbers>

namespace pavilion::core {
namespace {

// The orientation of the fit is undefined when the weighted scatter about the
// mean vanishes relative to the weighted squared ranges (coincident points), or
// when the scatter is isotropic ((D^2 + N^2) vanishes relative to its square).
constexpr double kDegenerateRelativeScatter = 1e-20;
constexpr double kIsotropicRelativeScatter = 1e-24;

}  // namespace

std::optional<Line> FitLine(std::span<const PolarPoint> points) {
  const std::size_t n = points.size();
  if (n < 2) return std::nullopt;
  double sum_w = 0.0;
  double sum_wx = 0.0;
  double sum_wy = 0.0;
  double sum_wrho2 = 0.0;
  for (const PolarPoint& p : points) {
    if (!std::isfinite(p.range_sigma_m) || p.range_sigma_m <= 0.0 || !std::isfinite(p.range_m) ||
        !std::isfinite(p.bearing_rad)) {
      return std::nullopt;
    }
    const double w = 1.0 / (p.range_sigma_m * p.range_sigma_m);  // eq. 3.11
    sum_w += w;
    sum_wx += w * p.range_m * std::cos(p.bearing_rad);
    sum_wy += w * p.range_m * std::sin(p.bearing_rad);
    sum_wrho2 += w * p.range_m * p.range_m;
  }
  // Weighted means x_w, y_w (below eq. 3.5).
  const double xw = sum_wx / sum_w;
  const double yw = sum_wy / sum_w;
  // Numerator N and denominator D of tan(2 alpha), eq. 3.4.
  double num = 0.0;
  double den = 0.0;
  double scatter = 0.0;
  for (const PolarPoint& p : points) {
    const double w = 1.0 / (p.range_sigma_m * p.range_sigma_m);
    const double dx = xw - p.range_m * std::cos(p.bearing_rad);
    const double dy = yw - p.range_m * std::sin(p.bearing_rad);
    num += -2.0 * w * dy * dx;
    den += w * (dy * dy - dx * dx);
    scatter += w * (dx * dx + dy * dy);
  }
  const double nd2 = num * num + den * den;
  if (!(scatter > kDegenerateRelativeScatter * sum_wrho2) ||
      !(nd2 > kIsotropicRelativeScatter * scatter * scatter)) {
    return std::nullopt;
  }
  // Eq. 3.4 (atan2 selects the minimum of the perpendicular errors), eq. 3.5.
  double alpha = 0.5 * std::atan2(num, den);
  double r = xw * std::cos(alpha) + yw * std::sin(alpha);
  // Partial derivatives with respect to rho_i (eqs. 3.8-3.10). With
  // x_i = rho_i cos(theta_i), y_i = rho_i sin(theta_i):
  //   dN/drho_i = 2 w_i (x_w sin th_i + y_w cos th_i - rho_i sin 2th_i)
  //   dD/drho_i = 2 w_i (x_w cos th_i - y_w sin th_i - rho_i cos 2th_i)
  //   dalpha/drho_i = (D dN - N dD) / (2 (D^2 + N^2))            (eq. 3.8)
  //   dr/drho_i = w_i / sum w cos(th_i - alpha)
  //             + dalpha/drho_i (y_w cos alpha - x_w sin alpha)   (eq. 3.9)
  const double ca = std::cos(alpha);
  const double sa = std::sin(alpha);
  const double dr_dalpha = yw * ca - xw * sa;
  double s_aa = 0.0;
  double s_rr = 0.0;
  double s_ar = 0.0;
  for (const PolarPoint& p : points) {
    const double var = p.range_sigma_m * p.range_sigma_m;
    const double w = 1.0 / var;
    const double ct = std::cos(p.bearing_rad);
    const double st = std::sin(p.bearing_rad);
    const double s2t = 2.0 * st * ct;
    const double c2t = ct * ct - st * st;
    const double dnum = 2.0 * w * (xw * st + yw * ct - p.range_m * s2t);
    const double dden = 2.0 * w * (xw * ct - yw * st - p.range_m * c2t);
    const double da = (den * dnum - num * dden) / (2.0 * nd2);
    const double dr = w / sum_w * (ct * ca + st * sa) + da * dr_dalpha;
    s_aa += da * da * var;  // eq. 3.8
    s_rr += dr * dr * var;  // eq. 3.9
    s_ar += da * dr * var;  // eq. 3.10
  }
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

}  // namespace pavilion::core
