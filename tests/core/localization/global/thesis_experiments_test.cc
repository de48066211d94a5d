// The experiments of thesis §5.7 as patterns: the Fig. 5.21 statistics of
// hypothesis generation for a local map of six segments with a half-open
// door, against p'_min; and the corridor run of §5.7.1 (Figs. 5.18-5.20):
// the localizer's state at every step of a 23-step path with a collision
// and a kidnap.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/localization/global/global_localizer.h"
#include "core/localization/global/interpretation_tree.h"
#include "core/localization/scan_observations.h"
#include "core/random/random_stream.h"
#include "tests/support/localization_world.h"
#include "tests/support/ray_cast_scanner.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
const Eigen::Matrix2d kLineR = testing::LineCovariance(0.3 * kDeg, 0.01);
const Eigen::Matrix2d kEndpointC = Eigen::Vector2d(4e-4, 4e-4).asDiagonal();  // 2 cm
const Eigen::Matrix2d kMapEndpointC = Eigen::Vector2d(1e-4, 1e-4).asDiagonal();

void AddSegment(RobotMap* map, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                const Eigen::Vector2d& seen_from) {
  MapSegment s;
  s.id = std::to_string(map->segments.size());
  s.line = testing::MapLineThrough(s.id, a, b, seen_from, 0.1 * kDeg, 0.005).line;
  s.first_endpoint = {a, kMapEndpointC};
  s.second_endpoint = {b, kMapEndpointC};
  map->segments.push_back(s);
}

// An office-like floor (designed for this test, not the thesis' map): a
// corridor y in [0, 2] along x in [0, 12] and three offices north of it,
// 4, 3 and 5 m wide and 4 m deep, each with a 1 m door in the corridor wall
// at a different place (the corridor sides of the office walls are left
// out); office 0's walls come first.
RobotMap OfficeFloor() {
  RobotMap map;
  const double x0[3] = {0.0, 4.0, 7.0};
  const double width[3] = {4.0, 3.0, 5.0};
  const double door[3] = {1.5, 0.4, 3.2};  // door start from the office's west wall
  for (int k = 0; k < 3; ++k) {
    const double w = x0[k];
    const double e = x0[k] + width[k];
    const Eigen::Vector2d in(0.5 * (w + e), 4.0);
    AddSegment(&map, {w, 2}, {w, 6}, in);                  // west
    AddSegment(&map, {w, 6}, {e, 6}, in);                  // north
    AddSegment(&map, {e, 6}, {e, 2}, in);                  // east
    AddSegment(&map, {w, 2}, {w + door[k], 2}, in);        // south, west of the door
    AddSegment(&map, {w + door[k] + 1.0, 2}, {e, 2}, in);  // south, east of the door
  }
  AddSegment(&map, {0, 0}, {12, 0}, {6, 1});  // corridor south wall
  return map;
}

// One observed segment from `world_from_robot` (sensor at the robot), noiseless.
Observation ObserveSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                           const Pose2& world_from_robot) {
  const Line world = testing::MapLineThrough("", a, b, world_from_robot.translation()).line;
  Observation o = testing::ObserveLine(world, world_from_robot, kLineR);
  const Pose2 robot_from_world = world_from_robot.Inverse();
  o.segments.push_back({{robot_from_world * a, kEndpointC}, {robot_from_world * b, kEndpointC}});
  return o;
}

