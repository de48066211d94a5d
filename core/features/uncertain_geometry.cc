#include "core/features/uncertain_geometry.h"

#include <cmath>
#include <stdexcept>

namespace pavilion::core {

Eigen::Vector2d Line::normal() const { return {std::cos(alpha_rad), std::sin(alpha_rad)}; }

double Line::SignedDistance(const Eigen::Vector2d& point) const {
  return normal().dot(point) - r_m;
}

bool Line::IsVisibleFrom(const Eigen::Vector2d& point) const { return normal().dot(point) < r_m; }

Line LineInChild(const Line& line_in_parent, const Pose2& parent_from_child,
                 const Eigen::Matrix3d& pose_covariance, LineTransformJacobians* jacobians) {
  const double a = line_in_parent.alpha_rad;
  const double ca = std::cos(a);
  const double sa = std::sin(a);
  const double x = parent_from_child.x_m;
  const double y = parent_from_child.y_m;
  Line out;
  out.alpha_rad = NormalizeAngle(a - parent_from_child.theta_rad);  // eq. B.23
  out.r_m = line_in_parent.r_m - x * ca - y * sa;                   // eq. B.22
  LineTransformJacobians J;
  J.J_line_line << 1.0, 0.0,        // eq. B.12
      x * sa - y * ca, 1.0;         // eq. B.13
  J.J_line_pose << 0.0, 0.0, -1.0,  // eq. B.14
      -ca, -sa, 0.0;                // eq. B.15
  // Eq. B.16, no robot-to-feature cross-correlation.
  out.covariance = J.J_line_line * line_in_parent.covariance * J.J_line_line.transpose() +
                   J.J_line_pose * pose_covariance * J.J_line_pose.transpose();
  if (jacobians != nullptr) *jacobians = J;
  return out;
}

Line LineInParent(const Line& line_in_child, const Pose2& parent_from_child,
                  const Eigen::Matrix3d& pose_covariance, LineTransformJacobians* jacobians) {
  const double x = parent_from_child.x_m;
  const double y = parent_from_child.y_m;
  // Eqs. B.22-B.23 solved for the parent parameters:
  //   alpha_p = alpha_c + theta,  r_p = r_c + x cos(alpha_p) + y sin(alpha_p).
  const double a = NormalizeAngle(line_in_child.alpha_rad + parent_from_child.theta_rad);
  const double ca = std::cos(a);
  const double sa = std::sin(a);
  const double dr_dalpha = -x * sa + y * ca;
  Line out;
  out.alpha_rad = a;
  out.r_m = line_in_child.r_m + x * ca + y * sa;
  LineTransformJacobians J;
  J.J_line_line << 1.0, 0.0, dr_dalpha, 1.0;
  J.J_line_pose << 0.0, 0.0, 1.0, ca, sa, dr_dalpha;
  out.covariance = J.J_line_line * line_in_child.covariance * J.J_line_line.transpose() +
                   J.J_line_pose * pose_covariance * J.J_line_pose.transpose();
  if (jacobians != nullptr) *jacobians = J;
  return out;
}

Point2Uncertain EndpointOnRay(const Line& line, double bearing_rad, double bearing_sigma_rad) {
  const double r = line.r_m;
  const double a = line.alpha_rad;
  const double ct = std::cos(bearing_rad);
  const double st = std::sin(bearing_rad);
  const double phi = a - bearing_rad;
  const double c = std::cos(phi);
  if (c == 0.0) {
    throw std::invalid_argument("EndpointOnRay: ray parallel to the line");
  }
  const double tan_phi_over_c = std::sin(phi) / (c * c);
  Point2Uncertain p;
  p.position_m = {r * ct / c, r * st / c};  // eq. 5.3
  // Jacobian of eq. 5.3 with respect to (alpha, r, theta_e), eqs. 5.4-5.6.
  Eigen::Matrix<double, 2, 3> J;
  J << r * ct * tan_phi_over_c, ct / c, -r * std::sin(a) / (c * c),  //
      r * st * tan_phi_over_c, st / c, r * std::cos(a) / (c * c);
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  C.topLeftCorner<2, 2>() = line.covariance;
  C(2, 2) = bearing_sigma_rad * bearing_sigma_rad;  // eq. 5.2
  p.covariance = J * C * J.transpose();             // eqs. 5.7-5.9
  return p;
}

Segment MakeSegment(const Line& line, double first_bearing_rad, double last_bearing_rad,
                    double bearing_sigma_rad, int point_count, int first_index, int last_index) {
  Segment s;
  s.line = line;
  s.first_endpoint = EndpointOnRay(line, first_bearing_rad, bearing_sigma_rad);
  s.last_endpoint = EndpointOnRay(line, last_bearing_rad, bearing_sigma_rad);
  const double sa = std::sin(line.alpha_rad);
  const double ca = std::cos(line.alpha_rad);
  const Eigen::Vector2d d = s.first_endpoint.position_m - s.last_endpoint.position_m;
  // Eq. 5.15; its sign depends on the order of the endpoints, the length does not.
  s.length_m = std::abs(d.x() * sa - d.y() * ca);
  // Eq. 5.16: the endpoints' variances along the supporting line.
  const Eigen::Matrix2d& c1 = s.first_endpoint.covariance;
  const Eigen::Matrix2d& c2 = s.last_endpoint.covariance;
  s.length_variance_m2 = (c1(0, 0) + c2(0, 0)) * sa * sa + (c1(1, 1) + c2(1, 1)) * ca * ca -
                         (c1(0, 1) + c2(0, 1)) * std::sin(2.0 * line.alpha_rad);
  s.point_count = point_count;
  s.first_index = first_index;
  s.last_index = last_index;
  return s;
}

}  // namespace pavilion::core
