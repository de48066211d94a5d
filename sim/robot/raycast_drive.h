#pragma once

#include <Eigen/Core>
#include <vector>

#include "sim/world/floor_relief.h"

namespace pavilion::sim {

// The fast wheel model's contact solver (sim::WheelModel::kRaycast): a robot is
// one rigid body, and each drive wheel and caster a sphere fixed under it whose
// contact with the floor plane is found by a vertical ray from its centre (the
// exact contact of a sphere on a plane, as the articulated reference's sphere
// wheels touch the floor). On an uneven floor (FloorRelief) each wheel meets
// the plane tangent to the relief below its centre: the contact's normal is
// the floor's, its traction and lateral directions lie in that plane. Every step, before the
// physics engine integrates, the contacts' normal, traction and lateral friction impulses are
// solved on the chassis alone by sequential impulses, as Bullet solves the reference's contacts,
// but without the wheel bodies, joints and contact manifolds.
//
// The drive wheels are massless and turned by ideal motors up to their torque
// limit: while the motor holds, the wheel turns at its commanded rate whatever
// the ground does, so a push or a skid moves the chassis but not the wheels
// (slip the encoders do not see); when the torque limit binds (driving against
// a wall), the wheel rolls with the ground instead. Casters are frictionless.
// Free of any physics-engine type, so that it is tested on its own.

// A wheel or caster of the fast model, in the chassis body frame (origin at the
// centre of mass, axes of the robot's base frame).
struct RaycastWheelSpec {
  Eigen::Vector3d centre_m{0, 0, 0};  // sphere centre when the robot rests on the floor
  double radius_m = 0.1;              // > 0
  bool driven = false;                // a drive wheel (else a caster)
  double friction = 0.0;              // combined coefficient with the floor, >= 0 (drive wheels)
  double max_torque_nm = 0.0;         // motor torque limit, > 0 (drive wheels)
  // A sprung wheel (a caster on a suspension): its floor contact pushes back
  // as a spring-damper of these rates, N/m and N·s/m, instead of the drive's
  // `contact_stiffness_npm` (0: as the others). The spring is at rest, its
  // force zero, when the sphere just touches the floor.
  double stiffness_npm = 0.0;
  double damping_nspm = 0.0;
};

// The chassis as the solver sees it, world frame (z up; the floor is z = floor_z).
struct RaycastChassis {
  Eigen::Matrix3d world_from_body = Eigen::Matrix3d::Identity();  // orientation
  Eigen::Vector3d com_m{0, 0, 0};                                 // centre of mass
  double inverse_mass = 1.0;
  Eigen::Matrix3d inverse_inertia = Eigen::Matrix3d::Identity();  // world frame, about the COM
  Eigen::Vector3d linear_mps{0, 0, 0};  // in: now; out: after the impulses
  Eigen::Vector3d angular_radps{0, 0, 0};
};

struct RaycastDriveOptions {
  int iterations = 10;                      // sequential-impulse passes per step, [1, 100]
  double gravity_mps2 = 9.81;               // acts during the step, >= 0
  double floor_z_m = 0.0;                   // height of the floor plane
  Eigen::Vector2d floor_min_m{-1e9, -1e9};  // the floor's extent: no support beyond it
  Eigen::Vector2d floor_max_m{1e9, 1e9};
  // Slopes and bumps above floor_z_m; null or flat: the plane alone. Not
  // owned: it outlives the drive (the world description holds it).
  const FloorRelief* relief = nullptr;
  // The tyres' and casters' compliance under load, N/m and N·s/m per wheel
  // (0: rigid, contact penetration removed at Bullet's default rate). Four
  // rigid points cannot all touch an uneven floor; a real wheel deflects a
  // millimetre or two under a tenth of a tonne and carries its share.
  double contact_stiffness_npm = 0.0;
  double contact_damping_nspm = 0.0;
};

// Contact solver and wheel state of one robot.
class RaycastDrive {
 public:
  RaycastDrive(std::vector<RaycastWheelSpec> wheels, const RaycastDriveOptions& options);

