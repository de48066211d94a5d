#include "scenarios/calibration/odometry_calibration.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/random/random_stream.h"
#include "scenarios/config/robot_setup.h"
#include "sim/robot/sim_robot.h"
#include "sim/world/world.h"

// =============================================================================
// Method (docs/calibration.md has the same with the figures obtained).
//
// Notation. The nominal model (URDF) has radii r_L, r_R and wheelbase b. The
// calibrated model has radii c_L·r_L, c_R·r_R and wheelbase b_c. Encoder
// angles φ give nominal travels s = r·φ; the calibrated travels are c·s.
// Define the mean scale S = (c_L + c_R)/2 and the ratio factor q = c_R/c_L
// (Borenstein & Feng's E_d when the nominal radii are equal).
//
// Straight runs. The robot drives a straight line of its odometry (s_l = s_r
// step by step) of odometric length D. Truly it drives an arc of length S·D
// whose chord and heading change γ the tape gives: arc = chord·(γ/2)/sin(γ/2).
//     S = Σ arc_i / Σ D_i.                                               (C1)
//
// UMBmark squares (derived here for our square; Borenstein & Feng 1996 give the
// same structure for theirs). The robot drives a square of side L by odometry
// feedback: legs with s_l = s_r, then in-place turns of ±90° (s_r = −s_l),
// counter-clockwise (σ = +1, left turns) or clockwise (σ = −1), 4 legs and 4
// turns. Two error types act, to first order:
//  - each in-place turn truly turns σ(π/2 + a): the true turn is
//    (c_R·s − c_L·(−s))/b_true = 2sS/b_true against the odometry's 2s/b, so the
//    turn factor ρ = (π/2 + a)/(π/2) = S·b/b_true;
//  - each leg truly changes heading by γ = (c_R − c_L)·L/b_true (left
//    positive), whatever the square's direction.
// (The in-place turns also move the centre by (c_R − c_L)s/2 along the mid
// heading; the four corner headings are 90° apart, so these cancel.)
// Let η_i be the heading error at the start of leg i = 0..3: η_i = i(γ + σa).
// Leg i, of true length S·L (≈ L to first order) and nominal direction u_i,
// is rotated by the mean heading error η_i + γ/2, which displaces its end by
// L(η_i + γ/2)·n_i, n_i = u_i rotated by +90°. The lengths' excess S·L·u_i sums
// to zero around the square. Summing, with u_i = (1,0),(0,1),(−1,0),(0,−1)
// for CCW and (1,0),(0,−1),(−1,0),(0,1) for CW:
//     Σ (i + ½) n_i = (2, −2) (CCW),  (−2, −2) (CW);  Σ i n_i the same,
// so the end-position errors (true − odometry, start frame) are
//     ε_ccw = 2L(γ + a)·(1, −1),    ε_cw = 2L(a − γ)·(1, 1).
// With the centres of gravity (x, y)_ccw, (x, y)_cw of several runs each,
// using both coordinates:
//     a = (x_ccw + x_cw − y_ccw + y_cw) / (8L),                          (C2)
//     γ = (x_ccw − x_cw − y_ccw − y_cw) / (8L).                          (C3)
// Then ρ = 1 + 2a/π and b_c = b·S/ρ. From γ = 2S·L·(q − 1)/((q + 1)·b_c),
//     q = (1 + γ·b_c/(2SL)) / (1 − γ·b_c/(2SL)) = (R + b_c/2)/(R − b_c/2)
// with R = S·L/γ the true radius of a leg (Borenstein & Feng's form), and
//     c_L = 2S/(1 + q),   c_R = 2S·q/(1 + q).                            (C4)
//
// Iterated UMBmark (C6). (C2)–(C4) are first order: Borenstein & Feng's single
// correction leaves the second-order terms, which for a 1% radius ratio (6° of
// heading change per 4 m leg) and a 2% wheelbase error are 0.2% of the
// wheelbase. As the recorded encoder counts can be re-integrated with any
// model, we apply (C2), (C3) again to the centres of gravity of the squares'
// residual errors under the current model, add the resulting a and γ to the
// estimates, recompute (C4), and repeat until a pass changes them by less than
// 1e-7 rad. At the fixed point the calibrated model reproduces both centres of
// gravity; for a kinematic robot that is its true model (test).
//
// Noise (§2.3). After the correction, the end-pose residual e_i of run i is
// modelled as N(0, P_i(k)), where P_i(k) is eq. 2.13 propagated along the run's
// recorded wheel travels from P = 0 with U = diag(k|s_r|, k|s_l|). P is linear
// in k (every term of eq. 2.13 is, starting from zero): P_i(k) = k·P_i(1). The
// log-likelihood of N runs is
//     ℓ(k) = −½ Σ_i [ log det(k·P_i(1)) + e_iᵀ P_i(1)⁻¹ e_i / k ] + const
//          = −½ [ 3N·log k + Σ_i e_iᵀ P_i(1)⁻¹ e_i / k ] + const,
// and dℓ/dk = 0 gives
//     k̂ = (1/(3N)) Σ_i e_iᵀ P_i(1)⁻¹ e_i.                               (C5)
// Since 3N·k̂/k ~ χ²(3N) under the model, k̂ has a relative standard deviation
// of √(2/(3N)) (16% for the 25 runs of `runs` = 5). The three systematic
// parameters fitted to the same runs take about 3/(3N) of the residual
// variance with them (1% here), which we leave as it is. The residuals also
// hold what the systematic model cannot (slip that depends on speed, lateral
// creep on arcs, turns that slide on when they stop): that is the physics'
// share of k, which is why the runs vary speed, direction, length and curvature.
// We estimate one k = k_L = k_R: the standard runs are mirror-symmetric (each
// left turn or arc has a right one), so their end poses inform k_L + k_R well
// and k_L − k_R hardly at all (a straight run's or a spin's end covariance
// depends on the sum alone), and the encoders' noise is configured symmetric.
// =============================================================================

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