// Fig. 5.21: six local segments in office 0 — west, north, east, the two
// pieces of the south wall, and a door standing half open (45 deg, not in
// the map). Generation with p'_min = 2..6 (pairing_margin large, so only
// p'_min filters): the counts fall as p' rises, none pairs all six (the
// door is unmodelled), and the best (largest p') is the truth.
TEST(ThesisExperimentsTest, Figure521HypothesesAgainstMinimumPairings) {
  const RobotMap map = OfficeFloor();
  const MeasurementPredictor predictor(map);
  const Pose2 truth{1.3, 3.8, 0.4};
  ObservationBatch batch;
  batch.view = testing::CentredView();
  for (const auto& [a, b] : std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>{
           {{0, 2}, {0, 6}},
           {{0, 6}, {4, 6}},
           {{4, 6}, {4, 2}},
           {{0, 2}, {1.5, 2}},
           {{2.5, 2}, {4, 2}},
           {{2.5, 2}, {2.5 - std::cos(kPi / 4), 2 + std::sin(kPi / 4)}}}) {
    batch.observations.push_back(ObserveSegment(a, b, truth));
  }
  LocalMap local;
  AddToLocalMap(batch, &local);
  const int thesis[5] = {63, 4, 2, 1, 0};  // p' >= 2..6, Fig. 5.21 and §5.7.2.1
  std::vector<std::size_t> counts;
  std::printf("p'_min  hypotheses  thesis (Fig. 5.21)\n");
  for (int p = 2; p <= 6; ++p) {
    InterpretationTreeOptions options;
    options.min_pairings = p;
    options.pairing_margin = 100;
    options.max_hypotheses = 100000;
    options.max_tree_nodes = 10000000;
    const InterpretationTree tree(predictor, options);
    TreeSearchStats stats;
    const std::vector<LocationHypothesisData> found = tree.Generate(local, &stats);
    EXPECT_FALSE(stats.node_limit_hit);
    EXPECT_FALSE(stats.hypothesis_limit_hit);
    counts.push_back(found.size());
    std::printf("%6d  %10zu  %6d\n", p, found.size(), thesis[p - 2]);
    if (found.empty()) continue;
    const Pose2& best = found.front().location.pose;
    EXPECT_EQ(found.front().pairings, 5) << p;
    EXPECT_LT(std::hypot(best.x_m - truth.x_m, best.y_m - truth.y_m), 0.01) << p;
    EXPECT_LT(std::abs(NormalizeAngle(best.theta_rad - truth.theta_rad)), 0.5 * kDeg) << p;
    EXPECT_TRUE(found.front().support[5].star) << "the door is unmodelled";
  }
  for (std::size_t k = 1; k < counts.size(); ++k) EXPECT_LE(counts[k], counts[k - 1]) << k;
  EXPECT_GT(counts[0], counts[2]);  // p' >= 2 admits many more than p' >= 4
  EXPECT_EQ(counts[3], 1u);         // p' >= 5: the truth alone
  EXPECT_EQ(counts[4], 0u);         // p' = 6: none
}

// ---------------------------------------------------------------------------
// §5.7.1, Figs. 5.18-5.20: the corridor pattern. A line-only map of a
// corridor of low feature discriminance (repeated structure: door recesses
// whose backs are lines 40-60 cm behind the walls), a 360 deg range finder
// of 1 deg resolution limited to 2 m, a robot "placed manually" along a
// 23-step path with magnified odometry errors, a collision at step 11 and a
// kidnap at step 18; Fig. 5.20 gives the localizer's state at every step.
//
// What is ours, not the thesis':
// - The corridor and the path (the thesis' map is not published): a hall W
//   (bottom left), a bottom corridor H, the corridor V going up with door
//   recesses on both sides, and a side corridor E off V; 23 targets in the
//   spirit of Fig. 5.18. The ray caster sees the walls as segments; the map
//   holds the infinite line through each wall, visible from its open side
//   (no extension and no unary constraint). The recesses' short sides are
//   walls but not map lines: seen edge-on from the corridor they rarely make
//   a line, and when they do it is an unpaired observation.
// - Odometry: the chapter-2 model (eqs. 2.5-2.13) for the true robot (whole
//   encoder ticks, wheel travel noise) and for the localizer alike, with
//   the wheel-space noise magnified x2 (k_L = k_R = 1e-5 m). The thesis'
//   Cartesian-space noise (x10) is replaced by the collision: at step 11
//   the robot is pushed 0.6 m sideways and turned 25 deg, which the
//   encoders do not see.
// - The localizer is GlobalLocalizer: once localized it tracks with the
//   chapter-4 EKF (no track splitting), so it stays localized at steps
//   14-18 where the thesis' track splitting made several hypotheses; the
//   kidnap goes unnoticed at step 18 here as there (the view is compatible
//   with the prediction), so the robot is declared localized at a wrong
//   place at step 18 — the one step exempt from the accuracy check.
// - Each step is a drive from the true pose to the next target (turn,
//   straight, turn: the thesis' user placed the robot relative to its last
//   true position) followed by one scan; the scan's seam (first and last
//   beam, where a wall would be cut in two) points backwards, which the
//   targets' headings leave open.
//
// The options are the thesis' experiment's (see CorridorOptions()).
// Checked for seeds 1-4 below. Of seeds 1-400, 398 give the whole pattern;
// in the other two an unlucky draw meets the 95% gates (the thesis' alpha):
// in 183 a poorly extracted line at step 3 lets a half-turned twin survive,
// pairing one line in two, until step 7 (localized at 7, not 3-5); in 351
// the west recess is not extracted at step 12 and its half-turned twin
// explains the other four lines as well, both surviving until the kidnap
// (not localized at 11-14).
constexpr int kTicksPerRevolution = 25000;
constexpr double kWheelRadiusM = 0.09;
constexpr double kWheelbaseM = 0.5;
constexpr double kOdometryPeriodS = 0.01;
constexpr std::int64_t kTicksPerPeriod = 400;  // 0.9 m/s
constexpr double kTickM = 2.0 * kPi * kWheelRadiusM / kTicksPerRevolution;
constexpr double kWheelNoiseM = 2.0 * 5e-6;  // §2.3's k_L = k_R, magnified x2
constexpr double kRangeSigmaM = 0.01;
constexpr double kMaxRangeM = 2.0;
// Declared localized only within these of the truth (except at the kidnap).
constexpr double kWrongPositionM = 0.5;
constexpr double kWrongHeadingRad = 10.0 * kDeg;

