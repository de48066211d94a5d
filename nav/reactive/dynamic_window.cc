#include "nav/reactive/dynamic_window.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/types/pose2.h"

namespace pavilion::nav {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Slack when comparing a candidate's speed with a cap (m/s, rad/s): grid
// values are sums of doubles.
constexpr double kLimitSlack = 1e-9;
// Wheel-space grid for the constructor's braking-reach check (per wheel).
constexpr int kReachCheckSamples = 101;
// Slack (m/s) on the contact normal · point velocity test: tangential
// motions give 0 up to rounding.
constexpr double kRateSlack_mps = 1e-9;
// A contact point may approach at up to this fraction of its speed along the
// robot (about 2°): a motion that grazes a contact counts as sliding along it.
// A bumper zone or a wall along a side of the mesh hull spans facets a degree
// or so apart, and the strict first-order test then forbade both forward and
// back — a robot pressed along its side froze (expo_tours_fallback seed 5).
// The contact polygons still bound how much deeper any contact gets before
// standstill (kContactSlack_m).
constexpr double kSlideSlope = 0.035;

double Clamp01(double x) { return std::clamp(x, 0.0, 1.0); }

// Sample k of n from lo to hi. A sum that cancels to rounding noise is 0: the
// middle sample of a window about standstill came out as 1e-17 m/s, a "move"
// that escaped the objective's no-clearance-for-stopping rule, scored full
// clearance and held a robot still beside any obstacle (the deadlocked pair
// of expo_tours_fallback seed 5 stood so for minutes).
double GridSpeed(double lo, double hi, int k, int n) {
  constexpr double kZeroMps = 1e-9;
  const double v = lo + (hi - lo) * k / (n - 1);
  return std::abs(v) < kZeroMps ? 0.0 : v;
}

// The largest speed from which holding it one period T and then braking at
// `decel` stops within `distance`: s·T + s²/(2·decel) = distance.
double StoppableSpeed(double distance, double decel, double period_s) {
  if (distance <= 0.0) return 0.0;
  return decel * (-period_s + std::sqrt(period_s * period_s + 2.0 * distance / decel));
}

}  // namespace

WheelVelocity RampTowards(const WheelVelocity& from, const WheelVelocity& to, double max_step_mps) {
  const double dl = to.left_mps - from.left_mps;
  const double dr = to.right_mps - from.right_mps;
  const double largest = std::max(std::abs(dl), std::abs(dr));
  if (largest <= max_step_mps) return to;
  const double f = max_step_mps / largest;
  return {from.left_mps + f * dl, from.right_mps + f * dr};
}

