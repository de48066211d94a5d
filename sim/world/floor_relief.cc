#include "sim/world/floor_relief.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace pavilion::sim {

FloorRelief::FloorRelief(std::vector<FloorWave> waves) : waves_(std::move(waves)) {
  for (const FloorWave& w : waves_) {
    if (!w.wavevector_radpm.allFinite() || !std::isfinite(w.amplitude_m) ||
        !std::isfinite(w.phase_rad) || w.amplitude_m < 0.0) {
      throw std::invalid_argument("FloorRelief: waves need finite values and amplitudes >= 0");
    }
  }
}

double FloorRelief::HeightAt(const Eigen::Vector2d& p_m) const {
  double h = 0.0;
  for (const FloorWave& w : waves_)
    h += w.amplitude_m * std::cos(w.wavevector_radpm.dot(p_m) + w.phase_rad);
  return h;
}

Eigen::Vector2d FloorRelief::GradientAt(const Eigen::Vector2d& p_m) const {
  Eigen::Vector2d g = Eigen::Vector2d::Zero();
  for (const FloorWave& w : waves_) {
    g -= w.amplitude_m * std::sin(w.wavevector_radpm.dot(p_m) + w.phase_rad) * w.wavevector_radpm;
  }
  return g;
}

FloorRelief::Sample FloorRelief::At(const Eigen::Vector2d& p_m) const {
  Sample s;
  for (const FloorWave& w : waves_) {
    const double phase = w.wavevector_radpm.dot(p_m) + w.phase_rad;
    s.height_m += w.amplitude_m * std::cos(phase);
    s.gradient -= w.amplitude_m * std::sin(phase) * w.wavevector_radpm;
  }
  return s;
}

Eigen::Vector3d FloorRelief::Sample::Normal() const {
  return Eigen::Vector3d(-gradient.x(), -gradient.y(), 1.0).normalized();
}

Eigen::Vector3d FloorRelief::NormalAt(const Eigen::Vector2d& p_m) const {
  return Sample{0.0, GradientAt(p_m)}.Normal();
}

double FloorRelief::SlopeBound() const {
  double s = 0.0;
  for (const FloorWave& w : waves_) s += w.amplitude_m * w.wavevector_radpm.norm();
  return s;
}

double FloorRelief::CurvatureBound() const {
  double c = 0.0;
  for (const FloorWave& w : waves_) c += w.amplitude_m * w.wavevector_radpm.squaredNorm();
  return c;
}

void FloorReliefOptions::Validate() const {
  const auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("FloorReliefOptions.") + what);
  };
  require(std::isfinite(max_slope_rad) && max_slope_rad > 0.0 && max_slope_rad <= 0.05,
          "max_slope_rad must be in (0, 0.05] rad");
  require(std::isfinite(min_wavelength_m) && min_wavelength_m >= 0.1 &&
              std::isfinite(max_wavelength_m) && max_wavelength_m >= min_wavelength_m &&
              max_wavelength_m <= 100.0,
          "wavelengths must satisfy 0.1 <= min_wavelength_m <= max_wavelength_m <= 100 m");
  require(waves >= 1 && waves <= 256, "waves must be in [1, 256]");
}

FloorRelief DrawFloorRelief(const FloorReliefOptions& options, const Eigen::Vector2d& min_m,
                            const Eigen::Vector2d& max_m, core::RandomStream* random) {
  options.Validate();
  if (!min_m.allFinite() || !max_m.allFinite() || !(max_m.array() > min_m.array()).all()) {
    throw std::invalid_argument(
        "DrawFloorRelief: the floor rectangle must be finite and non-empty");
  }
  std::vector<FloorWave> waves;
  const double log_min = std::log(options.min_wavelength_m);
  const double log_max = std::log(options.max_wavelength_m);
  for (int k = 0; k < options.waves; ++k) {
    const double direction = random->Uniform(0.0, 2.0 * std::numbers::pi);
    const double wavelength = std::exp(random->Uniform(log_min, log_max));
    const double phase = random->Uniform(0.0, 2.0 * std::numbers::pi);
    const double weight = std::abs(random->Normal());
    const double kappa = 2.0 * std::numbers::pi / wavelength;
    // Unit expected slope before scaling: amplitude times kappa is the weight.
    waves.push_back(
        {kappa * Eigen::Vector2d(std::cos(direction), std::sin(direction)), weight / kappa, phase});
  }
  FloorRelief unscaled(waves);
  const double curvature = unscaled.CurvatureBound();
  // The slopes on a grid of kReliefCheckSpacingM; every point lies within
  // spacing / sqrt(2) of a node, and the slope changes by at most the
  // curvature bound per metre.
  const double d = kReliefCheckSpacingM;
  const Eigen::Vector2d extent = max_m - min_m;
  const int nx = static_cast<int>(std::ceil(extent.x() / d));
  const int ny = static_cast<int>(std::ceil(extent.y() / d));
  const auto node = [&](int i, int j) {
    return Eigen::Vector2d(std::min(min_m.x() + i * d, max_m.x()),
                           std::min(min_m.y() + j * d, max_m.y()));
  };
  std::vector<double> slopes(static_cast<std::size_t>(nx + 1) * (ny + 1));
  double steepest = 0.0;
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      const double s = unscaled.GradientAt(node(i, j)).norm();
      slopes[static_cast<std::size_t>(i) * (ny + 1) + j] = s;
      steepest = std::max(steepest, s);
    }
  }
  // Only cells round nodes within that margin of the steepest can hold a
  // steeper point: they are searched again kReliefRefine times finer.
  const double coarse_margin = curvature * d / std::numbers::sqrt2;
  const double fine = d / kReliefRefine;
  double refined = steepest;
  for (int i = 0; i <= nx; ++i) {
    for (int j = 0; j <= ny; ++j) {
      if (slopes[static_cast<std::size_t>(i) * (ny + 1) + j] + coarse_margin < steepest) continue;
      const Eigen::Vector2d centre = node(i, j);
      for (int a = -kReliefRefine / 2; a <= kReliefRefine / 2; ++a) {
        for (int b = -kReliefRefine / 2; b <= kReliefRefine / 2; ++b) {
          const Eigen::Vector2d p =
              (centre + fine * Eigen::Vector2d(a, b)).cwiseMax(min_m).cwiseMin(max_m);
          refined = std::max(refined, unscaled.GradientAt(p).norm());
        }
      }
    }
  }
  const double bound = refined + curvature * fine / std::numbers::sqrt2;
  if (!(bound > 0.0)) return FloorRelief{};
  const double scale = std::tan(options.max_slope_rad) / bound;
  for (FloorWave& w : waves) w.amplitude_m *= scale;
  return FloorRelief(std::move(waves));
}

}  // namespace pavilion::sim