constexpr double kPi = std::numbers::pi;
constexpr double kQuarterTurnRad = kPi / 2;  // UMBmark's square corners
constexpr char kRobotId[] = "calib";
constexpr char kFloorMaterial[] = "floor";

// Driving: the robot's own controller, on its nominal-model odometry.
// Rest before a run starts, so the robot has settled on its wheels (s).
constexpr double kSettleS = 0.5;
// Stop after each segment, as UMBmark's stop-and-turn squares do (s); and at the end.
constexpr double kPauseS = 0.3;
constexpr double kFinalRestS = 0.5;
// The grid of the (C5') likelihood search: log10 of k and k_turn (m) from
// kLogKMin to kLogKMax in kLikelihoodGridSteps steps.
constexpr double kLogKMin = -10.0;
constexpr double kLogKMax = -3.0;
constexpr int kLikelihoodGridSteps = 56;
// Deceleration planned into the speed profile, as a fraction of the motors'
// rim acceleration limit, so the ramped motors can follow it.
constexpr double kDecelFraction = 0.5;
// Cruise speeds above this fraction of the top rim speed leave no room for steering.
constexpr double kMaxSpeedFraction = 0.8;
// Crawl speeds at the end of the profile, so a segment ends in finite time.
constexpr double kCreepMps = 0.01;
constexpr double kCreepRadps = 0.02;
// A segment ends within these of its target (odometry).
constexpr double kDistanceTolM = 2e-4;
constexpr double kAngleTolRad = 5e-4;
// Heading feedback on straights and arcs (1/s), lateral feedback (rad of
// heading per m of offset, at most kMaxLateralRad), steering limit (rad/s).
constexpr double kHeadingGainPerS = 3.0;
constexpr double kLateralGainRadPerM = 2.0;
constexpr double kMaxLateralRad = 0.1;
constexpr double kMaxSteerRadps = 0.5;
// A segment that takes longer than this multiple of its planned time (plus
// kTimeoutMarginS) means the robot is stuck.
constexpr double kTimeoutFactor = 3.0;
constexpr double kTimeoutMarginS = 10.0;
// Free floor around the farthest point a run can reach (m).
constexpr double kFloorMarginM = 3.0;
// Iterated UMBmark stops when a pass changes a and γ by less than this (rad),
// or after this many passes.
constexpr double kUmbmarkToleranceRad = 1e-7;
constexpr int kMaxUmbmarkIterations = 50;
// Stream of the per-run encoder seeds.
constexpr char kRunSeedStream[] = "odometry_calibration/runs";

double Wrap(double a) { return core::NormalizeAngle(a); }

sim::WorldDescription BareFloor(double half_size_m, double friction) {
  sim::WorldDescription w;
  w.name = "calibration_floor";
  sim::Material floor;
  floor.friction = friction;
  w.materials[kFloorMaterial] = floor;
  w.floor = {{-half_size_m, -half_size_m}, {half_size_m, half_size_m}, kFloorMaterial};
  return w;
}

// How far from the start a run can get (m), to size the floor.
double RunExtent(const DriveRun& run) {
  double extent = 0.0;
  for (const DriveSegment& s : run.segments) extent += std::abs(s.distance_m);
  return extent;
}

// Planned duration of a segment (s).
double PlannedDurationS(const DriveSegment& s, double decel_mps2, double half_base_m) {
  const double length = s.type == DriveSegment::Type::kTurn ? std::abs(s.angle_rad) * half_base_m
                                                            : std::abs(s.distance_m);
  return length / s.speed_mps + s.speed_mps / decel_mps2;
}

// Speed along a profile that brakes at `decel` to reach `remaining` with crawl
// speed `creep`, capped at `cruise`.
double ProfileSpeed(double remaining, double cruise, double decel, double creep) {
  return std::clamp(std::sqrt(2.0 * decel * std::max(remaining, 0.0)), creep, cruise);
}

Eigen::Vector2d Dir(double angle_rad) { return {std::cos(angle_rad), std::sin(angle_rad)}; }

core::WheelTravel Travel(const TickStep& t, int ticks_per_revolution,
                         const sim::OdometryCalibration& m) {
  const double per_tick = 2.0 * kPi / ticks_per_revolution;
  return {static_cast<double>(t.left) * per_tick * m.left_wheel_radius_m,
          static_cast<double>(t.right) * per_tick * m.right_wheel_radius_m};
}

// The errors of one kind of run.
std::vector<Eigen::Vector3d> ErrorsOf(const std::vector<RecordedRun>& runs,
                                      const std::vector<Eigen::Vector3d>& errors,
                                      CalibrationRunKind kind) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (runs[i].run.kind == kind) out.push_back(errors[i]);
  }
  return out;
}

Eigen::Vector2d CentreOfGravity(const std::vector<Eigen::Vector3d>& errors) {
  Eigen::Vector2d cg(0, 0);
  for (const Eigen::Vector3d& e : errors) cg += e.head<2>() / static_cast<double>(errors.size());
  return cg;
}

std::string Format(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v == 0.0 ? 0.0 : v);  // no "-0"
  return buf;
}

Json Vec3(const Eigen::Vector3d& v) { return Json::array({v[0], v[1], v[2]}); }