void DynamicWindowOptions::Validate() const {
  auto fail = [](const std::string& message) { throw std::invalid_argument(message); };
  auto in = [](double x, double lo, double hi) { return x > lo && x <= hi; };
  if (!in(period_s, 0.0, 1.0)) fail("period_s must be in (0, 1] s");
  if (samples_per_wheel < 11 || samples_per_wheel > 101 || samples_per_wheel % 2 == 0) {
    fail("samples_per_wheel must be odd in [11, 101]");
  }
  if (!in(wheelbase_m, 0.0, 5.0)) fail("wheelbase_m must be in (0, 5] m");
  if (!in(max_wheel_speed_mps, 0.0, 5.0)) fail("max_wheel_speed_mps must be in (0, 5] m/s");
  if (!in(max_wheel_accel_mps2, 0.0, 20.0)) fail("max_wheel_accel_mps2 must be in (0, 20] m/s^2");
  if (!in(max_speed_mps, 0.0, max_wheel_speed_mps)) {
    fail("max_speed_mps must be in (0, max_wheel_speed_mps] m/s");
  }
  if (!in(ttc_horizon_s, 0.0, 60.0)) fail("ttc_horizon_s must be in (0, 60] s");
  if (!(max_turn_rate_radps > 0.0 && max_turn_rate_radps <= 20.0)) {
    fail("max_turn_rate_radps must be in (0, 20] rad/s");
  }
  if (!(heading_horizon_s >= period_s && heading_horizon_s <= 10.0)) {
    fail("heading_horizon_s must be in [period_s, 10] s");
  }
  if (!(weight_heading >= 0.0 && std::isfinite(weight_heading))) {
    fail("weight_heading must be finite and >= 0");
  }
  if (!(weight_speed >= 0.0 && std::isfinite(weight_speed))) {
    fail("weight_speed must be finite and >= 0");
  }
  if (!(weight_clearance >= 0.0 && std::isfinite(weight_clearance))) {
    fail("weight_clearance must be finite and >= 0");
  }
  if (weight_heading + weight_speed + weight_clearance <= 0.0) {
    fail("weight_heading, weight_speed, weight_clearance must not all be 0");
  }
  if (!in(goal_tolerance_m, 0.0, 1.0)) fail("goal_tolerance_m must be in (0, 1] m");
  if (!(max_contact_depth_m >= 0.0 && max_contact_depth_m <= 0.1)) {
    fail("max_contact_depth_m must be in [0, 0.1] m");
  }
  if (!in(goal_heading_tolerance_rad, 0.0, 0.5)) {
    fail("goal_heading_tolerance_rad must be in (0, 0.5] rad");
  }
  TableOptions().Validate();
}

CollisionTableOptions DynamicWindowOptions::TableOptions() const {
  return {lookahead_m, table_cell_m, table_direction_bins, safety_margin_m};
}

DynamicWindow::DynamicWindow(const DynamicWindowOptions& options, core::Polygon2 robot_polygon)
    : options_((options.Validate(), options)),
      robot_polygon_(std::move(robot_polygon)),
      table_(SharedCollisionTable(options_.TableOptions(), robot_polygon_)) {
  margin_polygon_ = InflateConvexPolygon(robot_polygon_, options_.safety_margin_m);
  cycle_margin_m_ = options_.safety_margin_m;
  const core::Polygon2 unit_offset = InflateConvexPolygon(robot_polygon_, 1.0);
  const std::size_t vertices = robot_polygon_.size();
  miter_.resize(vertices);
  edge_normals_.resize(vertices);
  edge_offsets_.resize(vertices);
  for (std::size_t i = 0; i < vertices; ++i) {
    miter_[i] = unit_offset[i] - robot_polygon_[i];
    const Eigen::Vector2d d = robot_polygon_[(i + 1) % vertices] - robot_polygon_[i];
    edge_normals_[i] = Eigen::Vector2d(d.y(), -d.x()).normalized();
    edge_offsets_[i] = edge_normals_[i].dot(robot_polygon_[i]);
  }
  const core::Polygon2 deepest =
      InflateConvexPolygon(robot_polygon_, -(options_.max_contact_depth_m + kContactSlack_m));
  if (!IsConvexCounterClockwise(deepest)) {
    throw std::invalid_argument("max_contact_depth_m must leave the shrunk robot polygon convex");
  }
  near_offset_m_ = options_.safety_margin_m + std::sqrt(2.0) * options_.table_cell_m;
  near_radius_m_ = Circumradius(InflateConvexPolygon(robot_polygon_, near_offset_m_));
  const double w = options_.max_wheel_speed_mps;
  double reach_m = 0.0;
  for (int i = 0; i < kReachCheckSamples; ++i) {
    for (int j = 0; j < kReachCheckSamples; ++j) {
      const WheelVelocity wheels{-w + 2.0 * w * i / (kReachCheckSamples - 1),
                                 -w + 2.0 * w * j / (kReachCheckSamples - 1)};
      if (std::abs(0.5 * (wheels.left_mps + wheels.right_mps)) > options_.max_speed_mps) continue;
      reach_m = std::max(reach_m, StoppingArc(wheels));
    }
  }
  if (options_.lookahead_m < reach_m) {
    throw std::invalid_argument("lookahead_m must be >= the braking reach " +
                                std::to_string(reach_m) + " m");
  }
  const int n = options_.samples_per_wheel;
  candidates_.resize(static_cast<std::size_t>(n) * n);
  bin_arc_m_.resize(table_->bins());
  cell_stamp_.assign(static_cast<std::size_t>(table_->cells()), 0u);
}

