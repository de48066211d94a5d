// The lasers see the crowd as legs (issue acceptance): in expo_crowd, each
// person a SICK LMS 200 sees gives one or two leg arcs where the ground truth
// puts the legs, and >= 99 % of the scans that see legs have no extracted line
// supported by leg readings (the extraction issue's criterion, on moving legs).
// Both hit finders: the planar caster (the runs' path) and Bullet's rays with
// the people tested analytically (the tilted-plane fallback).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>

#include "core/features/line_extraction.h"
#include "core/random/random_stream.h"
#include "scenarios/config/scenario.h"
#include "scenarios/output/scan_log.h"
#include "scenarios/run/scenario_runner.h"
#include "sim/raycast/planar_caster.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {
namespace {

constexpr double kLaserHeightM = 0.5;
// A leg reading lies on its leg's outline: the geometric hit point's distance
// from the leg's axis matches its radius to within this (m).
constexpr double kOnLegToleranceM = 0.01;
// A reading supports an extracted line when its point lies this close to it
// (m): about three of the LMS 200's range sigmas. Readings of other objects
// between a segment's first and last reading (legs in front of a wall) do not.
constexpr double kSupportM = 0.03;

// True when an extracted line is supported mostly by leg readings. Support
// per line: the pieces of a multi-segment line (eq. 5.17) share one line,
// judged on all their readings (legs pressed against a wall lie on the wall's
// line, and no extractor can tell them from it).
template <typename IsPerson>
bool HasLegLine(const core::LaserScan& scan, const core::LaserScanTruth& truth,
                const core::LineExtractionOptions& extraction, IsPerson is_person) {
  std::map<int, std::pair<int, int>> support_by_line;  // line -> (legs, all)
  const std::vector<core::Segment> segments = core::ExtractLines(scan, extraction);
  for (std::size_t k = 0; k < segments.size(); ++k) {
    const core::Segment& s = segments[k];
    const int line = s.line_id >= 0 ? s.line_id : -1 - static_cast<int>(k);
    auto& [legs, support] = support_by_line[line];
    for (int r = s.first_index; r <= s.last_index; ++r) {
      const core::LaserReading& reading = scan.readings[r];
      if (!reading.valid) continue;
      const Eigen::Vector2d point =
          reading.range_m *
          Eigen::Vector2d(std::cos(reading.bearing_rad), std::sin(reading.bearing_rad));
      if (std::abs(s.line.SignedDistance(point)) > kSupportM) continue;
      ++support;
      legs += is_person(truth.element[r]) ? 1 : 0;
    }
  }
  for (const auto& [line, counts] : support_by_line) {
    if (2 * counts.first > counts.second) return true;
  }
  return false;
}

struct LegStats {
  int scans = 0;
  int scans_with_legs = 0;
  int scans_with_leg_lines = 0;
  int people_seen = 0;
  int people_with_one_or_two_arcs = 0;
  long leg_readings = 0;
  long leg_readings_on_legs = 0;
};

LegStats ScanTheCrowd(bool planar) {
  const Scenario scenario = LoadScenarioFile(PAVILION_SOURCE_DIR "/scenarios/expo_crowd.yaml", {});
  sim::WorldDescription d = scenario.world;
  sim::World world(d, scenario.physics);
  world.AddCrowd(*scenario.crowd, scenario.seed);
  const sim::crowd::Crowd& crowd = *world.crowd();
  std::map<int, int> person_of_element;
  for (int i = 0; i < crowd.size(); ++i) person_of_element[world.person_element(i)] = i;
  sim::PlanarCaster caster(&world, sim::PlanarCasterOptions{});
  sim::LaserScanner scanner("front", sim::LaserScannerOptions::Profile("sick_lms200"),
                            core::Pose2{}, kLaserHeightM, core::RandomStream(5, 1));
  const core::LineExtractionOptions extraction = core::LineExtractionOptions::SickLms200();
  // Scanners at four places of the hall, looking into the crowd.
  const core::Pose2 places[] = {
      {-6.0, 4.5, 0.0}, {2.0, 1.0, 1.2}, {8.0, 5.0, 3.1}, {-10.0, 1.0, 0.6}};
  LegStats stats;
  const double dt = world.step_s();
  for (int k = 0; k < 400; ++k) {
    for (int s = 0; s < static_cast<int>(0.5 / dt); ++s) world.Step();
    const core::Pose2& pose = places[k % 4];
    core::LaserScanTruth truth;
    core::LaserScan scan;
    if (planar) {
      caster.Update();
      scan = scanner.ScanFrom(caster.SliceAt(kLaserHeightM), pose, world.time_s(), -1, &truth);
    } else {
      scan = scanner.ScanFrom(world, pose, world.time_s(), -1, &truth);
    }
    ++stats.scans;
    // Arcs: runs of consecutive readings on one person.
    std::map<int, int> arcs;
    int previous = -1;
    bool any_leg = false;
    for (std::size_t r = 0; r < truth.element.size(); ++r) {
      const auto it = person_of_element.find(truth.element[r]);
      const int person = it == person_of_element.end() ? -1 : it->second;
      if (person >= 0) {
        any_leg = true;
        ++stats.leg_readings;
        if (person != previous) ++arcs[person];
        // The geometric hit against the ground truth's legs.
        const core::Pose2& sensor = truth.world_from_sensor[r];
        const double bearing = sensor.theta_rad + scan.readings[r].bearing_rad;
        const Eigen::Vector2d hit =
            sensor.translation() +
            truth.true_range_m[r] * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
        const sim::crowd::PersonState& p = crowd.person(person);
        double off = 1e9;
        for (const Eigen::Vector2d& c : p.LegCentres(kLaserHeightM)) {
          off = std::min(off, std::abs((hit - c).norm() - p.shape.leg_radius_m));
        }
        if (off <= kOnLegToleranceM) ++stats.leg_readings_on_legs;
      }
      previous = person;
    }
    for (const auto& [person, count] : arcs) {
      ++stats.people_seen;
      if (count <= 2) ++stats.people_with_one_or_two_arcs;
    }
    if (!any_leg) continue;
    ++stats.scans_with_legs;
    const bool leg_line =
        HasLegLine(scan, truth, extraction, [&](int e) { return person_of_element.contains(e); });
    stats.scans_with_leg_lines += leg_line ? 1 : 0;
  }
  std::printf(
      "%s: %d scans, %d see legs (%.1f leg readings each), %d with a line on legs; %d people "
      "seen, %d as one or two arcs; %.2f %% of leg readings on a true leg\n",
      planar ? "planar" : "bullet", stats.scans, stats.scans_with_legs,
      static_cast<double>(stats.leg_readings) / std::max(1, stats.scans_with_legs),
      stats.scans_with_leg_lines, stats.people_seen, stats.people_with_one_or_two_arcs,
      100.0 * static_cast<double>(stats.leg_readings_on_legs) / std::max(1L, stats.leg_readings));
  return stats;
}

void ExpectLegs(const LegStats& s) {
  EXPECT_GT(s.scans_with_legs, s.scans / 2);  // the crowd is seen
  EXPECT_EQ(s.leg_readings_on_legs, s.leg_readings);
  // Two legs make at most two arcs; a third means a leg split by another
  // person's leg in front of it (rare).
  EXPECT_GE(s.people_with_one_or_two_arcs, 0.95 * s.people_seen);
  // These vantage points look into the thick of the crowd (some 40 % of the
  // readings on legs): there, legs of people standing in a row still line up
  // now and then (measured: 3-4 % of the scans). The criterion proper is on
  // the robot's own scans below.
  EXPECT_LE(s.scans_with_leg_lines, s.scans_with_legs * 5 / 100);
}

TEST(CrowdScans, PlanarLaserSeesPeopleAsLegs) { ExpectLegs(ScanTheCrowd(true)); }

TEST(CrowdScans, BulletRaysSeePeopleAsLegs) { ExpectLegs(ScanTheCrowd(false)); }

struct RobotScanLegs {
  int with_legs = 0;
  int with_leg_lines = 0;
};

// The robot's own scans in a run of a shipped scenario, with the scan log on.
RobotScanLegs RobotScans(const std::string& name, double duration_s) {
  ScenarioOverrides overrides;
  overrides.duration_s = duration_s;
  overrides.assignments = {"outputs.scan_log=true"};
  const Scenario scenario =
      LoadScenarioFile(PAVILION_SOURCE_DIR "/scenarios/" + name + ".yaml", overrides);
  const std::filesystem::path out =
      std::filesystem::temp_directory_path() / ("crowd_scans_" + name);
  RunOptions options;
  options.out_dir = out.string();
  options.threads = 1;
  RunScenario(scenario, options);
  const ScanLog log = ReadScanLog((out / "scans.bin").string());
  std::vector<bool> person(log.element_ids.size(), false);
  for (std::size_t e = 0; e < log.element_ids.size(); ++e) {
    person[e] = log.element_ids[e].rfind("visitor_", 0) == 0;
  }
  const auto is_person = [&](int e) { return e >= 0 && person[e]; };
  const core::LineExtractionOptions extraction = core::LineExtractionOptions::SickLms200();
  RobotScanLegs result;
  long leg_readings = 0;
  for (const ScanLogRecord& r : log.records) {
    int legs = 0;
    for (int e : r.truth.element) legs += is_person(e) ? 1 : 0;
    if (legs == 0) continue;
    ++result.with_legs;
    leg_readings += legs;
    result.with_leg_lines += HasLegLine(r.scan, r.truth, extraction, is_person) ? 1 : 0;
  }
  std::printf("%s robot scans: %zu, %d see legs (%.1f leg readings each), %d with a line on legs\n",
              name.c_str(), log.records.size(), result.with_legs,
              static_cast<double>(leg_readings) / std::max(1, result.with_legs),
              result.with_leg_lines);
  return result;
}

// Among ordinary visitors (the demo), >= 99 % of the robot's scans that see
// legs have no line supported by leg readings: the extraction issue's
// criterion on moving legs.
TEST(CrowdScans, RobotScansAmongVisitorsHaveNoLegLines) {
  const RobotScanLegs r = RobotScans("expo_visitors", 60.0);
  EXPECT_GT(r.with_legs, 100);
  EXPECT_LE(r.with_leg_lines, r.with_legs / 100);
}

// In expo_crowd the robot is crowded in a U, followed and blocked (some 70
// leg readings per scan), and still >= 99 % of its scans that see legs have
// no leg line (measured: 16 of 2004).
TEST(CrowdScans, RobotScansInExpoCrowdHaveNoLegLines) {
  const RobotScanLegs r = RobotScans("expo_crowd", 120.0);
  EXPECT_GT(r.with_legs, 100);
  EXPECT_LE(r.with_leg_lines, r.with_legs / 100);
}

}  // namespace
}  // namespace pavilion::scenarios