struct Corridor {
  std::vector<testing::Wall> walls;  // for the ray caster
  RobotMap map;                      // infinite lines
};

// A wall from a to b; with `mapped`, also the infinite line through it,
// visible from `seen_from` (one map line per distinct line).
void AddWall(Corridor* c, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
             const Eigen::Vector2d& seen_from, bool mapped = true) {
  c->walls.push_back({a, b});
  if (!mapped) return;
  const MapLine line = testing::MapLineThrough(std::to_string(c->map.lines.size()), a, b, seen_from,
                                               0.1 * kDeg, 0.005);
  for (const MapLine& m : c->map.lines) {
    if (std::abs(NormalizeAngle(m.line.alpha_rad - line.line.alpha_rad)) < 1e-9 &&
        std::abs(m.line.r_m - line.line.r_m) < 1e-9) {
      return;
    }
  }
  c->map.lines.push_back(line);
}

// A corridor wall along x = x0 from y0 to y1 (y0 < y1), seen from the side
// opposite to `depth`'s sign, with door recesses `depth` deep over the given
// [from, to] intervals (ascending).
void WallWithRecesses(Corridor* c, double x0, double y0, double y1, double depth,
                      const std::vector<std::pair<double, double>>& recesses) {
  const double corridor_x = x0 - std::copysign(0.5, depth);
  double y = y0;
  for (const auto& [from, to] : recesses) {
    AddWall(c, {x0, y}, {x0, from}, {corridor_x, from});
    AddWall(c, {x0 + depth, from}, {x0 + depth, to}, {corridor_x, from});  // the back
    AddWall(c, {x0, from}, {x0 + depth, from}, {x0, from + 0.1}, false);   // the sides
    AddWall(c, {x0, to}, {x0 + depth, to}, {x0, to - 0.1}, false);
    y = to;
  }
  AddWall(c, {x0, y}, {x0, y1}, {corridor_x, y1});
}

// W: x in [-6.8, -4], y in [-8.8, -5.2], open to H on its east side;
// H: y in [-8.2, -6], from W to V; V: x in [-1, 1], from H up to y = 8.5,
// recesses 0.4 m deep on the west side and 0.6 m on the east side (the two
// sides differ so that V is not symmetric under a half turn); E: y in
// [3.2, 4.8], from V east to x = 3.6. No two pairs of facing parallel lines
// are equally far apart (W 2.8 x 3.6, H 2.2, V 2.0, E 1.6).
Corridor MakeCorridor() {
  Corridor c;
  const Eigen::Vector2d w(-5.5, -7.0);  // inside W
  AddWall(&c, {-6.8, -8.8}, {-6.8, -5.2}, w);
  AddWall(&c, {-6.8, -5.2}, {-4, -5.2}, w);
  AddWall(&c, {-6.8, -8.8}, {-4, -8.8}, w);
  AddWall(&c, {-4, -5.2}, {-4, -6}, w);
  AddWall(&c, {-4, -8.2}, {-4, -8.8}, w);
  AddWall(&c, {-4, -6}, {-1, -6}, {0, -7});
  AddWall(&c, {-4, -8.2}, {1, -8.2}, {0, -7});
  WallWithRecesses(&c, -1, -6, 8.5, -0.4, {{-4.6, -3.7}, {2.2, 3.1}, {3.6, 4.6}, {6.4, 7.3}});
  WallWithRecesses(&c, 1, -8.2, 3.2, 0.6, {{-0.9, 0.0}});
  WallWithRecesses(&c, 1, 4.8, 8.5, 0.6, {{6.0, 6.9}});
  AddWall(&c, {-1, 8.5}, {1, 8.5}, {0, 7});
  AddWall(&c, {1, 3.2}, {3.6, 3.2}, {2, 4});
  AddWall(&c, {1, 4.8}, {3.6, 4.8}, {2, 4});
  AddWall(&c, {3.6, 3.2}, {3.6, 4.8}, {2, 4});
  return c;
}

