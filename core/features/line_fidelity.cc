#include "core/features/line_fidelity.h"

#include <limits>

#include "core/types/pose2.h"

namespace pavilion::core {

bool FidelityPasses(const WindowFit* windows, double threshold) {
  const double ref = windows[1].alpha_rad;
  const double da[3] = {NormalizeAngle(windows[0].alpha_rad - ref), 0.0,
                        NormalizeAngle(windows[2].alpha_rad - ref)};
  Sym2 info;
  double info_x = 0.0;  // information times (alpha - ref, r), summed
  double info_y = 0.0;
  for (int j = 0; j < 3; ++j) {
    const Sym2& i = windows[j].information;
    info = info + i;
    info_x += i.a * da[j] + i.b * windows[j].r_m;
    info_y += i.b * da[j] + i.c * windows[j].r_m;
  }
  const Sym2 cw = info.Inverse();                     // eq. 3.14
  const double xw_a = cw.a * info_x + cw.b * info_y;  // eq. 3.13
  const double xw_r = cw.b * info_x + cw.c * info_y;
  // Eq. 3.12, sum_j e_j^T (C_j + C_w)^-1 e_j = sum_j q_j / det_j with q_j the
  // quadratic form of the adjugate, as one fraction. Its denominator is
  // positive for positive-definite covariances, and then the test needs no
  // division.
  double numerator = 0.0;
  double denominator = 1.0;
  for (int j = 0; j < 3; ++j) {
    const Sym2 s = windows[j].covariance + cw;
    const double x = da[j] - xw_a;
    const double y = windows[j].r_m - xw_r;
    const double det = s.Determinant();
    numerator = numerator * det + (s.c * x * x - 2.0 * s.b * x * y + s.a * y * y) * denominator;
    denominator *= det;
  }
  if (denominator > 0.0) return numerator <= threshold * denominator;
  return numerator / denominator <= threshold;
}

double CollinearityDistance(const Line& a, const Line& b) {
  const double ea = -NormalizeAngle(b.alpha_rad - a.alpha_rad);
  const double er = a.r_m - b.r_m;
  const Sym2 s = Sym2::Of(a.covariance) + Sym2::Of(b.covariance);
  if (!(s.Determinant() > 0.0)) return std::numeric_limits<double>::infinity();
  return s.InverseQuadratic(ea, er);
}

}  // namespace pavilion::core