double DynamicWindow::StoppingArc(const WheelVelocity& command) const {
  const BodyTwist twist =
      TwistFromWheels(command.left_mps, command.right_mps, options_.wheelbase_m);
  const double brake_s = std::max(std::abs(command.left_mps), std::abs(command.right_mps)) /
                         options_.max_wheel_accel_mps2;
  return table_->GeneralizedSpeed(twist) * (options_.period_s + 0.5 * brake_s);
}

WheelVelocity DynamicWindow::BrakeCommand(const WheelVelocity& current) const {
  const double step_mps = options_.max_wheel_accel_mps2 * options_.period_s;
  const double m = std::max(std::abs(current.left_mps), std::abs(current.right_mps));
  if (m <= step_mps) return {};
  const double scale = (m - step_mps) / m;
  return {current.left_mps * scale, current.right_mps * scale};
}

void DynamicWindow::BuildCandidates(const WheelVelocity& current, const DwaGoal& goal,
                                    Scene& scene) {
  const double a = options_.max_wheel_accel_mps2;
  const double step_mps = a * options_.period_s;
  const BodyTwist now = TwistFromWheels(current.left_mps, current.right_mps, options_.wheelbase_m);
  double cap = std::min(options_.max_speed_mps, goal.speed_limit_mps);
  if (goal.pose_goal) {
    // Pose mode: slow enough to stop at the goal (hold one period, then brake).
    cap = std::min(cap, StoppableSpeed(scene.goal_distance_m, a, options_.period_s));
    if (scene.orienting) {
      const double turn_decel = 2.0 * a / options_.wheelbase_m;
      const double error_rad = std::abs(core::NormalizeAngle(goal.goal_heading_in_robot_rad));
      scene.turn_cap_radps =
          std::min(scene.turn_cap_radps,
                   std::max(StoppableSpeed(error_rad, turn_decel, options_.period_s),
                            std::abs(now.omega_radps) - turn_decel * options_.period_s));
    }
  }
  // The caps never forbid the hardest braking the window allows.
  scene.speed_cap_mps = std::max(cap, std::abs(now.v_mps) - step_mps);
  scene.turn_cap_radps = std::max(
      scene.turn_cap_radps, std::abs(now.omega_radps) - 2.0 * step_mps / options_.wheelbase_m);
  auto window = [&](double c) {
    const double w = options_.max_wheel_speed_mps;
    double lo = std::max(c - step_mps, -w);
    double hi = std::min(c + step_mps, w);
    if (lo > hi) lo = hi = c - std::copysign(step_mps, c);
    return std::pair{lo, hi};
  };
  const auto [l_lo, l_hi] = window(current.left_mps);
  const auto [r_lo, r_hi] = window(current.right_mps);
  const int n = options_.samples_per_wheel;
  scene.reach_arc_m = 0.0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      Candidate& c = candidates_[static_cast<std::size_t>(i) * n + j];
      c = Candidate{};
      c.wheels = {GridSpeed(l_lo, l_hi, i, n), GridSpeed(r_lo, r_hi, j, n)};
      c.twist = TwistFromWheels(c.wheels.left_mps, c.wheels.right_mps, options_.wheelbase_m);
      c.speed_g = table_->GeneralizedSpeed(c.twist);
      c.stop_arc_m = StoppingArc(c.wheels);
      c.bin = table_->BinOf(c.twist);
      c.within_limits = std::abs(c.twist.v_mps) <= scene.speed_cap_mps + kLimitSlack &&
                        std::abs(c.twist.omega_radps) <= scene.turn_cap_radps + kLimitSlack;
      if (!c.within_limits) continue;
      const double clearance_arc_m = c.speed_g * options_.ttc_horizon_s;
      scene.reach_arc_m = std::max({scene.reach_arc_m, c.stop_arc_m, clearance_arc_m});
    }
  }
  scene.reach_arc_m = std::min(scene.reach_arc_m, options_.lookahead_m);
}