Pose2 At(double x_m, double y_m, double theta_deg) { return {x_m, y_m, theta_deg * kDeg}; }

// Where the robot is driven before each scan. Step 1: a corner of W (two
// perpendicular lines); 2: H (only lines along H: every hypothesis off in y
// falls); 3: the junction; 4: V (only lines along V: those off in x fall);
// 4-10 up V; 11: towards the recess at y = 2.2-3.1, where it is pushed;
// 12: the E junction (V's walls, E's walls and a west recess: unique);
// 13-17 up V to its end and back; 18: down V (but kidnapped to H); 19 and
// 20 in W; 21-23 back through H into V.
const std::vector<Pose2> kCorridorTargets = {
    At(-6.1, -5.9, 135), At(-3.0, -7.1, 0),   At(0.0, -6.7, 0),    At(0.0, -4.5, 90),
    At(0.3, -3.0, 80),   At(-0.3, -1.6, 110), At(0.3, -0.2, 70),   At(-0.3, 1.0, 100),
    At(0.0, 0.4, -90),   At(0.0, 1.4, 90),    At(0.0, 2.6, 90),    At(0.2, 4.0, 90),
    At(0.0, 5.6, 90),    At(-0.3, 6.8, 100),  At(0.2, 7.4, 80),    At(0.0, 7.8, 90),
    At(0.0, 6.4, -90),   At(0.0, 5.2, -90),   At(-5.4, -7.0, 180), At(-4.9, -7.1, 180),
    At(-2.3, -7.1, 0),   At(0.0, -6.7, 0),    At(0.0, -4.5, 90)};
constexpr int kCollisionStep = 11;
const Pose2 kCollisionPush = At(0.0, 0.6, 25);  // robot frame: to the left, turned left
constexpr int kKidnapStep = 18;
// At H's west end, heading west: H's north wall on the right 1.0 m away, as
// V's west wall is seen from the prediction (heading south in V), so the
// view at step 18 is compatible; at step 19, in W, none of the three lines
// seen is where the prediction (further down V) expects one.
const Pose2 kKidnapPose = At(-3.6, -7.0, 180);

// Fig. 5.20: L localized (diamonds), - lost (circles), . not localized.
constexpr char kFigure520[] = "...LLLLLLL-LL........LL";

// The options as the thesis' experiment had them.
GlobalLocalizerOptions CorridorOptions() {
  GlobalLocalizerOptions o;
  o.tracking.odometry = {kWheelRadiusM, kWheelRadiusM, kWheelbaseM, kWheelNoiseM, kWheelNoiseM};
  o.tracking.default_laser.extract_beacons = false;
  o.tracking.default_laser.lines.range_sigma_m = kRangeSigmaM;
  // "Observations ... receive a typical, constant and uncorrelated
  // uncertainty": the fit's, with a floor of 1 deg / 2 cm (which also
  // drops the few poorly fitted lines, above 1.5 deg / 3.5 cm).
  o.tracking.default_laser.lines.alpha_sigma_floor_rad = 1.0 * kDeg;
  o.tracking.default_laser.lines.r_sigma_floor_m = 0.02;
  // Lost at the first step without a valid pairing (steps 11 and 19), with
  // two observations or more.
  o.tracking.lost_failed_cycles = 1;
  o.tracking.min_observations_for_failure = 2;
  // Two lines make a hypothesis (two perpendicular lines: 72 at step 1),
  // and only the interpretations pairing the most observations count (step
  // 12: "four lines ... globally unique in combination ... a single
  // hypothesis"; with p'_best - 1 any three of them would place the robot
  // anywhere along V).
  o.tree.min_pairings = 2;
  o.tree.pairing_margin = 0;
  // A hypothesis without a valid pairing is falsified at once, whatever
  // the number of observations.
  o.min_evidence = 1;
  o.falsify_failed_cycles = 1;
  // Localized as soon as a single hypothesis remains.
  o.min_cycles_to_localize = 0;
  o.min_cycles_after_ambiguity = 0;
  // The thesis' constraints alone.
  o.use_free_space = false;
  // A step's drive takes up to 5 s.
  o.odometry_span_s = 10.0;
  return o;
}