Json OdometryJson(const sim::OdometryCalibration& o) {
  return Json{{"left_wheel_radius_m", o.left_wheel_radius_m},
              {"right_wheel_radius_m", o.right_wheel_radius_m},
              {"wheelbase_m", o.wheelbase_m},
              {"k_left_m", o.k_left_m},
              {"k_right_m", o.k_right_m}};
}

}  // namespace

void OdometryCalibrationOptions::Validate() const {
  auto in = [](double v, double lo, double hi, const char* name) {
    if (!(v >= lo && v <= hi) || !std::isfinite(v)) {
      throw std::invalid_argument(std::string("calibration option ") + name + " must be in [" +
                                  Format("%g", lo) + ", " + Format("%g", hi) + "]");
    }
  };
  in(physics_rate_hz, 10.0, 10000.0, "physics_rate_hz");
  in(runs, 1, 100, "runs");
  in(square_side_m, 0.5, 20.0, "square_side_m");
  in(spin_angle_rad, 1e-3, 20.0, "spin_angle_rad");
  in(floor_friction, 0.05, 2.0, "floor_friction");
  if (arc_radii_m.empty()) throw std::invalid_argument("calibration option arc_radii_m is empty");
  for (double r : arc_radii_m) in(r, 0.1, 20.0, "arc_radii_m[]");
  if (speeds_mps.empty()) throw std::invalid_argument("calibration option speeds_mps is empty");
  for (double v : speeds_mps) in(v, 1e-3, 10.0, "speeds_mps[]");
  if (straight_lengths_m.empty()) {
    throw std::invalid_argument("calibration option straight_lengths_m is empty");
  }
  for (double l : straight_lengths_m) in(l, 0.1, 50.0, "straight_lengths_m[]");
}

const char* RunKindName(CalibrationRunKind kind) {
  switch (kind) {
    case CalibrationRunKind::kSquareCcw:
      return "square_ccw";
    case CalibrationRunKind::kSquareCw:
      return "square_cw";
    case CalibrationRunKind::kStraight:
      return "straight";
    case CalibrationRunKind::kSpin:
      return "spin";
    case CalibrationRunKind::kArc:
      return "arc";
    case CalibrationRunKind::kPath:
      break;
  }
  return "path";
}

std::vector<DriveRun> StandardCalibrationRuns(const OdometryCalibrationOptions& options) {
  options.Validate();
  const auto speed = [&](int i) { return options.speeds_mps[i % options.speeds_mps.size()]; };
  const auto name = [](const char* kind, int i) {
    return std::string(kind) + "_" + std::to_string(i + 1);
  };
  std::vector<DriveRun> runs;
  // Squares in CCW/CW pairs of equal speed, so both centres of gravity average
  // the same speeds.
  for (int i = 0; i < options.runs; ++i) {
    for (const double sigma : {1.0, -1.0}) {
      DriveRun run;
      run.kind = sigma > 0 ? CalibrationRunKind::kSquareCcw : CalibrationRunKind::kSquareCw;
      run.name = name(RunKindName(run.kind), i);
      run.speed_mps = speed(i);
      for (int leg = 0; leg < 4; ++leg) {
        run.segments.push_back(
            {DriveSegment::Type::kStraight, options.square_side_m, 0.0, run.speed_mps});
        run.segments.push_back(
            {DriveSegment::Type::kTurn, 0.0, sigma * kQuarterTurnRad, run.speed_mps});
      }
      runs.push_back(run);
    }
  }
  for (int i = 0; i < options.runs; ++i) {
    DriveRun run;
    run.kind = CalibrationRunKind::kStraight;
    run.name = name("straight", i);
    run.speed_mps = speed(i);
    const double length =
        options.straight_lengths_m[i % options.straight_lengths_m.size()] * (i % 2 == 0 ? 1 : -1);
    run.segments.push_back({DriveSegment::Type::kStraight, length, 0.0, run.speed_mps});
    runs.push_back(run);
  }
  for (int i = 0; i < options.runs; ++i) {
    DriveRun run;
    run.kind = CalibrationRunKind::kSpin;
    run.name = name("spin", i);
    run.speed_mps = speed(i);
    run.segments.push_back({DriveSegment::Type::kTurn, 0.0,
                            options.spin_angle_rad * (i % 2 == 0 ? 1 : -1), run.speed_mps});
    runs.push_back(run);
  }
  for (int i = 0; i < options.runs; ++i) {
    DriveRun run;
    run.kind = CalibrationRunKind::kArc;
    run.name = name("arc", i);
    run.speed_mps = speed(i);
    const double radius = options.arc_radii_m[i % options.arc_radii_m.size()];
    run.segments.push_back(
        {DriveSegment::Type::kArc, kPi * radius, kPi * (i % 2 == 0 ? 1 : -1), run.speed_mps});
    runs.push_back(run);
  }
  return runs;
}

sim::OdometryCalibration NominalOdometry(const sim::RobotConfig& config) {
  sim::OdometryCalibration o;
  o.left_wheel_radius_m = config.description.left_wheel.radius_m;
  o.right_wheel_radius_m = config.description.right_wheel.radius_m;
  o.wheelbase_m = config.description.wheelbase_m();
  o.k_left_m = config.odometry.k_left_m;
  o.k_right_m = config.odometry.k_right_m;
  return o;
}