double DynamicWindow::EdgeDistance(const Eigen::Vector2d& p) const {
  double distance_m = -kInfinity;
  for (std::size_t i = 0; i < edge_normals_.size(); ++i) {
    distance_m = std::max(distance_m, edge_normals_[i].dot(p) - edge_offsets_[i]);
  }
  return distance_m;
}

void DynamicWindow::AddContact(const Eigen::Vector2d& p, double edge_distance_m) {
  const std::size_t k = contacts_.size();
  if (contact_polygons_.size() <= k) contact_polygons_.push_back(robot_polygon_);
  // The mitred offset polygon {EdgeDistance <= offset} passes kContactSlack_m inside p.
  const double offset_m = edge_distance_m - cycle_contact_slack_m_;
  core::Polygon2& polygon = contact_polygons_[k];
  for (std::size_t i = 0; i < robot_polygon_.size(); ++i) {
    polygon[i] = robot_polygon_[i] + offset_m * miter_[i];
  }
  ContactPoint contact;
  contact.point = p;
  contact.polygon = static_cast<int>(k);
  contact.distance_m = SignedDistance(robot_polygon_, p, &contact.normal);
  nearest_contact_m_ = std::min(nearest_contact_m_, contact.distance_m);
  contacts_.push_back(contact);
}

bool DynamicWindow::GatherPoints(std::span<const Eigen::Vector2d> obstacles, double reach_m) {
  points_.clear();
  cells_.clear();
  if (++stamp_ == 0) {  // wrapped: forget every stamp
    std::fill(cell_stamp_.begin(), cell_stamp_.end(), 0u);
    stamp_ = 1;
  }
  band_points_.clear();
  contacts_.clear();
  nearest_contact_m_ = kInfinity;
  bool shallow = true;
  const double reach_sq = reach_m * reach_m;
  const double near_sq = near_radius_m_ * near_radius_m_;
  for (const Eigen::Vector2d& p : obstacles) {
    if (!p.allFinite() || p.squaredNorm() > reach_sq) continue;
    const double edge_distance_m = p.squaredNorm() <= near_sq ? EdgeDistance(p) : kInfinity;
    if (edge_distance_m <= cycle_margin_m_) {
      if (edge_distance_m < -options_.max_contact_depth_m) shallow = false;
      AddContact(p, edge_distance_m);
      continue;
    }
    if (edge_distance_m <= near_offset_m_ - options_.safety_margin_m + cycle_margin_m_) {
      band_points_.push_back(p);
      continue;
    }
    const int cell = table_->CellOf(p);
    if (cell < 0) continue;  // cannot happen within reach_m <= table reach
    points_.push_back(p);
    // Each cell once: the table's minimum over cells does not care how many
    // points share one (a filled ghost barrier puts two or three in a cell).
    if (cell_stamp_[cell] != stamp_) {
      cell_stamp_[cell] = stamp_;
      cells_.push_back(cell);
    }
  }
  return shallow;
}

double DynamicWindow::ExactArc(const BodyTwist& twist, double up_to_m) const {
  const double speed_g = table_->GeneralizedSpeed(twist);
  const double reach_m = up_to_m + Circumradius(CyclePolygon());
  double arc_m = up_to_m;
  for (const Eigen::Vector2d& p : points_) {
    if (p.squaredNorm() > reach_m * reach_m) continue;
    arc_m = std::min(arc_m, speed_g * ExactTimeToCollision(CyclePolygon(), twist, p));
  }
  return arc_m;
}

