#include "core/odometry/umbmark.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

// =============================================================================
// Method (docs/calibration.md has the same with the figures obtained).
//
// Notation. The nominal model (URDF) has radii r_L, r_R and wheelbase b. The
// calibrated model has radii c_L·r_L, c_R·r_R and wheelbase b_c. Encoder
// angles φ give nominal travels s = r·φ; the calibrated travels are c·s.
// Define the mean scale S = (c_L + c_R)/2 and the ratio factor q = c_R/c_L
// (Borenstein & Feng's E_d when the nominal radii are equal).
//
// Straight runs. The robot drives a straight line of its odometry (s_l = s_r
// step by step) of odometric length D. Truly it drives an arc of length S·D
// whose chord and heading change γ the tape gives: arc = chord·(γ/2)/sin(γ/2).
//     S = Σ arc_i / Σ D_i.                                               (C1)
//
// UMBmark squares (derived here for our square; Borenstein & Feng 1996 give the
// same structure for theirs). The robot drives a square of side L by odometry
// feedback: legs with s_l = s_r, then in-place turns of ±90° (s_r = −s_l),
// counter-clockwise (σ = +1, left turns) or clockwise (σ = −1), 4 legs and 4
// turns. Two error types act, to first order:
//  - each in-place turn truly turns σ(π/2 + a): the true turn is
//    (c_R·s − c_L·(−s))/b_true = 2sS/b_true against the odometry's 2s/b, so the
//    turn factor ρ = (π/2 + a)/(π/2) = S·b/b_true;
//  - each leg truly changes heading by γ = (c_R − c_L)·L/b_true (left
//    positive), whatever the square's direction.
// (The in-place turns also move the centre by (c_R − c_L)s/2 along the mid
// heading; the four corner headings are 90° apart, so these cancel.)
// Let η_i be the heading error at the start of leg i = 0..3: η_i = i(γ + σa).
// Leg i, of true length S·L (≈ L to first order) and nominal direction u_i,
// is rotated by the mean heading error η_i + γ/2, which displaces its end by
// L(η_i + γ/2)·n_i, n_i = u_i rotated by +90°. The lengths' excess S·L·u_i sums
// to zero around the square. Summing, with u_i = (1,0),(0,1),(−1,0),(0,−1)
// for CCW and (1,0),(0,−1),(−1,0),(0,1) for CW:
//     Σ (i + ½) n_i = (2, −2) (CCW),  (−2, −2) (CW);  Σ i n_i the same,
// so the end-position errors (true − odometry, start frame) are
//     ε_ccw = 2L(γ + a)·(1, −1),    ε_cw = 2L(a − γ)·(1, 1).
// With the centres of gravity (x, y)_ccw, (x, y)_cw of several runs each,
// using both coordinates:
//     a = (x_ccw + x_cw − y_ccw + y_cw) / (8L),                          (C2)
//     γ = (x_ccw − x_cw − y_ccw − y_cw) / (8L).                          (C3)
// Then ρ = 1 + 2a/π and b_c = b·S/ρ. From γ = 2S·L·(q − 1)/((q + 1)·b_c),
//     q = (1 + γ·b_c/(2SL)) / (1 − γ·b_c/(2SL)) = (R + b_c/2)/(R − b_c/2)
// with R = S·L/γ the true radius of a leg (Borenstein & Feng's form), and
//     c_L = 2S/(1 + q),   c_R = 2S·q/(1 + q).                            (C4)
//
// Iterated UMBmark (C6). (C2)–(C4) are first order: Borenstein & Feng's single
// correction leaves the second-order terms, which for a 1% radius ratio (6° of
// heading change per 4 m leg) and a 2% wheelbase error are 0.2% of the
// wheelbase. As the recorded encoder counts can be re-integrated with any
// model, we apply (C2), (C3) again to the centres of gravity of the squares'
// residual errors under the current model, add the resulting a and γ to the
// estimates, recompute (C4), and repeat until a pass changes them by less than
// 1e-7 rad. At the fixed point the calibrated model reproduces both centres of
// gravity; for a kinematic robot that is its true model (test).
// =============================================================================

