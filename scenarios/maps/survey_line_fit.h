#pragma once

// Line fits of measured wall corners for map derivation (eq. B.4), and the
// survey error of whole walls (issue 20, `realism: realistic`).

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace pavilion::scenarios {

// Total-least-squares line through points (orthogonal distances, equal
// weights), its normal oriented like `hint`: (alpha, r) with eq. B.4's sign.
std::pair<double, double> FitLine(const std::vector<Eigen::Vector2d>& pts,
                                  const Eigen::Vector2d& hint);

// Covariance of (alpha, r) of FitLine when every coordinate has variance
// sigma^2, by first-order propagation with a central-difference Jacobian.
Eigen::Matrix2d FitCovariance(const std::vector<Eigen::Vector2d>& pts, const Eigen::Vector2d& hint,
                              double sigma);

// A surveyor who places the two ends of a wall off along its normal by
// `e_first` and `e_last` (the corners with the smallest and largest
// coordinate along `along`), the points in between by linear interpolation:
// the whole wall shifted and turned.
void ShiftWall(const Eigen::Vector2d& normal, const Eigen::Vector2d& along, double e_first,
               double e_last, std::vector<Eigen::Vector2d>* corners);

// Covariance of FitLine's (alpha, r) when both ends are off independently
// with standard deviation sigma (first order, central differences).
Eigen::Matrix2d WallEndCovariance(const std::vector<Eigen::Vector2d>& corners,
                                  const Eigen::Vector2d& normal, const Eigen::Vector2d& along,
                                  double sigma);

}  // namespace pavilion::scenarios