  // Solves the contacts of one step of `dt_s` and changes the chassis' velocities
  // by their impulses; gravity is taken as acting over the step (the physics
  // engine adds it afterwards). `command_radps` holds a commanded rate per wheel
  // (relative to the chassis, positive forward; ignored for casters).
  void Solve(double dt_s, const std::vector<double>& command_radps, RaycastChassis* chassis);
  // Advances the wheel angles by their rates over the step.
  void Integrate(double dt_s);
  // The robot is put down at rest (a kidnap): no impulses to warm-start from.
  void Reset();
  // Motors engaged (default) turn the drive wheels at their commands; with
  // the motors disengaged the wheels roll freely with the ground (no traction:
  // staff pushing a robot switched off, thesis §6.5), and their encoders see
  // the rolling.
  void SetEngaged(bool engaged) { engaged_ = engaged; }
  bool engaged() const { return engaged_; }

  int wheel_count() const { return static_cast<int>(wheels_.size()); }
  const RaycastWheelSpec& wheel(int i) const { return wheels_[i]; }
  // A wheel's rotation relative to the chassis, unwrapped (rad), and its rate (rad/s).
  double angle_rad(int i) const { return state_[i].angle_rad; }
  double rate_radps(int i) const { return state_[i].rate_radps; }
  bool in_contact(int i) const { return state_[i].contact; }
  // Normal impulse of the wheel's floor contact in the last step (N·s).
  double normal_impulse_ns(int i) const { return state_[i].normal_ns; }

 private:
  bool engaged_ = true;
  struct WheelState {
    double angle_rad = 0.0;
    double rate_radps = 0.0;
    bool contact = false;
    // Accumulated impulses of the last step (warm start of the next).
    double normal_ns = 0.0;
    double traction_ns = 0.0;
    double lateral_ns = 0.0;
  };
  // One constraint row on the chassis: impulse λ along J = [linear, angular].
  struct Row {
    Eigen::Vector3d linear;
    Eigen::Vector3d angular;
    Eigen::Vector3d inv_inertia_angular;  // I⁻¹ · angular
    double inverse_effective_mass = 0.0;  // 1 / (J M⁻¹ Jᵀ)
    double target_mps = 0.0;              // wanted J·v
    // A soft (spring-damper) row: gamma, and 1 / (J M⁻¹ Jᵀ + gamma). 0: rigid.
    double softness = 0.0;
    double soft_effective_mass = 0.0;
  };

  // The chassis' velocities and mass properties while one step is solved.
  struct Step;
  // Where a wheel meets the floor: the contact point, the floor's normal
  // there, the rolling and lateral directions in the floor's plane, and the
  // sphere's gap to it (negative: penetration).
  struct ContactFrame {
    Eigen::Vector3d point;
    Eigen::Vector3d normal;
    Eigen::Vector3d forward;
    Eigen::Vector3d left;
    double gap = 0.0;
  };
  // The contact of a sphere at `centre` on the plane tangent to the relief
  // below it; `body_forward` is the chassis' forward axis.
  ContactFrame ReliefContact(const Eigen::Vector3d& centre, const FloorRelief::Sample& floor,
                             const Eigen::Vector3d& body_forward, double radius_m) const;

  // The contact rows of the wheels on the floor, with their warm-start impulses applied.
  void AddContactRows(double dt_s, const std::vector<double>& command_radps,
                      const RaycastChassis& chassis, Step* step_io);
  // Sequential-impulse passes over the contact rows until they converge.
  void SolveRows(double dt_s, Step* step_io);
  // The drive wheels' rates after the solve.
  void SetWheelRates(double dt_s, const std::vector<double>& command_radps, const Step& step);

  std::vector<RaycastWheelSpec> wheels_;
  RaycastDriveOptions options_;
  std::vector<WheelState> state_;
  // Scratch rows of the current step, kept to avoid per-step allocations.
  std::vector<Row> normal_rows_, traction_rows_, lateral_rows_;
  std::vector<int> contact_wheel_;  // wheel index of each contact row
};

}  // namespace pavilion::sim