RecordedRun DriveCalibrationRun(const sim::RobotConfig& config, const DriveRun& run,
                                const OdometryCalibrationOptions& options, std::uint64_t run_seed) {
  options.Validate();
  const sim::RobotDescription& model = config.description;
  const sim::OdometryCalibration nominal = NominalOdometry(config);
  const double half_base = 0.5 * nominal.wheelbase_m;
  const double small_radius = std::min(nominal.left_wheel_radius_m, nominal.right_wheel_radius_m);
  const double max_rim_mps = model.max_wheel_speed_radps * small_radius;
  const double decel = kDecelFraction * model.max_wheel_accel_radps2 * small_radius;
  const std::string who = "robot '" + model.model + "', run '" + run.name + "': ";
  if (run.segments.empty()) throw std::invalid_argument(who + "no segments to drive");
  for (const DriveSegment& s : run.segments) {
    if (!(s.speed_mps > 0.0 && s.speed_mps <= kMaxSpeedFraction * max_rim_mps)) {
      throw std::invalid_argument(
          who + "speed " + Format("%g", s.speed_mps) + " m/s is outside (0, " +
          Format("%.3g", kMaxSpeedFraction * max_rim_mps) + "] (80% of the top wheel speed)");
    }
    if (s.type == DriveSegment::Type::kArc && !(s.distance_m > 0.0)) {
      throw std::invalid_argument(who + "an arc needs a path length > 0");
    }
  }

  sim::WorldDescription description =
      BareFloor(RunExtent(run) + kFloorMarginM, options.floor_friction);
  sim::SimRobotSetup setup = MakeSimRobotSetup(kRobotId, config, {}, &description);
  setup.lasers.clear();  // not needed here, and ray casts dominate a step's cost
  setup.bumpers.clear();
  sim::WorldOptions world_options;
  world_options.physics_rate_hz = options.physics_rate_hz;
  sim::World world(std::move(description), world_options);
  sim::SimRobot robot(&world, setup, run_seed);
  const int index = robot.index();

  // Steps the world; returns the encoder reading of the tick, if any.
  auto step = [&]() -> std::optional<core::EncoderReading> {
    const sim::RobotState before = world.robot_state(index);
    world.Step();
    const sim::SensorOutputs out = robot.AfterStep(before, world.robot_state(index));
    if (out.encoders.empty()) return std::nullopt;
    return out.encoders.back();
  };
  while (world.time_s() < kSettleS) step();
  std::optional<core::EncoderReading> reading;
  while (!(reading = step())) {
  }

  RecordedRun rec;
  rec.run = run;
  rec.ticks_per_revolution = reading->ticks_per_revolution;
  rec.true_start = world.robot_state(index).pose;
  const double start_s = world.time_s();
  std::int64_t last_left = reading->left_ticks, last_right = reading->right_ticks;

  // Odometry (nominal model, heading unwrapped) and the reference path it follows.
  Eigen::Vector2d odo_p = rec.true_start.translation();
  double odo_theta = rec.true_start.theta_rad;
  Eigen::Vector2d ref_p = odo_p;
  double ref_theta = odo_theta;

  std::size_t segment = 0;
  bool pausing = false;
  double phase_start_s = world.time_s();
  double arc_travel_m = 0.0;  // odometric path length along the current arc
  while (true) {
    reading = step();
    if (!reading) continue;
    const TickStep d{reading->left_ticks - last_left, reading->right_ticks - last_right};
    last_left = reading->left_ticks;
    last_right = reading->right_ticks;
    rec.ticks.push_back(d);
    const core::WheelTravel travel = Travel(d, rec.ticks_per_revolution, nominal);
    const core::Pose2 next =
        core::DiffDriveStep({odo_p.x(), odo_p.y(), odo_theta}, travel, nominal.wheelbase_m);
    odo_theta += (travel.right_m - travel.left_m) / nominal.wheelbase_m;
    odo_p = next.translation();
    arc_travel_m += 0.5 * (travel.left_m + travel.right_m);
    const double now = world.time_s();

    if (pausing) {
      const bool last = segment >= run.segments.size();
      if (now - phase_start_s < (last ? kFinalRestS : kPauseS)) continue;
      if (last) break;
      pausing = false;
      phase_start_s = now;
      arc_travel_m = 0.0;
    }
    const DriveSegment& s = run.segments[segment];
    if (now - phase_start_s >
        kTimeoutFactor * PlannedDurationS(s, decel, half_base) + kTimeoutMarginS) {
      throw std::runtime_error(who + "stuck in segment " + std::to_string(segment + 1) + " after " +
                               Format("%.1f", now - phase_start_s) + " s");
    }
    double v = 0.0, w = 0.0;
    bool done = false;
    switch (s.type) {
      case DriveSegment::Type::kStraight: {
        const double sign = s.distance_m >= 0 ? 1.0 : -1.0;
        const Eigen::Vector2d offset = odo_p - ref_p;
        const double remaining = std::abs(s.distance_m) - sign * offset.dot(Dir(ref_theta));
        if (remaining <= kDistanceTolM) {
          done = true;
          ref_p += s.distance_m * Dir(ref_theta);
          break;
        }
        v = sign * ProfileSpeed(remaining, s.speed_mps, decel, kCreepMps);
        const double lateral = offset.dot(Dir(ref_theta + kPi / 2));
        const double wanted =
            -sign * std::clamp(kLateralGainRadPerM * lateral, -kMaxLateralRad, kMaxLateralRad);
        w = std::clamp(-kHeadingGainPerS * (odo_theta - ref_theta - wanted), -kMaxSteerRadps,
                       kMaxSteerRadps);
        break;
      }
      case DriveSegment::Type::kTurn: {
        const double sign = s.angle_rad >= 0 ? 1.0 : -1.0;
        const double remaining = sign * (ref_theta + s.angle_rad - odo_theta);
        if (remaining <= kAngleTolRad) {
          done = true;
          ref_theta += s.angle_rad;
          break;
        }
        w = sign * ProfileSpeed(remaining, s.speed_mps / half_base, decel / half_base, kCreepRadps);
        break;
      }
      case DriveSegment::Type::kArc: {
        const double curvature = s.angle_rad / s.distance_m;
        const double remaining = s.distance_m - arc_travel_m;
        if (remaining <= kDistanceTolM) {
          done = true;
          // The ideal arc's chord, at the mean heading.
          const double half = 0.5 * s.angle_rad;
          const double chord =
              std::abs(half) < 1e-9 ? s.distance_m : s.distance_m * std::sin(half) / half;
          ref_p += chord * Dir(ref_theta + half);
          ref_theta += s.angle_rad;
          break;
        }
        v = ProfileSpeed(remaining, s.speed_mps, decel, kCreepMps);
        const double heading_ref = ref_theta + curvature * arc_travel_m;
        w = curvature * v + std::clamp(-kHeadingGainPerS * (odo_theta - heading_ref),
                                       -kMaxSteerRadps, kMaxSteerRadps);
        break;
      }
    }
    if (done) {
      robot.SetWheelSpeeds(0.0, 0.0);
      ++segment;
      pausing = true;
      phase_start_s = now;
      continue;
    }
    robot.SetWheelSpeeds((v - w * half_base) / nominal.left_wheel_radius_m,
                         (v + w * half_base) / nominal.right_wheel_radius_m);
  }
  rec.true_end = world.robot_state(index).pose;
  rec.duration_s = world.time_s() - start_s;
  return rec;
}

