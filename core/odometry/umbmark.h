#pragma once

// UMBmark (Borenstein & Feng 1996) and the straight-run scale: the systematic
// odometry errors of a differential-drive robot (thesis §2.3) from the end
// poses of calibration runs. Pure math on the measured end-pose errors; the
// runs themselves are driven elsewhere (scenarios/calibration/). The
// derivation of formulas (C1)–(C4) and (C6) is in umbmark.cc.

#include <Eigen/Core>
#include <functional>
#include <vector>

namespace pavilion::core {

// UMBmark for squares of side L driven with odometry feedback. The centres of
// gravity of the end-position errors (start frame) of the clockwise and
// counter-clockwise runs give the turn error per corner and the heading change
// per leg, and from them the correction factors.
struct UmbmarkResult {
  Eigen::Vector2d cg_ccw_m{0, 0};  // centre of gravity of CCW end-position errors
  Eigen::Vector2d cg_cw_m{0, 0};
  double corner_overturn_rad = 0.0;  // a: true − intended turn at each 90° corner
  double leg_curvature_rad = 0.0;    // γ: true heading change along each leg (left positive)
  // Correction factors of the calibrated model relative to the nominal one:
  double radius_ratio_factor = 1.0;  // E_d: (r_R/r_L)_calibrated / (r_R/r_L)_nominal
  double turn_factor = 1.0;          // ρ: true / odometric in-place turn angle
  double e_max_syst_m = 0.0;         // UMBmark's measure: max(|cg_cw|, |cg_ccw|)
};

// The wheel radii and wheelbase of an odometry model (m).
struct WheelGeometry {
  double left_wheel_radius_m = 0.0;
  double right_wheel_radius_m = 0.0;
  double wheelbase_m = 0.0;
};

// The mean of the [x, y] parts of end-pose errors [x, y, θ] (m).
Eigen::Vector2d CentreOfGravity(const std::vector<Eigen::Vector3d>& errors);

// The true length of a straight run (C1) from the chord between its true start
// and end and its true heading change: the robot drove an arc of constant
// curvature, arc = chord·(γ/2)/sin(γ/2) (m).
double ArcLengthFromChord(double chord_m, double heading_change_rad);

// UMBmark's one-step estimate from end-pose errors of squares of side `side_m`
// with 90° corners. `scale` is the straight-run scale (true / odometric
// distance), `wheelbase_m` the nominal wheelbase. Throws std::invalid_argument
// when either direction has no runs.
UmbmarkResult EstimateUmbmark(const std::vector<Eigen::Vector3d>& ccw_errors,
                              const std::vector<Eigen::Vector3d>& cw_errors, double side_m,
                              double scale, double wheelbase_m);

// Sets result's correction factors (E_d, ρ) from its corner over-turn a and
// leg curvature γ (formulas C2–C4 of umbmark.cc).
void SetUmbmarkFactors(double side_m, double scale, double wheelbase_m, UmbmarkResult* result);

// The calibrated radii and wheelbase (C4) for UMBmark's factors and the
// straight-run scale, relative to the nominal model.
WheelGeometry UmbmarkCorrectedGeometry(const WheelGeometry& nominal, const UmbmarkResult& u,
                                       double scale);

// The end-pose errors of the CCW and CW squares re-integrated with a model.
struct SquareErrors {
  std::vector<Eigen::Vector3d> ccw;
  std::vector<Eigen::Vector3d> cw;
};

// Iterated UMBmark (C6): starting from `one_step`, applies (C2), (C3) to the
// residual centres of gravity of the squares re-integrated by `residuals` with
// the current model, until a pass changes a and γ by less than
// `tolerance_rad` or after `max_iterations` passes. Returns the final result;
// `iterations` receives the passes made.
UmbmarkResult IterateUmbmark(const UmbmarkResult& one_step, const WheelGeometry& nominal,
                             double side_m, double scale,
                             const std::function<SquareErrors(const WheelGeometry&)>& residuals,
                             double tolerance_rad, int max_iterations, int* iterations);

}  // namespace pavilion::core
