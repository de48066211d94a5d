// `random:` entries of the event timeline (issue 17): expanded at load time
// into ordinary timed events, their times and robots drawn from the scenario
// seed (the same for a seed, others for another), periodic, uniform or a
// Poisson process; their records marked "random": true. Bad input is one
// line at its key.
#include "scenarios/events/random_events.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/events/kidnap_event.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/load_errors.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

const std::string kWorld = pavilion::testing::WalledRoomWorld("random_room", 8);

// A scenario of `duration_s` with three idle Roboxes and `events`.
std::string Write(const std::string& events, double duration_s = 3600) {
  const auto dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  return WriteFile(dir, "scenario.yaml",
                   "kind: scenario\n"
                   "name: random_test\n"
                   "seed: 5\n"
                   "duration_s: " +
                       std::to_string(duration_s) +
                       "\n"
                       "world: world.yaml\n"
                       "physics: {wheel_model: raycast}\n"
                       "robots:\n"
                       "  - {id: r1, model: robox, pose: [-4, -4, 0]}\n"
                       "  - {id: r2, model: robox, pose: [4, -4, 0]}\n"
                       "  - {id: r3, model: robox, pose: [0, 4, 0]}\n"
                       "events:\n" +
                       events);
}

// The expanded kidnaps: (time, robot) in timeline order.
std::vector<std::pair<double, std::string>> Kidnaps(const Scenario& s) {
  std::vector<std::pair<double, std::string>> out;
  for (const TimedEvent& e : s.events) {
    const auto* random = dynamic_cast<const RandomlyTimedEvent*>(e.event.get());
    EXPECT_NE(random, nullptr);
    if (random == nullptr) continue;
    const auto* kidnap = dynamic_cast<const KidnapEvent*>(&random->event());
    EXPECT_NE(kidnap, nullptr);
    if (kidnap != nullptr) out.emplace_back(e.at_s, kidnap->robot());
  }
  return out;
}

std::vector<std::pair<double, std::string>> LoadKidnaps(const std::string& path,
                                                        std::uint64_t seed) {
  ScenarioOverrides overrides;
  overrides.seed = seed;
  return Kidnaps(LoadScenarioFile(path, overrides));
}

// The same seed draws the same times and robots; another seed others. The
// count is honoured, in the window, sorted, every robot drawn from the list.
TEST(RandomEventsTest, CountIsDeterministicPerSeed) {
  const std::string path = Write(
      "  - {type: kidnap, random: {count: 12, start_s: 100, end_s: 900, robots: [r2, r3]},\n"
      "     min_distance_m: 1}\n");
  const auto a = LoadKidnaps(path, 5);
  const auto b = LoadKidnaps(path, 5);
  const auto c = LoadKidnaps(path, 6);
  ASSERT_EQ(a.size(), 12u);
  ASSERT_EQ(c.size(), 12u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  std::set<std::string> drawn;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_GE(a[k].first, 100.0);
    EXPECT_LT(a[k].first, 900.0);
    if (k > 0) {
      EXPECT_LE(a[k - 1].first, a[k].first);
    }
    drawn.insert(a[k].second);
  }
  EXPECT_EQ(drawn, (std::set<std::string>{"r2", "r3"}));  // 12 draws: both (p = 1 - 2^-11)
}

// every_s: periodic from start_s + every_s, while the run lasts: the run's
// duration after --duration, not the file's; a random robot each time.
TEST(RandomEventsTest, EveryUsesTheEffectiveDuration) {
  const std::string path = Write("  - {type: kidnap, random: {every_s: 1200}}\n");
  const auto file = Kidnaps(LoadScenarioFile(path));
  ASSERT_EQ(file.size(), 2u);  // 1200, 2400 (3600 ends the run)
  EXPECT_DOUBLE_EQ(file[0].first, 1200.0);
  EXPECT_DOUBLE_EQ(file[1].first, 2400.0);
  ScenarioOverrides longer;
  longer.duration_s = 7200;
  const auto run = Kidnaps(LoadScenarioFile(path, longer));
  ASSERT_EQ(run.size(), 5u);
  EXPECT_DOUBLE_EQ(run.back().first, 6000.0);
  ScenarioOverrides shorter;
  shorter.duration_s = 1000;
  EXPECT_TRUE(Kidnaps(LoadScenarioFile(path, shorter)).empty());
}