core::PoseWithCovariance IntegrateRecordedRun(const RecordedRun& run,
                                              const sim::OdometryCalibration& model,
                                              const core::WheelNoise& noise) {
  core::PoseWithCovariance state{run.true_start, Eigen::Matrix3d::Zero()};
  for (const TickStep& t : run.ticks) {
    state = core::DiffDriveStepWithCovariance(state, Travel(t, run.ticks_per_revolution, model),
                                              model.wheelbase_m, noise);
  }
  return state;
}

Eigen::Vector3d EndPoseError(const RecordedRun& run, const core::Pose2& odometry_end) {
  const Eigen::Vector2d d = run.true_end.translation() - odometry_end.translation();
  const double c = std::cos(run.true_start.theta_rad), s = std::sin(run.true_start.theta_rad);
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(),
          Wrap(run.true_end.theta_rad - odometry_end.theta_rad)};
}

UmbmarkResult EstimateUmbmark(const std::vector<Eigen::Vector3d>& ccw_errors,
                              const std::vector<Eigen::Vector3d>& cw_errors, double side_m,
                              double scale, double wheelbase_m) {
  if (ccw_errors.empty() || cw_errors.empty()) {
    throw std::invalid_argument("UMBmark needs clockwise and counter-clockwise squares");
  }
  UmbmarkResult u;
  u.cg_ccw_m = CentreOfGravity(ccw_errors);
  u.cg_cw_m = CentreOfGravity(cw_errors);
  const double x_ccw = u.cg_ccw_m.x(), y_ccw = u.cg_ccw_m.y();
  const double x_cw = u.cg_cw_m.x(), y_cw = u.cg_cw_m.y();
  const double leg_m = scale * side_m;                                  // true leg length
  u.corner_overturn_rad = (x_ccw + x_cw - y_ccw + y_cw) / (8 * leg_m);  // (C2)
  u.leg_curvature_rad = (x_ccw - x_cw - y_ccw - y_cw) / (8 * leg_m);    // (C3)
  u.e_max_syst_m = std::max(u.cg_ccw_m.norm(), u.cg_cw_m.norm());
  SetUmbmarkFactors(side_m, scale, wheelbase_m, &u);
  return u;
}

void SetUmbmarkFactors(double side_m, double scale, double wheelbase_m, UmbmarkResult* u) {
  const double leg_m = scale * side_m;
  u->turn_factor = (kQuarterTurnRad + u->corner_overturn_rad) / kQuarterTurnRad;
  const double wheelbase_c = wheelbase_m * scale / u->turn_factor;
  const double h = u->leg_curvature_rad * wheelbase_c / (2 * leg_m);
  u->radius_ratio_factor = (1 + h) / (1 - h);  // (C4): (R + b/2)/(R − b/2)
}

namespace {

// The calibrated radii and wheelbase for UMBmark's factors and the straight-run scale (C4).
sim::OdometryCalibration CorrectedModel(const sim::OdometryCalibration& nominal,
                                        const UmbmarkResult& u, double scale) {
  const double q = u.radius_ratio_factor;
  sim::OdometryCalibration m = nominal;
  m.left_wheel_radius_m *= 2 * scale / (1 + q);
  m.right_wheel_radius_m *= 2 * scale * q / (1 + q);
  m.wheelbase_m *= scale / u.turn_factor;
  return m;
}

}  // namespace

