#include "core/odometry/wheel_noise_fit.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>
#include <utility>

// =============================================================================
// Noise (§2.3). After the systematic correction, the end-pose residual e_i of
// run i is modelled as N(0, P_i(k)), where P_i(k) is eq. 2.13 propagated along
// the run's recorded wheel travels from P = 0 with U = diag(k|s_r|, k|s_l|). P
// is linear in k (every term of eq. 2.13 is, starting from zero):
// P_i(k) = k·P_i(1). The log-likelihood of N runs is
//     ℓ(k) = −½ Σ_i [ log det(k·P_i(1)) + e_iᵀ P_i(1)⁻¹ e_i / k ] + const
//          = −½ [ 3N·log k + Σ_i e_iᵀ P_i(1)⁻¹ e_i / k ] + const,
// and dℓ/dk = 0 gives
//     k̂ = (1/(3N)) Σ_i e_iᵀ P_i(1)⁻¹ e_i.                               (C5)
// Since 3N·k̂/k ~ χ²(3N) under the model, k̂ has a relative standard deviation
// of √(2/(3N)) (16% for 25 runs). The three systematic parameters fitted to
// the same runs take about 3/(3N) of the residual variance with them (1%
// here), which we leave as it is. The residuals also hold what the systematic
// model cannot (slip that depends on speed, lateral creep on arcs, turns that
// slide on when they stop): that is the physics' share of k, which is why the
// calibration runs vary speed, direction, length and curvature.
// We estimate one k = k_L = k_R: the standard runs are mirror-symmetric (each
// left turn or arc has a right one), so their end poses inform k_L + k_R well
// and k_L − k_R hardly at all (a straight run's or a spin's end covariance
// depends on the sum alone), and the encoders' noise is configured symmetric.
//
// (C5'): with the turn-slip term, P_i is linear in the two: P_i = k·A_i +
// k_turn·B_i, with A_i and B_i eq. 2.13 propagated with unit k and unit
// k_turn. The log-likelihood
//     ℓ = −½ Σ_i [log det P_i + e_iᵀ P_i⁻¹ e_i]
// has no closed-form maximum with two terms: it is maximized over a grid in
// log k × log k_turn (and k_turn = 0), then refined by coordinate search.
// =============================================================================

namespace pavilion::core {
namespace {

// The grid of the (C5') likelihood search: log10 of k and k_turn (m) from
// kLogKMin to kLogKMax in kLikelihoodGridSteps steps.
constexpr double kLogKMin = -10.0;
constexpr double kLogKMax = -3.0;
constexpr int kLikelihoodGridSteps = 56;
// Coordinate refinement: the first multiplicative step, and the step at which it stops.
constexpr double kFirstRefineStep = 1.5;
constexpr double kLastRefineStep = 1.0001;

// ℓ(k, k_turn) up to a constant; −inf where a P_i is not positive definite.
double LogLikelihood(const std::vector<NoiseFitRun>& runs, double k, double k_turn) {
  double l = 0.0;
  for (const NoiseFitRun& run : runs) {
    const Eigen::Matrix3d p = k * run.unit_k + k_turn * run.unit_turn;
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(p);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
      return -std::numeric_limits<double>::infinity();
    }
    l -= 0.5 * (ldlt.vectorD().array().log().sum() + run.residual.dot(ldlt.solve(run.residual)));
  }
  return l;
}

struct Candidate {
  double k = 1e-6;
  double turn = 0.0;
  double l = -std::numeric_limits<double>::infinity();
};

// The best point of the log-grid (k_turn also 0).
Candidate GridSearch(const std::vector<NoiseFitRun>& runs) {
  Candidate best;
  for (int a = 0; a <= kLikelihoodGridSteps; ++a) {
    const double k = std::pow(10.0, kLogKMin + (kLogKMax - kLogKMin) * a / kLikelihoodGridSteps);
    for (int b = -1; b <= kLikelihoodGridSteps; ++b) {
      const double turn =
          b < 0 ? 0.0 : std::pow(10.0, kLogKMin + (kLogKMax - kLogKMin) * b / kLikelihoodGridSteps);
      const double l = LogLikelihood(runs, k, turn);
      if (l > best.l) best = {k, turn, l};
    }
  }
  return best;
}

// Coordinate refinement: multiplicative steps that shrink.
Candidate Refine(const std::vector<NoiseFitRun>& runs, Candidate best) {
  for (double step = kFirstRefineStep; step > kLastRefineStep; step = std::sqrt(step)) {
    for (bool improved = true; improved;) {
      improved = false;
      for (const auto& [k, turn] : {std::pair{best.k * step, best.turn},
                                    {best.k / step, best.turn},
                                    {best.k, best.turn * step},
                                    {best.k, best.turn / step}}) {
        const double l = LogLikelihood(runs, k, turn);
        if (l > best.l) {
          best = {k, turn, l};
          improved = true;
        }
      }
    }
  }
  return best;
}

}  // namespace

WheelNoiseFit FitWheelNoise(const std::vector<NoiseFitRun>& runs) {
  const Candidate best = Refine(runs, GridSearch(runs));
  WheelNoiseFit fit;
  fit.k_m = best.k;
  fit.k_turn_m = best.turn;
  for (const NoiseFitRun& run : runs) {
    const Eigen::Matrix3d p = best.k * run.unit_k + best.turn * run.unit_turn;
    fit.mahalanobis_sq.push_back(run.residual.dot(p.ldlt().solve(run.residual)));
  }
  return fit;
}

}  // namespace pavilion::core
