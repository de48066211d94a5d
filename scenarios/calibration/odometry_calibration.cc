#include "scenarios/calibration/odometry_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "core/localization/encoder_odometry.h"
#include "core/odometry/umbmark.h"
#include "core/odometry/wheel_noise_fit.h"
#include "core/random/random_stream.h"
#include "scenarios/config/robot_setup.h"
#include "sim/robot/sim_robot.h"
#include "sim/world/world.h"

// Method: the straight runs give the scale (C1), the UMBmark squares the
// radius ratio and the wheelbase (C2)–(C4), iterated on the re-integrated runs
// (C6) — core/odometry/umbmark.cc; every run's residual then gives the §2.3
// noise k and the turn slip k_turn by maximum likelihood (C5') —
// core/odometry/wheel_noise_fit.cc. docs/calibration.md has the figures.

namespace pavilion::scenarios {
namespace {

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

sim::WorldDescription BareFloor(double half_size_m, double friction) {
  sim::WorldDescription w;
  w.name = "calibration_floor";
  sim::Material floor;
  floor.friction = friction;
  w.materials[kFloorMaterial] = floor;
  w.floor = {{-half_size_m, -half_size_m}, {half_size_m, half_size_m}, kFloorMaterial, {}};
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

// A tick step's wheel travels under model `m` (eq. 2.5).
core::WheelTravel Travel(const TickStep& t, int ticks_per_revolution,
                         const core::EncoderOdometryOptions& m) {
  return core::WheelTravelFromEncoders({0.0, 0, 0, ticks_per_revolution},
                                       {0.0, t.left, t.right, ticks_per_revolution}, m);
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

std::string Format(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v == 0.0 ? 0.0 : v);  // no "-0"
  return buf;
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

core::EncoderOdometryOptions NominalOdometry(const sim::RobotConfig& config) {
  core::EncoderOdometryOptions o;
  o.left_wheel_radius_m = config.description.left_wheel.radius_m;
  o.right_wheel_radius_m = config.description.right_wheel.radius_m;
  o.wheelbase_m = config.description.wheelbase_m();
  o.k_left_m = config.odometry.k_left_m;
  o.k_right_m = config.odometry.k_right_m;
  return o;
}

namespace {

// Limits of the base that the speed profiles respect.
struct DriveLimits {
  double half_base_m = 0.0;
  double decel_mps2 = 0.0;  // planned deceleration of the rims
};

// The odometry (nominal model, heading unwrapped) and the reference path it follows.
struct PathTracking {
  Eigen::Vector2d odo_p{0, 0};
  double odo_theta = 0.0;
  Eigen::Vector2d ref_p{0, 0};
  double ref_theta = 0.0;
  double arc_travel_m = 0.0;  // odometric path length along the current arc
};

// A command of the base: forward speed (m/s), turn rate (rad/s), or the
// segment is done (the reference path has moved to its end).
struct BaseCommand {
  double v = 0.0;
  double w = 0.0;
  bool done = false;
};

// Throws unless every segment's speed is reachable and every arc has a length.
void CheckSegments(const DriveRun& run, double max_rim_mps, const std::string& who) {
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
}

// Straight: profile speed along the reference heading, steering back onto its line.
BaseCommand StraightCommand(const DriveSegment& s, const DriveLimits& limits, PathTracking* t) {
  BaseCommand c;
  const double sign = s.distance_m >= 0 ? 1.0 : -1.0;
  const Eigen::Vector2d offset = t->odo_p - t->ref_p;
  const double remaining = std::abs(s.distance_m) - sign * offset.dot(Dir(t->ref_theta));
  if (remaining <= kDistanceTolM) {
    c.done = true;
    t->ref_p += s.distance_m * Dir(t->ref_theta);
    return c;
  }
  c.v = sign * ProfileSpeed(remaining, s.speed_mps, limits.decel_mps2, kCreepMps);
  const double lateral = offset.dot(Dir(t->ref_theta + kPi / 2));
  const double wanted =
      -sign * std::clamp(kLateralGainRadPerM * lateral, -kMaxLateralRad, kMaxLateralRad);
  c.w = std::clamp(-kHeadingGainPerS * (t->odo_theta - t->ref_theta - wanted), -kMaxSteerRadps,
                   kMaxSteerRadps);
  return c;
}

// In-place turn: profile rate to the reference heading plus the segment's angle.
BaseCommand TurnCommand(const DriveSegment& s, const DriveLimits& limits, PathTracking* t) {
  BaseCommand c;
  const double sign = s.angle_rad >= 0 ? 1.0 : -1.0;
  const double remaining = sign * (t->ref_theta + s.angle_rad - t->odo_theta);
  if (remaining <= kAngleTolRad) {
    c.done = true;
    t->ref_theta += s.angle_rad;
    return c;
  }
  c.w = sign * ProfileSpeed(remaining, s.speed_mps / limits.half_base_m,
                            limits.decel_mps2 / limits.half_base_m, kCreepRadps);
  return c;
}

// Arc: profile speed along the path, the turn rate of its curvature plus heading feedback.
BaseCommand ArcCommand(const DriveSegment& s, const DriveLimits& limits, PathTracking* t) {
  BaseCommand c;
  const double curvature = s.angle_rad / s.distance_m;
  const double remaining = s.distance_m - t->arc_travel_m;
  if (remaining <= kDistanceTolM) {
    c.done = true;
    // The ideal arc's chord, at the mean heading.
    const double half = 0.5 * s.angle_rad;
    const double chord =
        std::abs(half) < 1e-9 ? s.distance_m : s.distance_m * std::sin(half) / half;
    t->ref_p += chord * Dir(t->ref_theta + half);
    t->ref_theta += s.angle_rad;
    return c;
  }
  c.v = ProfileSpeed(remaining, s.speed_mps, limits.decel_mps2, kCreepMps);
  const double heading_ref = t->ref_theta + curvature * t->arc_travel_m;
  c.w = curvature * c.v + std::clamp(-kHeadingGainPerS * (t->odo_theta - heading_ref),
                                     -kMaxSteerRadps, kMaxSteerRadps);
  return c;
}

BaseCommand SegmentCommand(const DriveSegment& s, const DriveLimits& limits, PathTracking* t) {
  switch (s.type) {
    case DriveSegment::Type::kStraight:
      return StraightCommand(s, limits, t);
    case DriveSegment::Type::kTurn:
      return TurnCommand(s, limits, t);
    case DriveSegment::Type::kArc:
      return ArcCommand(s, limits, t);
  }
  return {};
}

// Dead reckoning of one encoder step with the nominal model (heading unwrapped).
void AdvanceOdometry(const core::WheelTravel& travel, double wheelbase_m, PathTracking* t) {
  const core::Pose2 next =
      core::DiffDriveStep({t->odo_p.x(), t->odo_p.y(), t->odo_theta}, travel, wheelbase_m);
  t->odo_theta += (travel.right_m - travel.left_m) / wheelbase_m;
  t->odo_p = next.translation();
  t->arc_travel_m += 0.5 * (travel.left_m + travel.right_m);
}

// One calibration run in progress: the bare-floor world, the robot and what it records.
class CalibrationDrive {
 public:
  CalibrationDrive(const sim::RobotConfig& config, const DriveRun& run,
                   const OdometryCalibrationOptions& options, std::uint64_t run_seed)
      : run_(run),
        nominal_(NominalOdometry(config)),
        who_("robot '" + config.description.model + "', run '" + run.name + "': "),
        world_(MakeWorld(config, run, options, &robot_config_)),
        robot_(&world_, robot_config_, sim::RobotPlacement{kRobotId, {}}, run_seed),
        index_(robot_.index()) {
    const sim::RobotDescription& model = config.description;
    const double small_radius =
        std::min(nominal_.left_wheel_radius_m, nominal_.right_wheel_radius_m);
    limits_.half_base_m = 0.5 * nominal_.wheelbase_m;
    limits_.decel_mps2 = kDecelFraction * model.max_wheel_accel_radps2 * small_radius;
  }

  RecordedRun Drive() {
    while (world_.time_s() < kSettleS) Step();
    std::optional<core::EncoderReading> reading;
    while (!(reading = Step())) {
    }
    rec_.run = run_;
    rec_.ticks_per_revolution = reading->ticks_per_revolution;
    rec_.true_start = world_.robot_state(index_).pose;
    const double start_s = world_.time_s();
    last_left_ = reading->left_ticks;
    last_right_ = reading->right_ticks;
    tracking_.odo_p = rec_.true_start.translation();
    tracking_.odo_theta = rec_.true_start.theta_rad;
    tracking_.ref_p = tracking_.odo_p;
    tracking_.ref_theta = tracking_.odo_theta;
    phase_start_s_ = world_.time_s();
    while (true) {
      reading = Step();
      if (!reading) continue;
      Record(*reading);
      if (!Control(world_.time_s())) break;
    }
    rec_.true_end = world_.robot_state(index_).pose;
    rec_.duration_s = world_.time_s() - start_s;
    return rec_;
  }

 private:
  static sim::World MakeWorld(const sim::RobotConfig& config, const DriveRun& run,
                              const OdometryCalibrationOptions& options, sim::RobotConfig* robot) {
    sim::WorldDescription description =
        BareFloor(RunExtent(run) + kFloorMarginM, options.floor_friction);
    *robot = WithWorldMaterials(config, &description);
    robot->lasers.clear();  // not needed here, and ray casts dominate a step's cost
    robot->bumpers.clear();
    sim::WorldOptions world_options;
    world_options.physics_rate_hz = options.physics_rate_hz;
    return sim::World(std::move(description), world_options);
  }

  // Steps the world; returns the encoder reading of the tick, if any.
  std::optional<core::EncoderReading> Step() {
    const sim::RobotState before = world_.robot_state(index_);
    world_.Step();
    const sim::SensorOutputs out = robot_.AfterStep(before, world_.robot_state(index_));
    if (out.encoders.empty()) return std::nullopt;
    return out.encoders.back();
  }

  // Records the tick step of `reading` and advances the odometry with it.
  void Record(const core::EncoderReading& reading) {
    const TickStep d{reading.left_ticks - last_left_, reading.right_ticks - last_right_};
    last_left_ = reading.left_ticks;
    last_right_ = reading.right_ticks;
    rec_.ticks.push_back(d);
    AdvanceOdometry(Travel(d, rec_.ticks_per_revolution, nominal_), nominal_.wheelbase_m,
                    &tracking_);
  }

  // Sets the wheel speeds for time `now`; false when the run is over.
  bool Control(double now) {
    if (pausing_) {
      const bool last = segment_ >= run_.segments.size();
      if (now - phase_start_s_ < (last ? kFinalRestS : kPauseS)) return true;
      if (last) return false;
      pausing_ = false;
      phase_start_s_ = now;
      tracking_.arc_travel_m = 0.0;
    }
    const DriveSegment& s = run_.segments[segment_];
    if (now - phase_start_s_ >
        kTimeoutFactor * PlannedDurationS(s, limits_.decel_mps2, limits_.half_base_m) +
            kTimeoutMarginS) {
      throw std::runtime_error(who_ + "stuck in segment " + std::to_string(segment_ + 1) +
                               " after " + Format("%.1f", now - phase_start_s_) + " s");
    }
    const BaseCommand c = SegmentCommand(s, limits_, &tracking_);
    if (c.done) {
      robot_.SetWheelSpeeds(0.0, 0.0);
      ++segment_;
      pausing_ = true;
      phase_start_s_ = now;
      return true;
    }
    robot_.SetWheelSpeeds((c.v - c.w * limits_.half_base_m) / nominal_.left_wheel_radius_m,
                          (c.v + c.w * limits_.half_base_m) / nominal_.right_wheel_radius_m);
    return true;
  }

  const DriveRun& run_;
  const core::EncoderOdometryOptions nominal_;
  const std::string who_;
  DriveLimits limits_;
  sim::RobotConfig robot_config_;
  sim::World world_;
  sim::SimRobot robot_;
  const int index_;
  RecordedRun rec_;
  PathTracking tracking_;
  std::int64_t last_left_ = 0;
  std::int64_t last_right_ = 0;
  std::size_t segment_ = 0;
  bool pausing_ = false;
  double phase_start_s_ = 0.0;
};

}  // namespace

RecordedRun DriveCalibrationRun(const sim::RobotConfig& config, const DriveRun& run,
                                const OdometryCalibrationOptions& options, std::uint64_t run_seed) {
  options.Validate();
  const core::EncoderOdometryOptions nominal = NominalOdometry(config);
  const double small_radius = std::min(nominal.left_wheel_radius_m, nominal.right_wheel_radius_m);
  CheckSegments(run, config.description.max_wheel_speed_radps * small_radius,
                "robot '" + config.description.model + "', run '" + run.name + "': ");
  return CalibrationDrive(config, run, options, run_seed).Drive();
}

core::PoseWithCovariance IntegrateRecordedRun(const RecordedRun& run,
                                              const core::EncoderOdometryOptions& model,
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
          core::NormalizeAngle(run.true_end.theta_rad - odometry_end.theta_rad)};
}

namespace {

core::WheelGeometry GeometryOf(const core::EncoderOdometryOptions& m) {
  return {m.left_wheel_radius_m, m.right_wheel_radius_m, m.wheelbase_m};
}

// The calibrated radii and wheelbase for UMBmark's factors and the straight-run scale (C4).
core::EncoderOdometryOptions CorrectedModel(const core::EncoderOdometryOptions& nominal,
                                            const core::UmbmarkResult& u, double scale) {
  const core::WheelGeometry g = core::UmbmarkCorrectedGeometry(GeometryOf(nominal), u, scale);
  core::EncoderOdometryOptions m = nominal;
  m.left_wheel_radius_m = g.left_wheel_radius_m;
  m.right_wheel_radius_m = g.right_wheel_radius_m;
  m.wheelbase_m = g.wheelbase_m;
  return m;
}

}  // namespace

namespace {

// The common side of the UMBmark squares (m); -1 when there are none.
double SquareSide(const std::vector<RecordedRun>& runs) {
  double side_m = -1.0;
  for (const RecordedRun& r : runs) {
    if (r.run.kind == CalibrationRunKind::kSquareCcw ||
        r.run.kind == CalibrationRunKind::kSquareCw) {
      const double side = std::abs(r.run.segments.front().distance_m);
      if (side_m >= 0 && std::abs(side - side_m) > 1e-9) {
        throw std::invalid_argument("UMBmark squares must all have the same side");
      }
      side_m = side;
    }
  }
  return side_m;
}

// (C1): true over odometric distance of the straight runs under the nominal model.
double StraightRunScale(const std::vector<RecordedRun>& runs,
                        const core::EncoderOdometryOptions& nominal) {
  double arc_sum = 0.0, odometric_sum = 0.0;
  for (const RecordedRun& r : runs) {
    if (r.run.kind != CalibrationRunKind::kStraight) continue;
    // The true arc from its chord and heading change.
    const double chord = (r.true_end.translation() - r.true_start.translation()).norm();
    arc_sum += core::ArcLengthFromChord(
        chord, core::NormalizeAngle(r.true_end.theta_rad - r.true_start.theta_rad));
    double ds = 0.0;
    for (const TickStep& t : r.ticks) {
      const core::WheelTravel w = Travel(t, r.ticks_per_revolution, nominal);
      ds += 0.5 * (w.left_m + w.right_m);
    }
    odometric_sum += std::abs(ds);
  }
  if (!(odometric_sum > 0.0)) throw std::invalid_argument("the calibration needs straight runs");
  return arc_sum / odometric_sum;
}

// The end-pose errors of the squares re-integrated with `model` (noise-free).
core::SquareErrors SquareErrorsOf(const std::vector<RecordedRun>& runs,
                                  const core::EncoderOdometryOptions& model) {
  core::SquareErrors errors;
  for (const CalibrationRunKind kind :
       {CalibrationRunKind::kSquareCcw, CalibrationRunKind::kSquareCw}) {
    for (const RecordedRun& r : runs) {
      if (r.run.kind == kind) {
        (kind == CalibrationRunKind::kSquareCcw ? errors.ccw : errors.cw)
            .push_back(EndPoseError(r, IntegrateRecordedRun(r, model, {}).pose));
      }
    }
  }
  return errors;
}

// Sets the UMBmark estimates of `report` (one step and iterated, C6) and the
// calibrated radii and wheelbase.
void EstimateSystematic(const std::vector<RecordedRun>& runs,
                        const std::vector<Eigen::Vector3d>& nominal_errors, double side_m,
                        OdometryCalibrationReport* report) {
  const double scale = report->straight_scale;
  const core::EncoderOdometryOptions& nominal = report->nominal;
  report->umbmark_one_step =
      core::EstimateUmbmark(ErrorsOf(runs, nominal_errors, CalibrationRunKind::kSquareCcw),
                            ErrorsOf(runs, nominal_errors, CalibrationRunKind::kSquareCw), side_m,
                            scale, nominal.wheelbase_m);
  const auto residuals = [&](const core::WheelGeometry& g) {
    core::EncoderOdometryOptions model = nominal;
    model.left_wheel_radius_m = g.left_wheel_radius_m;
    model.right_wheel_radius_m = g.right_wheel_radius_m;
    model.wheelbase_m = g.wheelbase_m;
    return SquareErrorsOf(runs, model);
  };
  report->umbmark = core::IterateUmbmark(report->umbmark_one_step, GeometryOf(nominal), side_m,
                                         scale, residuals, kUmbmarkToleranceRad,
                                         kMaxUmbmarkIterations, &report->umbmark_iterations);
  report->calibrated = CorrectedModel(nominal, report->umbmark, scale);
}

// (C5'): k̂ and k̂_turn from the residuals of every run under the calibrated
// model; sets them in `report` and returns each run's Mahalanobis distance².
// `calibrated_errors` receives the runs' residuals in their start frames.
std::vector<double> EstimateNoise(const std::vector<RecordedRun>& runs,
                                  OdometryCalibrationReport* report,
                                  std::vector<Eigen::Vector3d>* calibrated_errors) {
  std::vector<core::NoiseFitRun> fit_runs;
  for (const RecordedRun& r : runs) {
    const core::PoseWithCovariance a =
        IntegrateRecordedRun(r, report->calibrated, core::WheelNoise{1.0, 1.0, 0.0});
    const core::PoseWithCovariance b =
        IntegrateRecordedRun(r, report->calibrated, core::WheelNoise{0.0, 0.0, 1.0});
    calibrated_errors->push_back(EndPoseError(r, a.pose));
    core::NoiseFitRun fit_run;
    // The residual in the world frame, as P is.
    fit_run.residual = {r.true_end.x_m - a.pose.x_m, r.true_end.y_m - a.pose.y_m,
                        core::NormalizeAngle(r.true_end.theta_rad - a.pose.theta_rad)};
    fit_run.unit_k = a.covariance;
    fit_run.unit_turn = b.covariance;
    fit_runs.push_back(fit_run);
  }
  const core::WheelNoiseFit fit = core::FitWheelNoise(fit_runs);
  report->k_dof = 3 * static_cast<int>(runs.size());
  report->k_m = fit.k_m;
  report->k_turn_m = fit.k_turn_m;
  report->calibrated.k_left_m = report->k_m;
  report->calibrated.k_right_m = report->k_m;
  report->calibrated.k_turn_m = report->k_turn_m;
  return fit.mahalanobis_sq;
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
  for (const RecordedRun& r : runs) {
    nominal_errors.push_back(EndPoseError(r, IntegrateRecordedRun(r, report.nominal, {}).pose));
    report.simulated_s += r.duration_s;
  }
  const double side_m = SquareSide(runs);
  report.straight_scale = StraightRunScale(runs, report.nominal);
  EstimateSystematic(runs, nominal_errors, side_m, &report);
  std::vector<Eigen::Vector3d> calibrated_errors;
  const std::vector<double> m2 = EstimateNoise(runs, &report, &calibrated_errors);
  report.e_max_syst_after_m = std::max(
      core::CentreOfGravity(ErrorsOf(runs, calibrated_errors, CalibrationRunKind::kSquareCcw))
          .norm(),
      core::CentreOfGravity(ErrorsOf(runs, calibrated_errors, CalibrationRunKind::kSquareCw))
          .norm());

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

}  // namespace pavilion::scenarios
