#include "sim/robot/raycast_drive.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace pavilion::sim {
namespace {

// A wheel whose sphere is within this of the floor is in contact (m): the row
// then lets it approach at most by the gap in one step (a speculative contact,
// as Bullet's contact breaking threshold keeps near contacts), so a wheel does
// not bounce when it comes down.
constexpr double kContactReachM = 0.005;
// Fraction of a penetration removed per step (Bullet's default contact ERP).
constexpr double kPenetrationErp = 0.2;
// Fraction of the last step's impulses the solver starts from: all of them,
// unlike Bullet's 0.85 for its contacts. Two wheels and two casters are a
// statically indeterminate support; with 15 % of the load to re-distribute
// every step the passes never converged (10 of 10 on every robot of the hall
// benchmark, a quarter of the step time with 1000 robots); with the whole
// split kept, 2–3 passes do.
constexpr double kWarmStartFactor = 1.0;
// Below this length the chassis' forward axis has no horizontal direction (a
// robot on its side): its wheels give no traction or lateral friction.
constexpr double kMinForwardNorm = 1e-6;
// Sequential-impulse passes end when the largest impulse change of a pass is
// below this fraction of the robot's weight times the step (the conformance
// test's poses are the same to 0.1 mm as with every pass run).
constexpr double kConvergedFraction = 1e-6;

}  // namespace

RaycastDrive::RaycastDrive(std::vector<RaycastWheelSpec> wheels, const RaycastDriveOptions& options)
    : wheels_(std::move(wheels)), options_(options), state_(wheels_.size()) {
  for (const RaycastWheelSpec& w : wheels_) {
    if (!(w.radius_m > 0.0)) throw std::invalid_argument("raycast wheel radius must be > 0");
    if (w.driven && !(w.max_torque_nm > 0.0 && w.friction >= 0.0)) {
      throw std::invalid_argument("raycast drive wheel needs torque > 0 and friction >= 0");
    }
    if (!(w.stiffness_npm >= 0.0) || !(w.damping_nspm >= 0.0)) {
      throw std::invalid_argument("raycast wheel stiffness and damping must be >= 0");
    }
  }
  if (options_.iterations < 1 || options_.iterations > 100) {
    throw std::invalid_argument("raycast drive iterations must be in [1, 100]");
  }
  if (!(options_.contact_stiffness_npm >= 0.0) || !(options_.contact_damping_nspm >= 0.0)) {
    throw std::invalid_argument("raycast drive contact stiffness and damping must be >= 0");
  }
  normal_rows_.reserve(wheels_.size());
  traction_rows_.reserve(wheels_.size());
  lateral_rows_.reserve(wheels_.size());
  contact_wheel_.reserve(wheels_.size());
}

struct RaycastDrive::Step {
  double inv_mass = 0.0;
  const Eigen::Matrix3d* inv_inertia = nullptr;
  // Velocities at the end of the step, gravity taken out while the contacts act.
  Eigen::Vector3d v{0, 0, 0};
  Eigen::Vector3d w{0, 0, 0};
  // The rolling direction on the floor: the chassis' forward axis made level.
  Eigen::Vector3d forward{0, 0, 0};
  Eigen::Vector3d left{0, 0, 0};
  bool level_enough = false;
  double largest_change_ns = 0.0;  // of the current pass

  Row MakeRow(const Eigen::Vector3d& direction, const Eigen::Vector3d& arm, double target) const {
    Row row;
    row.linear = direction;
    row.angular = arm.cross(direction);
    row.inv_inertia_angular = *inv_inertia * row.angular;
    row.inverse_effective_mass = 1.0 / (inv_mass + row.angular.dot(row.inv_inertia_angular));
    row.target_mps = target;
    return row;
  }

  void Apply(const Row& row, double impulse) {
    v += inv_mass * impulse * row.linear;
    w += impulse * row.inv_inertia_angular;
  }

  void SolveRow(const Row& row, double lo, double hi, double* accumulated) {
    const double velocity = row.linear.dot(v) + row.angular.dot(w);
    const double wanted = *accumulated + (row.target_mps - velocity) * row.inverse_effective_mass;
    Clamp(row, wanted, lo, hi, accumulated);
  }

  // A spring-damper row (Catto's soft constraint): the impulse also answers
  // the row's own accumulated impulse through its softness gamma, and its
  // effective mass is 1 / (J M^-1 J^T + gamma) (`soft_effective_mass`).
  void SolveSoftRow(const Row& row, double lo, double hi, double* accumulated) {
    const double velocity = row.linear.dot(v) + row.angular.dot(w);
    const double wanted = *accumulated + (row.target_mps - velocity - row.softness * *accumulated) *
                                             row.soft_effective_mass;
    Clamp(row, wanted, lo, hi, accumulated);
  }

  void Clamp(const Row& row, double wanted, double lo, double hi, double* accumulated) {
    const double clamped = std::clamp(wanted, lo, hi);
    Apply(row, clamped - *accumulated);
    largest_change_ns = std::max(largest_change_ns, std::abs(clamped - *accumulated));
    *accumulated = clamped;
  }
};