OdometryCalibrationReport EstimateCalibration(const sim::RobotConfig& config,
                                              const OdometryCalibrationOptions& options,
                                              const std::vector<RecordedRun>& runs) {
  OdometryCalibrationReport report;
  report.robot = config.description.model;
  report.options = options;
  report.systematic = config.systematic;
  report.encoder_noise = config.encoders.noise;
  report.encoder_k_left_m = config.encoders.k_left_m;
  report.encoder_k_right_m = config.encoders.k_right_m;
  report.nominal = NominalOdometry(config);

  std::vector<Eigen::Vector3d> nominal_errors;
  double arc_sum = 0.0, odometric_sum = 0.0, side_m = -1.0;
  for (const RecordedRun& r : runs) {
    nominal_errors.push_back(EndPoseError(r, IntegrateRecordedRun(r, report.nominal, {}).pose));
    report.simulated_s += r.duration_s;
    if (r.run.kind == CalibrationRunKind::kStraight) {
      // (C1): the true arc from its chord and heading change.
      const double chord = (r.true_end.translation() - r.true_start.translation()).norm();
      const double half = 0.5 * std::abs(Wrap(r.true_end.theta_rad - r.true_start.theta_rad));
      arc_sum += half < 1e-9 ? chord : chord * half / std::sin(half);
      double ds = 0.0;
      for (const TickStep& t : r.ticks) {
        const core::WheelTravel w = Travel(t, r.ticks_per_revolution, report.nominal);
        ds += 0.5 * (w.left_m + w.right_m);
      }
      odometric_sum += std::abs(ds);
    }
    if (r.run.kind == CalibrationRunKind::kSquareCcw ||
        r.run.kind == CalibrationRunKind::kSquareCw) {
      const double side = std::abs(r.run.segments.front().distance_m);
      if (side_m >= 0 && std::abs(side - side_m) > 1e-9) {
        throw std::invalid_argument("UMBmark squares must all have the same side");
      }
      side_m = side;
    }
  }
  if (!(odometric_sum > 0.0)) throw std::invalid_argument("the calibration needs straight runs");
  report.straight_scale = arc_sum / odometric_sum;
  const double scale = report.straight_scale;
  const auto square_errors = [&](const sim::OdometryCalibration& model, CalibrationRunKind kind) {
    std::vector<Eigen::Vector3d> errors;
    for (const RecordedRun& r : runs) {
      if (r.run.kind == kind)
        errors.push_back(EndPoseError(r, IntegrateRecordedRun(r, model, {}).pose));
    }
    return errors;
  };
  report.umbmark_one_step =
      EstimateUmbmark(ErrorsOf(runs, nominal_errors, CalibrationRunKind::kSquareCcw),
                      ErrorsOf(runs, nominal_errors, CalibrationRunKind::kSquareCw), side_m, scale,
                      report.nominal.wheelbase_m);
  // Iterated UMBmark (C6): apply (C2), (C3) to the residual centres of gravity
  // of the squares re-integrated with the current model, until they vanish.
  report.umbmark = report.umbmark_one_step;
  for (int i = 0; i < kMaxUmbmarkIterations; ++i) {
    const sim::OdometryCalibration model = CorrectedModel(report.nominal, report.umbmark, scale);
    const UmbmarkResult residual =
        EstimateUmbmark(square_errors(model, CalibrationRunKind::kSquareCcw),
                        square_errors(model, CalibrationRunKind::kSquareCw), side_m, scale,
                        report.nominal.wheelbase_m);
    report.umbmark.corner_overturn_rad += residual.corner_overturn_rad;
    report.umbmark.leg_curvature_rad += residual.leg_curvature_rad;
    SetUmbmarkFactors(side_m, scale, report.nominal.wheelbase_m, &report.umbmark);
    report.umbmark_iterations = i + 1;
    if (std::max(std::abs(residual.corner_overturn_rad), std::abs(residual.leg_curvature_rad)) <
        kUmbmarkToleranceRad) {
      break;
    }
  }
  report.calibrated = CorrectedModel(report.nominal, report.umbmark, scale);

  // (C5'): k̂ and k̂_turn from the residuals of every run under the calibrated
  // model. P_i is linear in the two: P_i = k·A_i + k_turn·B_i, with A_i and
  // B_i eq. 2.13 propagated with unit k and unit k_turn. The log-likelihood
  //     ℓ = −½ Σ_i [log det P_i + e_iᵀ P_i⁻¹ e_i]
  // has no closed-form maximum with two terms: it is maximized over a grid in
  // log k × log k_turn (and k_turn = 0), then refined by coordinate search.
  std::vector<Eigen::Matrix3d> unit_k, unit_turn;
  std::vector<Eigen::Vector3d> world_errors;
  std::vector<Eigen::Vector3d> calibrated_errors;
  for (const RecordedRun& r : runs) {
    const core::PoseWithCovariance a =
        IntegrateRecordedRun(r, report.calibrated, core::WheelNoise{1.0, 1.0, 0.0});
    const core::PoseWithCovariance b =
        IntegrateRecordedRun(r, report.calibrated, core::WheelNoise{0.0, 0.0, 1.0});
    calibrated_errors.push_back(EndPoseError(r, a.pose));
    // The residual in the world frame, as P is.
    world_errors.emplace_back(r.true_end.x_m - a.pose.x_m, r.true_end.y_m - a.pose.y_m,
                              Wrap(r.true_end.theta_rad - a.pose.theta_rad));
    unit_k.push_back(a.covariance);
    unit_turn.push_back(b.covariance);
  }
  const auto log_likelihood = [&](double k, double k_turn) {
    double l = 0.0;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      const Eigen::Matrix3d p = k * unit_k[i] + k_turn * unit_turn[i];
      const Eigen::LDLT<Eigen::Matrix3d> ldlt(p);
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
        return -std::numeric_limits<double>::infinity();
      }
      l -= 0.5 *
           (ldlt.vectorD().array().log().sum() + world_errors[i].dot(ldlt.solve(world_errors[i])));
    }
    return l;
  };
  double best_k = 1e-6, best_turn = 0.0;
  double best_l = -std::numeric_limits<double>::infinity();
  for (int a = 0; a <= kLikelihoodGridSteps; ++a) {
    const double k = std::pow(10.0, kLogKMin + (kLogKMax - kLogKMin) * a / kLikelihoodGridSteps);
    for (int b = -1; b <= kLikelihoodGridSteps; ++b) {
      const double turn =
          b < 0 ? 0.0 : std::pow(10.0, kLogKMin + (kLogKMax - kLogKMin) * b / kLikelihoodGridSteps);
      const double l = log_likelihood(k, turn);
      if (l > best_l) {
        best_l = l;
        best_k = k;
        best_turn = turn;
      }
    }
  }
  // Coordinate refinement: multiplicative steps that shrink.
  for (double step = 1.5; step > 1.0001; step = std::sqrt(step)) {
    for (bool improved = true; improved;) {
      improved = false;
      for (const auto& [k, turn] : {std::pair{best_k * step, best_turn},
                                    {best_k / step, best_turn},
                                    {best_k, best_turn * step},
                                    {best_k, best_turn / step}}) {
        const double l = log_likelihood(k, turn);
        if (l > best_l) {
          best_l = l;
          best_k = k;
          best_turn = turn;
          improved = true;
        }
      }
    }
  }
  std::vector<double> m2;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const Eigen::Matrix3d p = best_k * unit_k[i] + best_turn * unit_turn[i];
    m2.push_back(world_errors[i].dot(p.ldlt().solve(world_errors[i])));
  }
  report.k_dof = 3 * static_cast<int>(runs.size());
  report.k_m = best_k;
  report.k_turn_m = best_turn;
  report.calibrated.k_left_m = report.k_m;
  report.calibrated.k_right_m = report.k_m;
  report.calibrated.k_turn_m = report.k_turn_m;
  report.e_max_syst_after_m = std::max(
      CentreOfGravity(ErrorsOf(runs, calibrated_errors, CalibrationRunKind::kSquareCcw)).norm(),
      CentreOfGravity(ErrorsOf(runs, calibrated_errors, CalibrationRunKind::kSquareCw)).norm());

  for (std::size_t i = 0; i < runs.size(); ++i) {
    const RecordedRun& r = runs[i];
    CalibrationRunReport row;
    row.name = r.run.name;
    row.kind = r.run.kind;
    row.speed_mps = r.run.speed_mps;
    row.duration_s = r.duration_s;
    for (const TickStep& t : r.ticks) {
      const core::WheelTravel w = Travel(t, r.ticks_per_revolution, report.nominal);
      row.wheel_travel_m += std::abs(w.left_m) + std::abs(w.right_m);
    }
    row.error_nominal = nominal_errors[i];
    row.error_calibrated = calibrated_errors[i];
    row.mahalanobis_sq = m2[i];
    report.runs.push_back(row);
  }
  return report;
}

