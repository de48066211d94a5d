#include "core/localization/ekf_update.h"

#include <Eigen/Cholesky>
#include <stdexcept>

namespace pavilion::core {
namespace {

template <int Dim>
bool Update(const Eigen::Matrix<double, Dim, 1>& v, const Eigen::Matrix<double, Dim, 3>& H,
            const Eigen::Matrix<double, Dim, Dim>& N, PoseWithCovariance* state) {
  const Eigen::Matrix3d& P = state->covariance;
  const Eigen::Matrix<double, Dim, 3> HP = H * P;
  const Eigen::Matrix<double, Dim, Dim> S = HP * H.transpose() + N;  // eq. 4.12
  const Eigen::LLT<Eigen::Matrix<double, Dim, Dim>> llt(S);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::Matrix<double, 3, Dim> W = llt.solve(HP).transpose();  // eq. 4.13 (P, S symmetric)
  const Eigen::Vector3d dx = W * v;                                   // eq. 4.14
  state->pose.x_m += dx.x();
  state->pose.y_m += dx.y();
  state->pose.theta_rad = NormalizeAngle(state->pose.theta_rad + dx.z());
  const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() - W * H;
  const Eigen::Matrix3d joseph = A * P * A.transpose() + W * N * W.transpose();  // eq. 4.15
  state->covariance = 0.5 * (joseph + joseph.transpose());
  return true;
}

template <int Dim>
bool UpdateCorrelated(const Eigen::Matrix<double, Dim, 1>& v,
                      const Eigen::Matrix<double, Dim, 3>& H,
                      const Eigen::Matrix<double, Dim, Dim>& N,
                      const Eigen::Matrix<double, Dim, 2>& G, const PairedMapFeature& map,
                      PoseWithCovariance* state, PoseMapCrossCovariance* correlations) {
  const Eigen::Matrix3d& P = state->covariance;
  const PoseMapCross C = correlations->Get(map.feature);
  const Eigen::Matrix<double, 3, Dim> PHt = P * H.transpose() + C * G.transpose();
  const Eigen::Matrix<double, Dim, Dim> HCGt = H * C * G.transpose();
  const Eigen::Matrix<double, Dim, Dim> S = H * P * H.transpose() + HCGt + HCGt.transpose() + N;
  const Eigen::LLT<Eigen::Matrix<double, Dim, Dim>> llt(S);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::Matrix<double, 3, Dim> W = llt.solve(PHt.transpose()).transpose();
  const Eigen::Vector3d dx = W * v;
  state->pose.x_m += dx.x();
  state->pose.y_m += dx.y();
  state->pose.theta_rad = NormalizeAngle(state->pose.theta_rad + dx.z());
  const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() - W * H;
  const Eigen::Matrix3d cross = A * C * G.transpose() * W.transpose();
  const Eigen::Matrix3d joseph =
      A * P * A.transpose() + W * N * W.transpose() - cross - cross.transpose();
  state->covariance = 0.5 * (joseph + joseph.transpose());
  const PoseMapCross C_paired = A * C - W * G * map.map_covariance;
  correlations->Transform(A);
  correlations->Set(map.feature, C_paired);
  return true;
}

}  // namespace

bool UpdatePoseEstimate(const Eigen::Vector2d& innovation, const Eigen::Matrix<double, 2, 3>& H,
                        const Eigen::Matrix2d& N, int dimension, const PairedMapFeature& map,
                        PoseWithCovariance* state, PoseMapCrossCovariance* correlations) {
  if (correlations == nullptr) return UpdatePoseEstimate(innovation, H, N, dimension, state);
  if (!innovation.allFinite() || !H.allFinite() || !N.allFinite() || !map.J_z_map.allFinite() ||
      !map.map_covariance.allFinite()) {
    return false;
  }
  if (dimension == 2) {
    return UpdateCorrelated<2>(innovation, H, N, map.J_z_map, map, state, correlations);
  }
  if (dimension == 1) {
    return UpdateCorrelated<1>(innovation.head<1>(), H.topRows<1>(), N.topLeftCorner<1, 1>(),
                               map.J_z_map.topRows<1>(), map, state, correlations);
  }
  throw std::invalid_argument("UpdatePoseEstimate: dimension must be 1 or 2");
}

bool UpdatePoseEstimate(const Eigen::Vector2d& innovation, const Eigen::Matrix<double, 2, 3>& H,
                        const Eigen::Matrix2d& N, int dimension, PoseWithCovariance* state) {
  if (!innovation.allFinite() || !H.allFinite() || !N.allFinite()) return false;
  if (dimension == 2) return Update<2>(innovation, H, N, state);
  if (dimension == 1) {
    return Update<1>(innovation.head<1>(), H.topRows<1>(), N.topLeftCorner<1, 1>(), state);
  }
  throw std::invalid_argument("UpdatePoseEstimate: dimension must be 1 or 2");
}

}  // namespace pavilion::core