RaycastDrive::ContactFrame RaycastDrive::ReliefContact(const Eigen::Vector3d& centre,
                                                       const FloorRelief::Sample& floor,
                                                       const Eigen::Vector3d& body_forward,
                                                       double radius_m) const {
  const Eigen::Vector3d normal = floor.Normal();
  const Eigen::Vector3d below(centre.x(), centre.y(), options_.floor_z_m + floor.height_m);
  // The distance from the centre to the tangent plane, and its foot there.
  const double distance = (centre - below).dot(normal);
  ContactFrame frame;
  frame.point = centre - distance * normal;
  frame.normal = normal;
  frame.gap = distance - radius_m;
  frame.forward = body_forward - body_forward.dot(normal) * normal;
  const double norm = frame.forward.norm();
  if (norm > kMinForwardNorm) frame.forward /= norm;
  frame.left = normal.cross(frame.forward);
  return frame;
}

// Inlined into Solve (called once per robot and step).
[[gnu::always_inline]] inline void RaycastDrive::AddContactRows(
    double dt_s, const std::vector<double>& command_radps, const RaycastChassis& chassis,
    Step* step_io) {
  // A local copy, which nothing else can alias: the velocities stay in
  // registers while the impulses accumulate into the wheel states.
  Step step = *step_io;
  const Eigen::Vector3d up(0, 0, 1);
  const Eigen::Matrix3d& R = chassis.world_from_body;
  normal_rows_.clear();
  traction_rows_.clear();
  lateral_rows_.clear();
  contact_wheel_.clear();
  const bool relief = options_.relief != nullptr && !options_.relief->flat();
  for (int i = 0; i < wheel_count(); ++i) {
    const RaycastWheelSpec& spec = wheels_[i];
    WheelState& s = state_[i];
    const Eigen::Vector3d centre = chassis.com_m + R * spec.centre_m;
    // Above the relief's height below the centre (a tangent plane's vertical
    // gap; the normal one is within cos 0.5° of it): the same contact test.
    const FloorRelief::Sample floor =
        relief ? options_.relief->At(centre.head<2>()) : FloorRelief::Sample{};
    const double floor_z = relief ? options_.floor_z_m + floor.height_m : options_.floor_z_m;
    const double gap = centre.z() - floor_z - spec.radius_m;
    const bool on_floor = centre.x() >= options_.floor_min_m.x() &&
                          centre.x() <= options_.floor_max_m.x() &&
                          centre.y() >= options_.floor_min_m.y() &&
                          centre.y() <= options_.floor_max_m.y() && gap < kContactReachM;
    if (!on_floor) {
      s = {s.angle_rad, spec.driven ? command_radps[i] : 0.0, false, 0.0, 0.0, 0.0};
      continue;
    }
    // The ray from the sphere's centre straight down meets the floor at the
    // sphere's contact point; on a relief, the plane tangent to it there.
    ContactFrame frame{Eigen::Vector3d(centre.x(), centre.y(), options_.floor_z_m), up,
                       step.forward, step.left, gap};
    if (relief) frame = ReliefContact(centre, floor, R.col(0), spec.radius_m);
    const Eigen::Vector3d arm = frame.point - chassis.com_m;
    const double target = frame.gap > 0.0 ? -frame.gap / dt_s : -kPenetrationErp * frame.gap / dt_s;
    normal_rows_.push_back(step.MakeRow(frame.normal, arm, target));
    const bool sprung = spec.stiffness_npm > 0.0;
    const double k = sprung ? spec.stiffness_npm : options_.contact_stiffness_npm;
    // A sprung wheel is soft from its first touch: held rigid at a zero gap,
    // it carried the robot with the rigid wheels as an indeterminate four-point
    // support, and the solver drifted to the casters alone, the drive wheels
    // touching without load (expo_day seed 3, 172 s: a Robox glided on).
    if (k > 0.0 && (frame.gap <= 0.0 || sprung)) {
      // The deflection -gap pushes back as a spring-damper (Catto's soft
      // step: gamma = 1 / (h (c + h k)), the error reduced by h k / (c + h k));
      // short of the floor, the wheel may close the gap within the step.
      Row& row = normal_rows_.back();
      const double c = sprung ? spec.damping_nspm : options_.contact_damping_nspm;
      const double denominator = c + dt_s * k;
      row.softness = 1.0 / (dt_s * denominator);
      row.target_mps =
          frame.gap > 0.0 ? -frame.gap / dt_s : -(dt_s * k / denominator) * frame.gap / dt_s;
      row.soft_effective_mass = 1.0 / (1.0 / row.inverse_effective_mass + row.softness);
    }
    // Friction rows exist for drive wheels only; casters hold empty rows so
    // that the row lists stay parallel.
    const bool friction = spec.driven && step.level_enough;
    traction_rows_.push_back(
        friction ? step.MakeRow(frame.forward, arm, spec.radius_m * command_radps[i]) : Row{});
    lateral_rows_.push_back(friction ? step.MakeRow(frame.left, arm, 0.0) : Row{});
    contact_wheel_.push_back(i);
    if (s.contact) {
      s.normal_ns *= kWarmStartFactor;
      s.traction_ns = friction ? kWarmStartFactor * s.traction_ns : 0.0;
      s.lateral_ns = friction ? kWarmStartFactor * s.lateral_ns : 0.0;
      step.Apply(normal_rows_.back(), s.normal_ns);
      if (friction) {
        step.Apply(traction_rows_.back(), s.traction_ns);
        step.Apply(lateral_rows_.back(), s.lateral_ns);
      }
    } else {
      s.normal_ns = s.traction_ns = s.lateral_ns = 0.0;
    }
    s.contact = true;
  }
  *step_io = step;
}