bool DynamicWindow::ConfirmExact(const Candidate& c) const {
  if (c.speed_g == 0.0) return true;
  return ExactArc(c.twist, c.stop_arc_m) >= c.stop_arc_m;
}

bool DynamicWindow::RecedesFromContacts(Candidate& c) const {
  double predicted_m = kInfinity;
  for (const ContactPoint& contact : contacts_) {
    // Velocity of the world-fixed point in the robot frame: -v·x - ω × p.
    const Eigen::Vector2d velocity(-c.twist.v_mps + c.twist.omega_radps * contact.point.y(),
                                   -c.twist.omega_radps * contact.point.x());
    const double rate_mps = contact.normal.dot(velocity);
    if (!cycle_slide_waived_ && rate_mps < -kSlideSlope * velocity.norm() - kRateSlack_mps) {
      return false;
    }
    predicted_m = std::min(predicted_m, contact.distance_m + rate_mps * options_.period_s);
  }
  c.escape_gain_m = contacts_.empty() ? 0.0 : predicted_m - nearest_contact_m_;
  return true;
}

double DynamicWindow::NearArc(const Candidate& c, double arc_m) const {
  for (const Eigen::Vector2d& p : band_points_) {
    arc_m = std::min(arc_m, c.speed_g * ExactTimeToCollision(CyclePolygon(), c.twist, p));
    if (arc_m <= c.stop_arc_m) return arc_m;
  }
  for (const ContactPoint& contact : contacts_) {
    const core::Polygon2& polygon = contact_polygons_[contact.polygon];
    arc_m = std::min(arc_m, c.speed_g * ExactTimeToCollision(polygon, c.twist, contact.point));
    if (arc_m <= c.stop_arc_m) return arc_m;
  }
  return arc_m;
}

bool DynamicWindow::Admissible(Candidate& c, const Scene& scene) {
  if (!RecedesFromContacts(c)) return false;
  c.near_checked = c.speed_g == 0.0 || (band_points_.empty() && contacts_.empty());
  if (c.speed_g == 0.0) {
    c.arc_to_collision_m = options_.lookahead_m;
    c.ttc_s = kInfinity;
    return true;
  }
  double arc_m = options_.lookahead_m;
  if (scene.use_table) {
    double& bin_arc_m = bin_arc_m_[c.bin];
    if (bin_arc_m < 0.0) bin_arc_m = table_->MinArcToCollision(c.bin, cells_);
    arc_m = bin_arc_m;
  } else {
    arc_m = ExactArc(c.twist, options_.lookahead_m);
  }
  c.arc_to_collision_m = arc_m;
  c.ttc_s = arc_m / c.speed_g;
  if (c.stop_arc_m >= arc_m) c.near_checked = true;
  return c.stop_arc_m < arc_m;
}

void DynamicWindow::CheckNear(Candidate& c, const DwaGoal& goal, const Scene& scene) {
  c.near_checked = true;
  const double arc_m = NearArc(c, c.arc_to_collision_m);
  if (arc_m == c.arc_to_collision_m) return;  // the score stands
  c.arc_to_collision_m = arc_m;
  c.ttc_s = arc_m / c.speed_g;
  c.admissible = c.stop_arc_m < arc_m;
  if (c.admissible) c.score = Objective(c, goal, scene);
}