// Entries draw from their own streams: a random entry's draws do not change
// when another random entry is added after it.
TEST(RandomEventsTest, AnotherEntryDoesNotShiftTheDraws) {
  const std::string alone = Write("  - {type: kidnap, random: {count: 5}}\n");
  const auto a = LoadKidnaps(alone, 5);
  const std::string two = Write(
      "  - {type: kidnap, random: {count: 5}}\n"
      "  - {type: sensor_fault, random: {rate_per_h: 20}, mode: blackout}\n");
  std::vector<std::pair<double, std::string>> b;
  for (const TimedEvent& e : LoadScenarioFile(two).events) {
    const auto& inner = dynamic_cast<const RandomlyTimedEvent&>(*e.event).event();
    if (const auto* k = dynamic_cast<const KidnapEvent*>(&inner))
      b.emplace_back(e.at_s, k->robot());
  }
  EXPECT_EQ(a, b);
}

// A run shortened with --duration is the first part of the full run: the
// same times and robots up to its end (rate_per_h and every_s; a count is
// spread over the window instead).
TEST(RandomEventsTest, AShortenedRunDrawsTheFirstPartOfTheFullRun) {
  const std::string path = Write(
      "  - {type: kidnap, random: {rate_per_h: 20}}\n"
      "  - {type: kidnap, random: {every_s: 300}}\n",
      4 * 3600.0);
  const auto full = Kidnaps(LoadScenarioFile(path));
  ScenarioOverrides shorter;
  shorter.duration_s = 3600;
  const auto first_hour = Kidnaps(LoadScenarioFile(path, shorter));
  std::vector<std::pair<double, std::string>> full_first_hour;
  for (const auto& k : full) {
    if (k.first < 3600.0) full_first_hour.push_back(k);
  }
  ASSERT_GT(first_hour.size(), 20u);
  EXPECT_EQ(first_hour, full_first_hour);
}

// rate_per_h: a Poisson process. Over 1000 h at 10 per hour the count is
// Poisson(10000) (sd 100): within 4 sd of its mean; its gaps are exponential:
// the fraction shorter than the mean gap is 1 - 1/e, within 4 binomial sd.
TEST(RandomEventsTest, RateIsAPoissonProcess) {
  RandomTimes t;
  t.kind = RandomTimes::Kind::kRate;
  t.rate_per_h = 10.0;
  t.start_s = 0.0;
  t.end_s = 1000.0 * 3600.0;
  core::RandomStream stream(7, core::RandomStream::StreamId("random/0"));
  const std::vector<double> times = DrawRandomTimes(t, &stream);
  const double mean = 10.0 * 1000.0;
  EXPECT_NEAR(static_cast<double>(times.size()), mean, 4.0 * std::sqrt(mean));
  ASSERT_TRUE(std::is_sorted(times.begin(), times.end()));
  const double mean_gap_s = 360.0;
  int short_gaps = 0;
  for (std::size_t k = 1; k < times.size(); ++k) short_gaps += times[k] - times[k - 1] < mean_gap_s;
  const double n = static_cast<double>(times.size() - 1);
  const double p = 1.0 - std::exp(-1.0);
  EXPECT_NEAR(short_gaps / n, p, 4.0 * std::sqrt(p * (1.0 - p) / n));
  // Rate 0: none.
  t.rate_per_h = 0.0;
  EXPECT_TRUE(DrawRandomTimes(t, &stream).empty());
}

// Through the loader, a day at 3 per hour expands into about 72 kidnaps
// (Poisson: within 4 sd, 4 sqrt(72) = 34), all in the run.
TEST(RandomEventsTest, RateThroughTheLoader) {
  const auto k = Kidnaps(
      LoadScenarioFile(Write("  - {type: kidnap, random: {rate_per_h: 3}}\n", 24 * 3600.0)));
  EXPECT_NEAR(static_cast<double>(k.size()), 72.0, 4.0 * std::sqrt(72.0));
  for (const auto& [at_s, robot] : k) EXPECT_LT(at_s, 24 * 3600.0);
}