struct Motion {
  double distance_m = 0.0;
  double turn_rad = 0.0;  // signed, unwrapped
};

// Drives the true robot from where it is to `target`: a turn towards it, a
// straight, a turn to its heading (turning around clockwise), at whole ticks
// with wheel noise. Returns the commanded motion.
Motion DriveTo(const Pose2& target, testing::TickDrive* drive, GlobalLocalizer* localizer,
               RandomStream* rng) {
  const auto run = [&](double left_m, double right_m) {
    const std::int64_t total = std::llround(std::max(std::abs(left_m), std::abs(right_m)) / kTickM);
    const std::int64_t left_sign = left_m < 0.0 ? -1 : 1;
    const std::int64_t right_sign = right_m < 0.0 ? -1 : 1;
    for (std::int64_t done = 0; done < total; done += kTicksPerPeriod) {
      const std::int64_t t = std::min(kTicksPerPeriod, total - done);
      localizer->AddEncoders(drive->Step(left_sign * t, right_sign * t, rng, kWheelNoiseM));
    }
  };
  const auto turn = [&](double angle_rad) {
    const double s = 0.5 * kWheelbaseM * angle_rad;
    run(-s, s);
  };
  const auto clockwise_about = [](double angle_rad) {
    return angle_rad > 170.0 * kDeg ? angle_rad - 2.0 * kPi : angle_rad;
  };
  const Pose2 from = drive->pose();
  const Eigen::Vector2d d = target.translation() - from.translation();
  const bool moves = d.norm() > 0.05;
  const double heading = moves ? std::atan2(d.y(), d.x()) : from.theta_rad;
  Motion motion;
  for (const double angle_rad : {clockwise_about(NormalizeAngle(heading - from.theta_rad)),
                                 clockwise_about(NormalizeAngle(target.theta_rad - heading))}) {
    turn(angle_rad);
    motion.turn_rad += angle_rad;
    if (moves && motion.distance_m == 0.0) {
      run(d.norm(), d.norm());
      motion.distance_m = d.norm();
    }
  }
  return motion;
}

struct CorridorStep {
  Pose2 truth;
  Motion driven;  // since the previous scan (a push or kidnap aside)
  int lines = 0;  // extracted from the scan
  GlobalLocalizationState state = GlobalLocalizationState::kLost;
  int hypotheses = 0;  // n after the step
  double position_error_m = 0.0;
  double heading_error_rad = 0.0;
};

const char* StateName(GlobalLocalizationState state) {
  switch (state) {
    case GlobalLocalizationState::kLost:
      return "lost";
    case GlobalLocalizationState::kNotLocalized:
      return "not localized";
    case GlobalLocalizationState::kLocalized:
      return "localized";
  }
  return "?";
}

const char* ThesisStateName(char c) {
  return c == 'L' ? "localized" : c == '-' ? "lost" : "not localized";
}

// The 23 steps with the given seed (wheel and range noise).
std::vector<CorridorStep> RunCorridor(std::uint64_t seed, GlobalLocalizerCounters* counters) {
  const Corridor corridor = MakeCorridor();
  const GlobalLocalizerOptions options = CorridorOptions();
  testing::Scanner scanner;
  scanner.beams = 360;
  scanner.field_of_view_rad = 2.0 * kPi;
  scanner.max_range_m = kMaxRangeM;
  scanner.range_sigma_m = kRangeSigmaM;
  GlobalLocalizer localizer(corridor.map, options);
  testing::TickDrive drive(kCorridorTargets[0], kTicksPerRevolution, kWheelRadiusM, kWheelbaseM,
                           kOdometryPeriodS);
  RandomStream rng(seed, RandomStream::StreamId("thesis_corridor"));
  localizer.AddEncoders(drive.Start());
  std::vector<CorridorStep> steps;
  for (int k = 1; k <= static_cast<int>(kCorridorTargets.size()); ++k) {
    const Motion driven =
        k > 1 ? DriveTo(kCorridorTargets[k - 1], &drive, &localizer, &rng) : Motion{};
    if (k == kCollisionStep) drive.Teleport(drive.pose() * kCollisionPush);
    if (k == kKidnapStep) drive.Teleport(kKidnapPose);
    const LaserScan scan =
        testing::CastScan(corridor.walls, drive.pose(), scanner, drive.stamp_s(), &rng);
    localizer.AddScan(scan);
    CorridorStep step;
    step.truth = drive.pose();
    step.driven = driven;
    step.lines = static_cast<int>(
        ScanObservations(scan, scan, options.tracking.default_laser).observations.size());
    step.state = localizer.state();
    step.hypotheses = localizer.hypothesis_count();
    step.position_error_m = testing::PositionError(localizer.Estimate().pose, drive.pose());
    step.heading_error_rad = testing::HeadingError(localizer.Estimate().pose, drive.pose());
    steps.push_back(step);
  }
  *counters = localizer.counters();
  return steps;
}