namespace pavilion::core {
namespace {

constexpr double kQuarterTurnRad = std::numbers::pi / 2;  // UMBmark's square corners
// Below this half heading change (rad) a straight run's arc is its chord.
constexpr double kStraightHalfAngleRad = 1e-9;

}  // namespace

Eigen::Vector2d CentreOfGravity(const std::vector<Eigen::Vector3d>& errors) {
  Eigen::Vector2d cg(0, 0);
  for (const Eigen::Vector3d& e : errors) cg += e.head<2>() / static_cast<double>(errors.size());
  return cg;
}

double ArcLengthFromChord(double chord_m, double heading_change_rad) {
  const double half = 0.5 * std::abs(heading_change_rad);
  return half < kStraightHalfAngleRad ? chord_m : chord_m * half / std::sin(half);
}

UmbmarkResult EstimateUmbmark(const std::vector<Eigen::Vector3d>& ccw_errors,
                              const std::vector<Eigen::Vector3d>& cw_errors, double side_m,
                              double scale, double wheelbase_m) {
  if (ccw_errors.empty() || cw_errors.empty()) {
    throw std::invalid_argument("UMBmark needs clockwise and counter-clockwise squares");
  }
  UmbmarkResult u;
  u.cg_ccw_m = CentreOfGravity(ccw_errors);
  u.cg_cw_m = CentreOfGravity(cw_errors);
  const double x_ccw = u.cg_ccw_m.x(), y_ccw = u.cg_ccw_m.y();
  const double x_cw = u.cg_cw_m.x(), y_cw = u.cg_cw_m.y();
  const double leg_m = scale * side_m;                                  // true leg length
  u.corner_overturn_rad = (x_ccw + x_cw - y_ccw + y_cw) / (8 * leg_m);  // (C2)
  u.leg_curvature_rad = (x_ccw - x_cw - y_ccw - y_cw) / (8 * leg_m);    // (C3)
  u.e_max_syst_m = std::max(u.cg_ccw_m.norm(), u.cg_cw_m.norm());
  SetUmbmarkFactors(side_m, scale, wheelbase_m, &u);
  return u;
}

void SetUmbmarkFactors(double side_m, double scale, double wheelbase_m, UmbmarkResult* u) {
  const double leg_m = scale * side_m;
  u->turn_factor = (kQuarterTurnRad + u->corner_overturn_rad) / kQuarterTurnRad;
  const double wheelbase_c = wheelbase_m * scale / u->turn_factor;
  const double h = u->leg_curvature_rad * wheelbase_c / (2 * leg_m);
  u->radius_ratio_factor = (1 + h) / (1 - h);  // (C4): (R + b/2)/(R − b/2)
}

WheelGeometry UmbmarkCorrectedGeometry(const WheelGeometry& nominal, const UmbmarkResult& u,
                                       double scale) {
  const double q = u.radius_ratio_factor;
  WheelGeometry m = nominal;
  m.left_wheel_radius_m *= 2 * scale / (1 + q);
  m.right_wheel_radius_m *= 2 * scale * q / (1 + q);
  m.wheelbase_m *= scale / u.turn_factor;
  return m;
}

UmbmarkResult IterateUmbmark(const UmbmarkResult& one_step, const WheelGeometry& nominal,
                             double side_m, double scale,
                             const std::function<SquareErrors(const WheelGeometry&)>& residuals,
                             double tolerance_rad, int max_iterations, int* iterations) {
  UmbmarkResult u = one_step;
  *iterations = 0;
  for (int i = 0; i < max_iterations; ++i) {
    const SquareErrors errors = residuals(UmbmarkCorrectedGeometry(nominal, u, scale));
    const UmbmarkResult residual =
        EstimateUmbmark(errors.ccw, errors.cw, side_m, scale, nominal.wheelbase_m);
    u.corner_overturn_rad += residual.corner_overturn_rad;
    u.leg_curvature_rad += residual.leg_curvature_rad;
    SetUmbmarkFactors(side_m, scale, nominal.wheelbase_m, &u);
    *iterations = i + 1;
    if (std::max(std::abs(residual.corner_overturn_rad), std::abs(residual.leg_curvature_rad)) <
        tolerance_rad) {
      break;
    }
  }
  return u;
}

}  // namespace pavilion::core