OdometryCalibrationReport CalibrateOdometry(const sim::RobotConfig& config,
                                            const OdometryCalibrationOptions& options) {
  const std::vector<DriveRun> plan = StandardCalibrationRuns(options);
  core::RandomStream seeds(options.seed, core::RandomStream::StreamId(kRunSeedStream));
  std::vector<RecordedRun> runs;
  for (const DriveRun& run : plan) {
    runs.push_back(DriveCalibrationRun(config, run, options, seeds.NextU64()));
  }
  return EstimateCalibration(config, options, runs);
}

std::string CalibrationJson(const OdometryCalibrationReport& r) {
  Json runs = Json::array();
  for (const CalibrationRunReport& row : r.runs) {
    runs.push_back(Json{{"name", row.name},
                        {"kind", RunKindName(row.kind)},
                        {"speed_mps", row.speed_mps},
                        {"wheel_travel_m", row.wheel_travel_m},
                        {"duration_s", row.duration_s},
                        {"error_nominal", Vec3(row.error_nominal)},
                        {"error_calibrated", Vec3(row.error_calibrated)},
                        {"mahalanobis_sq", row.mahalanobis_sq}});
  }
  const UmbmarkResult& u = r.umbmark;
  Json j{{"schema", "pavilion.calibration/1"},
         {"robot", r.robot},
         {"options",
          {{"physics_rate_hz", r.options.physics_rate_hz},
           {"runs", r.options.runs},
           {"square_side_m", r.options.square_side_m},
           {"speeds_mps", r.options.speeds_mps},
           {"straight_lengths_m", r.options.straight_lengths_m},
           {"spin_angle_rad", r.options.spin_angle_rad},
           {"arc_radii_m", r.options.arc_radii_m},
           {"floor_friction", r.options.floor_friction},
           {"seed", r.options.seed}}},
         {"simulated_robot",
          {{"wheel_radius_ratio", r.systematic.wheel_radius_ratio},
           {"wheelbase_factor", r.systematic.wheelbase_factor},
           {"encoder_noise", r.encoder_noise},
           {"encoder_k_left_m", r.encoder_k_left_m},
           {"encoder_k_right_m", r.encoder_k_right_m}}},
         {"nominal", OdometryJson(r.nominal)},
         {"calibrated", OdometryJson(r.calibrated)},
         {"estimates",
          {{"straight_scale", r.straight_scale},
           {"umbmark",
            {{"cg_ccw_m", {u.cg_ccw_m.x(), u.cg_ccw_m.y()}},
             {"cg_cw_m", {u.cg_cw_m.x(), u.cg_cw_m.y()}},
             {"one_step",
              {{"corner_overturn_rad", r.umbmark_one_step.corner_overturn_rad},
               {"leg_curvature_rad", r.umbmark_one_step.leg_curvature_rad},
               {"radius_ratio_factor", r.umbmark_one_step.radius_ratio_factor},
               {"turn_factor", r.umbmark_one_step.turn_factor}}},
             {"iterations", r.umbmark_iterations},
             {"corner_overturn_rad", u.corner_overturn_rad},
             {"leg_curvature_rad", u.leg_curvature_rad},
             {"radius_ratio_factor", u.radius_ratio_factor},
             {"turn_factor", u.turn_factor}}},
           {"wheel_radius_ratio",
            r.calibrated.right_wheel_radius_m / r.calibrated.left_wheel_radius_m},
           {"wheelbase_factor", r.calibrated.wheelbase_m / r.nominal.wheelbase_m},
           {"k_m", r.k_m},
           {"k_turn_m", r.k_turn_m},
           {"k_dof", r.k_dof},
           {"e_max_syst_before_m", u.e_max_syst_m},
           {"e_max_syst_after_m", r.e_max_syst_after_m}}},
         {"simulated_s", r.simulated_s},
         {"runs", runs}};
  return j.dump(2) + "\n";
}