// In a run, each expanded event acts and is recorded as a hand-written one,
// with "random": true; a given robot is kept.
TEST(RandomEventsTest, RecordsAreMarkedRandom) {
  const Scenario s = LoadScenarioFile(Write(
      "  - {type: sensor_fault, robot: r1, random: {count: 3}, mode: blackout, duration_s: 0.2}\n"
      "  - {at_s: 1, type: push, body: r2, impulse: [5, 0]}\n"
      "  - {type: odometry_bias, random: {count: 1, start_s: 1}, wheel: both, radius_scale: "
      "1.01}\n",
      3.0));
  const auto out = TestDir() / "out";
  RunScenario(s, RunOptions{out.string(), false, 1});
  int faults = 0, biases = 0, pushes = 0;
  std::ifstream in(out / "events.jsonl");
  for (std::string line; std::getline(in, line);) {
    const nlohmann::json e = nlohmann::json::parse(line);
    if (e.at("type") == "sensor_fault") {
      ++faults;
      EXPECT_EQ(e.at("robot"), "r1");
      EXPECT_EQ(e.at("random"), true);
    } else if (e.at("type") == "odometry_bias") {
      ++biases;
      EXPECT_EQ(e.at("random"), true);
      EXPECT_GE(e.at("time_s").get<double>(), 1.0);
      EXPECT_DOUBLE_EQ(e.at("radius_scale").get<double>(), 1.01);
    } else if (e.at("type") == "push") {
      ++pushes;
      EXPECT_FALSE(e.contains("random"));
    }
  }
  EXPECT_EQ(faults, 3);
  EXPECT_EQ(biases, 1);
  EXPECT_EQ(pushes, 1);
}

TEST(RandomEventsTest, BadInputIsAnErrorAtItsKey) {
  const auto expect_error = [](const std::string& events, const std::string& key_path,
                               const std::string& says) {
    pavilion::testing::ExpectOneLoadError(Write(events), key_path, says);
  };
  expect_error("  - {type: kidnap, random: {start_s: 5}}\n", "events[0].random",
               "give one of every_s, rate_per_h or count");
  expect_error("  - {type: kidnap, random: {every_s: 60, count: 3}}\n", "events[0].random.count",
               "not both");
  expect_error("  - {type: kidnap, random: {every_s: -60}}\n", "events[0].random.every_s",
               "must be > 0");
  expect_error("  - {type: kidnap, random: {rate_per_h: -1}}\n", "events[0].random.rate_per_h",
               "must be in");
  expect_error("  - {type: kidnap, random: {count: -2}}\n", "events[0].random.count", "must be in");
  expect_error("  - {type: kidnap, random: {count: 2, start_s: -1}}\n", "events[0].random.start_s",
               "must be in");
  expect_error("  - {type: kidnap, random: {count: 2, start_s: 4000}}\n",
               "events[0].random.start_s", "after the scenario's duration_s (3600 s)");
  expect_error("  - {type: kidnap, random: {count: 2, start_s: 50, end_s: 40}}\n",
               "events[0].random.end_s", "after start_s");
  expect_error("  - {type: kidnap, random: {every_s: 0.001}}\n", "events[0].random.every_s",
               "more than 100000 events");
  expect_error("  - {at_s: 10, type: kidnap, random: {count: 2}}\n", "events[0].at_s",
               "give at_s or random, not both");
  expect_error("  - {type: kidnap, random: {count: 2, robots: [r1, r9]}}\n",
               "events[0].random.robots[1]", "no robot 'r9'");
  expect_error("  - {type: kidnap, robot: r1, random: {count: 2, robots: [r2]}}\n",
               "events[0].random.robots", "give robot or random.robots, not both");
  expect_error("  - {type: door, door: d1, state: open, random: {count: 2}}\n", "events[0].random",
               "not supported for door");
  expect_error("  - {type: kidnap, random: {count: 2, often: true}}\n", "events[0].random.often",
               "unknown key");
  // The type's own keys, checked as for a fixed event (here against a drawn robot).
  expect_error("  - {type: sensor_fault, random: {count: 2}, sensor: side, mode: blackout}\n",
               "events[0].sensor", "no laser 'side'");
  expect_error("  - {type: odometry_bias, random: {count: 2}, wheel: left, radius_scale: 2}\n",
               "events[0].radius_scale", "[0.8, 1.2]");
  expect_error("  - {type: push, random: {count: 2}}\n", "events[0].impulse", "");
}

}  // namespace
}  // namespace pavilion::scenarios