double DynamicWindow::Objective(const Candidate& c, const DwaGoal& goal, const Scene& scene) const {
  const Eigen::Vector3d pose = PoseAfter(c.twist, options_.period_s);
  const Eigen::Vector2d at = pose.head<2>();
  auto bearing_error = [&](const Eigen::Vector2d& to) {
    const Eigen::Vector2d d = to - at;
    return std::abs(core::NormalizeAngle(std::atan2(d.y(), d.x()) - pose.z()));
  };
  double clearance = Clamp01(c.ttc_s / options_.ttc_horizon_s);
  // Standing still is always clear; rewarding that would make stopping beat
  // any admissible move past a close door post (the classic DWA stall).
  // Stop is chosen when nothing else is admissible, or when it leads.
  if (!goal.pose_goal && c.twist.v_mps == 0.0 && c.twist.omega_radps == 0.0) clearance = 0.0;
  // Within the margin: the first-order growth of the clearance over one
  // period, against the travel one period of acceleration gives from
  // standstill; reversing away is not penalised.
  const bool escaping = !contacts_.empty();
  if (escaping) {
    const double reference_m =
        options_.max_wheel_accel_mps2 * options_.period_s * options_.period_s;
    clearance = std::min(clearance, Clamp01(c.escape_gain_m / reference_m));
  }
  double heading = 0.0;
  double speed = 0.0;
  if (!goal.pose_goal) {
    // The heading is judged where the candidate leads within the heading
    // horizon (Fox et al. 1997 judge it at the predicted position): over one
    // 0.1 s period a turn from rest changes it too little to outweigh the
    // clearance of standing still, and the robot would dither.
    // (In contact the escape rules lead; the heading is judged after the period.)
    const Eigen::Vector3d ahead =
        PoseAfter(c.twist, escaping ? options_.period_s : options_.heading_horizon_s);
    const Eigen::Vector2d d = goal.target_in_robot - ahead.head<2>();
    const double front = goal.reverse ? ahead.z() + std::numbers::pi : ahead.z();
    heading =
        1.0 - std::abs(core::NormalizeAngle(std::atan2(d.y(), d.x()) - front)) / std::numbers::pi;
    speed = (goal.reverse ? -c.twist.v_mps : c.twist.v_mps) / options_.max_speed_mps;
  } else {
    const double d_pred_m = (goal.goal_in_robot - at).norm();
    const double error_rad =
        scene.orienting
            ? std::abs(core::NormalizeAngle(goal.goal_heading_in_robot_rad - pose.z()))
            : (d_pred_m > options_.goal_tolerance_m ? bearing_error(goal.goal_in_robot) : 0.0);
    heading = 1.0 - error_rad / std::numbers::pi;
    speed = (scene.goal_distance_m - d_pred_m) / (options_.max_speed_mps * options_.period_s);
  }
  if (escaping) speed = std::max(speed, 0.0);
  return options_.weight_heading * heading + options_.weight_speed * speed +
         options_.weight_clearance * clearance;
}

void DynamicWindow::ScoreCandidates(const DwaGoal& goal, const Scene& scene) {
  std::fill(bin_arc_m_.begin(), bin_arc_m_.end(), -1.0);
  for (Candidate& c : candidates_) {
    if (!c.within_limits) continue;
    c.admissible = Admissible(c, scene);
    if (c.admissible) c.score = Objective(c, goal, scene);
  }
}