// Inlined into Solve (called once per robot and step).
[[gnu::always_inline]] inline void RaycastDrive::SolveRows(double dt_s, Step* step_io) {
  // A local copy, as in AddContactRows.
  Step step = *step_io;
  const std::size_t contacts = contact_wheel_.size();
  // Passes stop early once no impulse changes by more than kConvergedFraction
  // of the robot's weight over the step.
  const double converged_ns =
      kConvergedFraction * options_.gravity_mps2 * dt_s / std::max(step.inv_mass, 1e-12);
  for (int pass = 0; pass < options_.iterations; ++pass) {
    step.largest_change_ns = 0.0;
    for (std::size_t c = 0; c < contacts; ++c) {
      WheelState& s = state_[contact_wheel_[c]];
      const Row& row = normal_rows_[c];
      constexpr double kUnbounded = std::numeric_limits<double>::infinity();
      if (row.softness > 0.0) {
        step.SolveSoftRow(row, 0.0, kUnbounded, &s.normal_ns);
      } else {
        step.SolveRow(row, 0.0, kUnbounded, &s.normal_ns);
      }
    }
    // Friction after the normals, bounded by their current impulses (a
    // friction pyramid, as the reference's two friction rows per contact).
    for (std::size_t c = 0; c < contacts; ++c) {
      const RaycastWheelSpec& spec = wheels_[contact_wheel_[c]];
      if (!spec.driven || !step.level_enough) continue;
      WheelState& s = state_[contact_wheel_[c]];
      const double grip = spec.friction * s.normal_ns;
      const double drive =
          engaged_ ? std::min(grip, spec.max_torque_nm / spec.radius_m * dt_s) : 0.0;
      step.SolveRow(traction_rows_[c], -drive, drive, &s.traction_ns);
      step.SolveRow(lateral_rows_[c], -grip, grip, &s.lateral_ns);
    }
    if (step.largest_change_ns <= converged_ns) break;
  }
  *step_io = step;
}

// Inlined into Solve (called once per robot and step).
[[gnu::always_inline]] inline void RaycastDrive::SetWheelRates(
    double dt_s, const std::vector<double>& command_radps, const Step& step) {
  // The wheels' rates: the commanded one while the motor holds it (rolling or
  // skidding); rolling with the ground when the torque limit binds first.
  for (int i = 0; i < wheel_count(); ++i) {
    if (!wheels_[i].driven) continue;
    state_[i].rate_radps = command_radps[i];
  }
  for (std::size_t c = 0; c < contact_wheel_.size(); ++c) {
    const int i = contact_wheel_[c];
    const RaycastWheelSpec& spec = wheels_[i];
    if (!spec.driven || !step.level_enough) continue;
    const WheelState& s = state_[i];
    const double torque_bound = spec.max_torque_nm / spec.radius_m * dt_s;
    const bool torque_limited =
        torque_bound < spec.friction * s.normal_ns && std::abs(s.traction_ns) >= torque_bound;
    if (torque_limited || !engaged_) {
      const Row& row = traction_rows_[c];
      state_[i].rate_radps = (row.linear.dot(step.v) + row.angular.dot(step.w)) / spec.radius_m;
    }
  }
}

void RaycastDrive::Solve(double dt_s, const std::vector<double>& command_radps,
                         RaycastChassis* chassis) {
  const Eigen::Vector3d up(0, 0, 1);
  const Eigen::Matrix3d& R = chassis->world_from_body;
  Step step;
  step.inv_mass = chassis->inverse_mass;
  step.inv_inertia = &chassis->inverse_inertia;
  step.v = chassis->linear_mps - options_.gravity_mps2 * dt_s * up;
  step.w = chassis->angular_radps;
  step.forward = R.col(0);
  step.forward.z() = 0.0;
  step.level_enough = step.forward.norm() > kMinForwardNorm;
  if (step.level_enough) step.forward.normalize();
  step.left = up.cross(step.forward);

  AddContactRows(dt_s, command_radps, *chassis, &step);
  SolveRows(dt_s, &step);
  SetWheelRates(dt_s, command_radps, step);
  chassis->linear_mps = step.v + options_.gravity_mps2 * dt_s * up;
  chassis->angular_radps = step.w;
}

void RaycastDrive::Integrate(double dt_s) {
  for (WheelState& s : state_) s.angle_rad += s.rate_radps * dt_s;
}

void RaycastDrive::Reset() {
  for (WheelState& s : state_) s = {s.angle_rad, 0.0, false, 0.0, 0.0, 0.0};
}

}  // namespace pavilion::sim