std::string OdometryYamlBlock(const OdometryCalibrationReport& r, const std::string& comment) {
  std::ostringstream s;
  s << "odometry:\n";
  std::istringstream lines(comment);
  for (std::string line; std::getline(lines, line);) s << "  # " << line << "\n";
  s << "  left_wheel_radius_m: " << Format("%.7f", r.calibrated.left_wheel_radius_m) << "\n";
  s << "  right_wheel_radius_m: " << Format("%.7f", r.calibrated.right_wheel_radius_m) << "\n";
  s << "  wheelbase_m: " << Format("%.6f", r.calibrated.wheelbase_m) << "\n";
  s << "  k_left_m: " << Format("%.3e", r.calibrated.k_left_m) << "\n";
  s << "  k_right_m: " << Format("%.3e", r.calibrated.k_right_m) << "\n";
  s << "  k_turn_m: " << Format("%.3e", r.calibrated.k_turn_m) << "\n";
  return s.str();
}

std::string CalibrationTable(const OdometryCalibrationReport& r) {
  std::ostringstream s;
  char buf[256];
  s << "end-pose errors true - odometry in the start frame (mm, mrad): nominal -> calibrated\n";
  std::snprintf(buf, sizeof buf, "%-14s %5s %7s | %8s %8s %8s | %8s %8s %8s | %6s\n", "run", "m/s",
                "travel", "dx", "dy", "dth", "dx'", "dy'", "dth'", "chi2");
  s << buf;
  for (const CalibrationRunReport& row : r.runs) {
    const Eigen::Vector3d a = row.error_nominal * 1e3, b = row.error_calibrated * 1e3;
    std::snprintf(buf, sizeof buf,
                  "%-14s %5.2f %6.1fm | %8.1f %8.1f %8.1f | %8.1f %8.1f %8.1f | %6.2f\n",
                  row.name.c_str(), row.speed_mps, row.wheel_travel_m, a[0], a[1], a[2], b[0], b[1],
                  b[2], row.mahalanobis_sq);
    s << buf;
  }
  const UmbmarkResult& u = r.umbmark;
  const UmbmarkResult& o = r.umbmark_one_step;
  std::snprintf(buf, sizeof buf,
                "UMBmark: cg_ccw (%.1f, %.1f) mm, cg_cw (%.1f, %.1f) mm; E_max,syst %.1f mm -> "
                "%.1f mm calibrated\n",
                u.cg_ccw_m.x() * 1e3, u.cg_ccw_m.y() * 1e3, u.cg_cw_m.x() * 1e3,
                u.cg_cw_m.y() * 1e3, u.e_max_syst_m * 1e3, r.e_max_syst_after_m * 1e3);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "  one step: corner over-turn %.3f mrad, leg curvature %.3f mrad, E_d %.5f, turn "
                "factor %.5f\n",
                o.corner_overturn_rad * 1e3, o.leg_curvature_rad * 1e3, o.radius_ratio_factor,
                o.turn_factor);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "  iterated (%d): corner over-turn %.3f mrad, leg curvature %.3f mrad, E_d %.5f, "
                "turn factor %.5f; straight scale %.5f\n",
                r.umbmark_iterations, u.corner_overturn_rad * 1e3, u.leg_curvature_rad * 1e3,
                u.radius_ratio_factor, u.turn_factor, r.straight_scale);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "estimated: r_L %.6f m, r_R %.6f m (ratio %.5f, truth %.5f), b %.5f m "
                "(factor %.5f, truth %.5f)\n",
                r.calibrated.left_wheel_radius_m, r.calibrated.right_wheel_radius_m,
                r.calibrated.right_wheel_radius_m / r.calibrated.left_wheel_radius_m,
                r.systematic.wheel_radius_ratio, r.calibrated.wheelbase_m,
                r.calibrated.wheelbase_m / r.nominal.wheelbase_m, r.systematic.wheelbase_factor);
  s << buf;
  std::snprintf(buf, sizeof buf,
                "           k_L = k_R = %.3e m, k_turn = %.3e m from %d residual dof", r.k_m,
                r.k_turn_m, r.k_dof);
  s << buf;
  if (r.encoder_noise) {
    std::snprintf(buf, sizeof buf, " (encoder noise on: k_L %.3e, k_R %.3e)", r.encoder_k_left_m,
                  r.encoder_k_right_m);
    s << buf;
  }
  s << "\n";
  return s.str();
}

}  // namespace pavilion::scenarios
