#include "sim/world/bullet_conversions.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>

namespace pavilion::sim {

btVector3 ToBt(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

double YawOf(const btTransform& t) {
  btScalar yaw, pitch, roll;
  t.getBasis().getEulerZYX(yaw, pitch, roll);
  return static_cast<double>(yaw);
}

btTransform PlanarTransform(const core::Pose2& pose, double z) {
  btTransform t;
  t.setIdentity();
  t.setOrigin(btVector3(pose.x_m, pose.y_m, z));
  t.setRotation(btQuaternion(btVector3(0, 0, 1), pose.theta_rad));
  return t;
}

std::unique_ptr<btBoxShape> MakeBox(const Eigen::Vector3d& half_m) {
  auto box = std::make_unique<btBoxShape>(ToBt(half_m));
  const double margin = std::min(box->getMargin(), 0.25 * half_m.minCoeff());
  box->setMargin(margin);  // keeps the outer extents at half_m
  return box;
}

btTransform BoxTransform(const Box& box) {
  btTransform t;
  t.setIdentity();
  t.setOrigin(btVector3(box.pose.x_m, box.pose.y_m, box.base_z_m + 0.5 * box.size_m.z()));
  t.setRotation(btQuaternion(btVector3(0, 0, 1), box.pose.theta_rad));
  return t;
}

}  // namespace pavilion::sim
