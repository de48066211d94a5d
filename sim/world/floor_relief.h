#pragma once

// An uneven floor (issue 20): the gentle slopes and bumps of a real building's
// floor, which tilt a robot, move the load between its wheels and its lasers'
// beam planes, and which no encoder sees. The height above z = 0 is a sum of
// plane waves,
//
//   h(p) = sum_k a_k cos(kappa_k . p + phi_k),
//
// smooth everywhere, with exact bounds on its slope (|grad h| <= sum a_k
// |kappa_k|) and curvature (the Hessian's norm <= sum a_k |kappa_k|^2). The
// physics gets it as a height field (sim/world/static_geometry.cc), the
// ray-cast wheels query it directly (sim/robot/raycast_drive.h). A flat relief
// (no waves) leaves the floor the slab it always was.

#include <Eigen/Core>
#include <vector>

#include "core/random/random_stream.h"

namespace pavilion::sim {

struct FloorWave {
  Eigen::Vector2d wavevector_radpm{0.0, 0.0};  // kappa, rad/m; wavelength 2 pi / |kappa|
  double amplitude_m = 0.0;                    // a >= 0
  double phase_rad = 0.0;                      // phi
};

class FloorRelief {
 public:
  FloorRelief() = default;  // flat: z = 0 everywhere
  // Throws std::invalid_argument for non-finite values or negative amplitudes.
  explicit FloorRelief(std::vector<FloorWave> waves);

  bool flat() const { return waves_.empty(); }
  const std::vector<FloorWave>& waves() const { return waves_; }

  // The height and its gradient at p in one pass over the waves.
  struct Sample {
    double height_m = 0.0;
    Eigen::Vector2d gradient{0.0, 0.0};
    Eigen::Vector3d Normal() const;  // upward unit normal
  };
  Sample At(const Eigen::Vector2d& p_m) const;
  double HeightAt(const Eigen::Vector2d& p_m) const;
  Eigen::Vector2d GradientAt(const Eigen::Vector2d& p_m) const;
  // The floor's upward unit normal at p.
  Eigen::Vector3d NormalAt(const Eigen::Vector2d& p_m) const;
  // Upper bounds everywhere: of |grad h| (m/m) and of the Hessian's norm (1/m).
  double SlopeBound() const;
  double CurvatureBound() const;

 private:
  std::vector<FloorWave> waves_;
};

struct FloorReliefOptions {
  // No slope of the floor is steeper than this, rad, (0, 0.05]. The issue's
  // ±0.5°: a floor a building inspector would pass (DIN 18202 allows 4 mm in
  // 1 m, 0.23°, for finished floors, and more over longer distances).
  double max_slope_rad = 0.5 * 3.14159265358979323846 / 180.0;
  // The waves' wavelengths are log-uniform in [min, max], m, 0.1 <= min <= max
  // <= 100. Chosen: from a bump under a wheel's footprint-to-axle span (half a
  // metre) to a slope across a room (8 m).
  double min_wavelength_m = 0.5;
  double max_wavelength_m = 8.0;
  // Number of waves, [1, 256]. Chosen: enough that the floor does not look
  // periodic over a hall, few enough to evaluate every step at every wheel.
  int waves = 24;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Draws a relief for the floor rectangle [min_m, max_m]: `options.waves`
// waves with directions and phases uniform, wavelengths log-uniform, and
// amplitudes that give each the same expected slope (a_k proportional to its
// wavelength times |N(0, 1)|), scaled so that the steepest slope on the
// rectangle is at most max_slope_rad: the largest |grad h| on a grid of
// kReliefCheckSpacingM, searched kReliefRefine times finer round the nodes
// that may hold the steepest, plus the curvature bound times the farthest a
// point is from a fine node equals tan(max_slope_rad). The steepest slope
// then lies within that curvature term (a few per cent) below the maximum.
FloorRelief DrawFloorRelief(const FloorReliefOptions& options, const Eigen::Vector2d& min_m,
                            const Eigen::Vector2d& max_m, core::RandomStream* random);

// The grid DrawFloorRelief checks the slope on, m, and how much finer it
// searches round the steepest nodes.
inline constexpr double kReliefCheckSpacingM = 0.05;
inline constexpr int kReliefRefine = 8;
// The physics' height field samples the relief this far apart, m: between
// samples it deviates from the waves by at most CurvatureBound() * d^2 / 8
// (about 0.05 mm for the default options).
inline constexpr double kReliefGridSpacingM = 0.1;

}  // namespace pavilion::sim