DwaResult DynamicWindow::Choose(const WheelVelocity& current,
                                std::span<const Eigen::Vector2d> obstacles_in_robot,
                                const DwaGoal& goal) {
  if (!std::isfinite(current.left_mps) || !std::isfinite(current.right_mps)) {
    throw std::invalid_argument("current wheel velocity must be finite");
  }
  if (!goal.target_in_robot.allFinite() || !goal.goal_in_robot.allFinite() ||
      !std::isfinite(goal.goal_heading_in_robot_rad) || !(goal.speed_limit_mps >= 0.0)) {
    throw std::invalid_argument("goal must be finite with speed_limit_mps >= 0");
  }
  const bool reduced = goal.margin_m >= 0.0;
  if (reduced && (!(goal.margin_m <= options_.safety_margin_m) || !goal.exact_clearance)) {
    throw std::invalid_argument(
        "goal.margin_m must be at most safety_margin_m, with exact_clearance");
  }
  if (reduced && goal.margin_m != reduced_margin_m_) {
    reduced_margin_m_ = goal.margin_m;
    reduced_polygon_ = InflateConvexPolygon(robot_polygon_, reduced_margin_m_);
  }
  cycle_margin_m_ = reduced ? goal.margin_m : options_.safety_margin_m;
  cycle_reduced_ = reduced;
  if (goal.contact_slack_m > kMaxContactSlack_m || std::isnan(goal.contact_slack_m)) {
    throw std::invalid_argument("goal.contact_slack_m must be at most 5 mm");
  }
  cycle_slide_waived_ = goal.contact_slack_m >= 0.0;
  cycle_contact_slack_m_ = cycle_slide_waived_ ? goal.contact_slack_m : kContactSlack_m;
  DwaResult result;
  Scene scene;
  scene.speed_cap_mps = kInfinity;
  scene.turn_cap_radps = options_.max_turn_rate_radps;
  scene.use_table =
      options_.clearance_geometry == ClearanceGeometry::kLookupTable && !goal.exact_clearance;
  result.command = BrakeCommand(current);
  result.time_to_collision_s = options_.ttc_horizon_s;
  result.candidates_evaluated = static_cast<int>(candidates_.size());
  scene.goal_distance_m = goal.goal_in_robot.norm();
  scene.orienting = goal.pose_goal && scene.goal_distance_m <= options_.goal_tolerance_m;
  if (scene.orienting && std::abs(core::NormalizeAngle(goal.goal_heading_in_robot_rad)) <=
                             options_.goal_heading_tolerance_rad) {
    result.goal_reached = true;
    return result;
  }
  BuildCandidates(current, goal, scene);
  const bool shallow = GatherPoints(obstacles_in_robot,
                                    table_->reach_m() - options_.lookahead_m + scene.reach_arc_m);
  result.contact_points = static_cast<int>(contacts_.size());
  result.band_points = static_cast<int>(band_points_.size());
  result.points_in_reach =
      static_cast<int>(points_.size()) + result.contact_points + result.band_points;
  for (const ContactPoint& contact : contacts_) {
    if (core::Contains(robot_polygon_, contact.point)) result.in_collision = true;
  }
  if (!shallow) return result;
  ScoreCandidates(goal, scene);
  const bool use_table = scene.use_table;
  for (const Candidate& c : candidates_) result.candidates_admissible += c.admissible ? 1 : 0;
  // Best first: a score before CheckNear is an upper bound (the band and
  // contact points only shorten the arc, and the objective never rises as the
  // time to collision falls), so the first maximum (in grid order) that has
  // been checked is the one a full evaluation would pick.
  while (true) {
    Candidate* best = nullptr;
    for (Candidate& c : candidates_) {
      if (c.admissible && (best == nullptr || c.score > best->score)) best = &c;
    }
    if (best == nullptr) return result;
    if (!best->near_checked) {
      CheckNear(*best, goal, scene);
      continue;
    }
    if (use_table && !ConfirmExact(*best)) {
      best->admissible = false;
      ++result.exact_rejections;
      continue;
    }
    result.command = best->wheels;
    result.time_to_collision_s = std::min(best->ttc_s, options_.ttc_horizon_s);
    result.admissible_found = true;
    return result;
  }
}

std::vector<Eigen::Vector2d> DynamicWindow::ChosenArc(const DwaResult& result,
                                                      double duration_s) const {
  const BodyTwist twist =
      TwistFromWheels(result.command.left_mps, result.command.right_mps, options_.wheelbase_m);
  std::vector<Eigen::Vector2d> arc;
  for (double t = 0.0; t < duration_s; t += kArcStep_s)
    arc.push_back(PoseAfter(twist, t).head<2>());
  arc.push_back(PoseAfter(twist, std::max(duration_s, 0.0)).head<2>());
  return arc;
}

}  // namespace pavilion::nav