// §5.7.1, Figs. 5.18-5.20 (see the comment above kTicksPerRevolution).
// Checked, for each seed: the first generation yields many hypotheses; lost
// at step 11 +-1 and at step 19 +-1 (state lost, or n = 0 after the step);
// each step s at which Fig. 5.20 shows the robot localized (4-10, 12, 13,
// 22, 23) is matched by a step in [s - 1, s + 1] at which ours is localized
// (the tolerance is per step: a localization one step early or late, or a
// step missed inside a localized stretch, passes); and, except at the
// kidnap step, never localized farther than 0.5 m / 10 deg from the truth.
TEST(ThesisExperimentsTest, Figure520CorridorPattern) {
  constexpr int kSteps = sizeof(kFigure520) - 1;
  ASSERT_EQ(kCorridorTargets.size(), static_cast<std::size_t>(kSteps));
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    GlobalLocalizerCounters counters;
    const std::vector<CorridorStep> steps = RunCorridor(seed, &counters);
    std::printf(
        "seed %llu\nstep  truth (x, y, theta)     lines  ours            n  error        "
        "thesis (Fig. 5.20)\n",
        static_cast<unsigned long long>(seed));
    for (int k = 1; k <= kSteps; ++k) {
      const CorridorStep& s = steps[k - 1];
      std::printf("%4d  (%5.2f, %5.2f, %4.0f)  %5d  %-13s %3d  %4.2f m %4.1f  %s%s\n", k,
                  s.truth.x_m, s.truth.y_m, s.truth.theta_rad / kDeg, s.lines, StateName(s.state),
                  s.hypotheses, s.position_error_m, s.heading_error_rad / kDeg,
                  ThesisStateName(kFigure520[k - 1]),
                  k == 1                ? " (72 hypotheses)"
                  : k == kCollisionStep ? " (collision)"
                  : k == kKidnapStep    ? " (kidnapped)"
                                        : "");
    }
    double distance_m = 0.0;
    double turn_rad = 0.0;
    for (int k = 2; k <= kSteps; ++k) {
      distance_m += steps[k - 1].driven.distance_m;
      turn_rad += steps[k - 1].driven.turn_rad;
    }
    std::printf(
        "driven between scans: %.2f m and %.1f deg on average (thesis: 1.49 m, "
        "-18.0 deg); generations %ld, splits %ld, falsified %ld, node limit hits %ld\n",
        distance_m / (kSteps - 1), turn_rad / (kSteps - 1) / kDeg, counters.generations,
        counters.splits, counters.falsified, counters.node_limit_hits);
    const auto lost = [&](int k) {
      const CorridorStep& s = steps[k - 1];
      return s.state == GlobalLocalizationState::kLost || s.hypotheses == 0;
    };
    const auto localized = [&](int k) {
      return steps[k - 1].state == GlobalLocalizationState::kLocalized;
    };
    const auto within_one = [&](int s, const auto& holds) {
      for (int k = std::max(1, s - 1); k <= std::min(kSteps, s + 1); ++k) {
        if (holds(k)) return true;
      }
      return false;
    };
    EXPECT_GE(steps[0].hypotheses, 10) << "the first generation (thesis: 72)";
    EXPECT_TRUE(within_one(kCollisionStep, lost)) << "lost after the collision";
    EXPECT_TRUE(within_one(kKidnapStep + 1, lost)) << "lost after the kidnap";
    for (int s = 1; s <= kSteps; ++s) {
      if (kFigure520[s - 1] == 'L') {
        EXPECT_TRUE(within_one(s, localized)) << "localized near step " << s;
      }
      if (localized(s) && s != kKidnapStep) {
        EXPECT_LT(steps[s - 1].position_error_m, kWrongPositionM) << "step " << s;
        EXPECT_LT(steps[s - 1].heading_error_rad, kWrongHeadingRad) << "step " << s;
      }
    }
    EXPECT_EQ(counters.node_limit_hits, 0);  // complete searches, as the thesis'
  }
}

}  // namespace
}  // namespace pavilion::core
