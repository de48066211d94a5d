// The runner's seams: a test-only event type registered with the event
// registry, a test-only sensor added to each robot, and an observer of the
// robots' sensor outputs, run in a scenario without any change to the runner,
// the world or the robot.
#include <gtest/gtest.h>

#include <any>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/events/event_registry.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

// A test-only event: slows every body of the world to a stop and says how
// many it stopped.
class HaltBodiesEvent : public ScenarioEvent {
 public:
  explicit HaltBodiesEvent(std::string label) : label_(std::move(label)) {}
  std::string type() const override { return "test_halt_bodies"; }
  EventFields Apply(const EventContext& context) const override {
    for (int b = 0; b < context.world->body_count(); ++b) {
      context.world->SetPlanarVelocity(b, Eigen::Vector2d::Zero(), 0.0);
    }
    return EventFields{{"label", label_}, {"bodies", context.world->body_count()}};
  }

 private:
  std::string label_;
};

void RegisterHaltBodies() {
  static const bool registered = [] {
    EventRegistry::Global().Register("test_halt_bodies", [](MapReader& r, const EventTargets&) {
      return std::make_shared<const HaltBodiesEvent>(r.RequiredString("label").value_or(""));
    });
    return true;
  }();
  (void)registered;
}

// A test-only sensor: the robot's true speed (a wheel-free speedometer) at 20 Hz.
class SpeedometerSensor : public sim::Sensor {
 public:
  const std::string& id() const override { return id_; }
  double sample_rate_hz() const override { return 20.0; }
  void Sample(const sim::SensorTick& tick, sim::SensorOutputs* out) override {
    out->custom.push_back({id_, tick.end_s, tick.after.velocity_mps.norm()});
  }

 private:
  std::string id_ = "speedometer";
};

// Counts each robot's encoder readings, scans and speedometer readings as the run goes.
class CountingObserver : public RunObserver {
 public:
  void OnRobotOutputs(const RobotEntry& robot, const sim::SensorOutputs& outputs,
                      double now_s) override {
    EXPECT_EQ(robot.id, "r1");
    EXPECT_GT(now_s, last_s);
    last_s = now_s;
    encoders += static_cast<int>(outputs.encoders.size());
    scans += static_cast<int>(outputs.scans.size());
    for (const sim::CustomReading& r : outputs.custom) {
      EXPECT_EQ(r.sensor_id, "speedometer");
      EXPECT_DOUBLE_EQ(r.stamp_s, now_s);
      speeds.push_back(std::any_cast<double>(r.value));
    }
  }
  double last_s = 0.0;
  int encoders = 0;
  int scans = 0;
  std::vector<double> speeds;
};

const char* const kScenario =
    "kind: scenario\n"
    "name: seams\n"
    "world: small_lab\n"
    "seed: 3\n"
    "duration_s: 2\n"
    "materials:\n"
    "  cart: {friction: 0.5, color: [0.3, 0.3, 0.3]}\n"
    "bodies:\n"
    "  - {id: cart, shape: {type: box, size: [0.5, 0.4, 0.8]}, mass_kg: 20, material: cart, pose: "
    "[1.2, 1.4, 0],\n"
    "     motion: {type: scripted, segments: [{duration_s: 10, velocity: [0.3, 0]}]}}\n"
    "robots:\n"
    "  - {id: r1, model: pygmalion, pose: [-1.2, -1.5, 0.0],\n"
    "     drive: [{at_s: 0, speed_mps: 0.2, turn_radps: 0.0}]}\n"
    "events:\n"
    "  - {at_s: 0.5, type: test_halt_bodies, label: first}\n"
    "  - {at_s: 1.5, type: test_halt_bodies, label: second}\n"
    "  - {at_s: 1.0, type: push, body: cart, impulse: [5, 0]}\n";

TEST(ExtensionSeamsTest, ATestOnlyEventTypeSensorAndObserverRunWithoutRunnerChanges) {
  RegisterHaltBodies();
  const auto dir = pavilion::testing::TestDir();
  const Scenario s = LoadScenarioFile(pavilion::testing::WriteFile(dir, "seams.yaml", kScenario));
  ASSERT_EQ(s.events.size(), 3u);
  CountingObserver observer;
  RunExtensions extensions;
  extensions.observers.push_back(&observer);
  extensions.add_sensors = [](const RobotEntry&, sim::SimRobot* robot) {
    robot->AddSensor(std::make_unique<SpeedometerSensor>());
  };
  const RunSummary summary =
      RunScenario(s, RunOptions{(dir / "out").string(), false, 1}, extensions);

  // The registered type reached the timeline, the log and the metrics.
  EXPECT_EQ(summary.metrics.event_counts.at("test_halt_bodies"), 2);
  EXPECT_EQ(summary.metrics.event_counts.at("push"), 1);
  std::ifstream in(dir / "out" / "events.jsonl");
  std::vector<nlohmann::json> halts;
  for (std::string line; std::getline(in, line);) {
    const nlohmann::json e = nlohmann::json::parse(line);
    if (e["type"] == "test_halt_bodies") halts.push_back(e);
  }
  ASSERT_EQ(halts.size(), 2u);
  EXPECT_DOUBLE_EQ(halts[0]["time_s"].get<double>(), 0.5);
  EXPECT_EQ(halts[0]["label"], "first");
  EXPECT_EQ(halts[1]["bodies"], 1);

  // The observer saw every tick's readings: 200 Hz encoders for 2 s, and the
  // scans the run counted.
  EXPECT_EQ(observer.encoders, 400);
  EXPECT_EQ(observer.scans, summary.metrics.robots.at(0).scans);
  EXPECT_GT(observer.scans, 0);
  // The added sensor at its own 20 Hz; the robot drives at 0.2 m/s once its
  // motors have ramped up.
  ASSERT_EQ(observer.speeds.size(), 40u);
  EXPECT_NEAR(observer.speeds.back(), 0.2, 0.02);
  EXPECT_LT(observer.speeds.front(), observer.speeds.back());
}

// An unknown event type is an input error naming the key, with the registered types.
TEST(ExtensionSeamsTest, UnknownEventTypesAreInputErrors) {
  const auto dir = pavilion::testing::TestDir();
  std::string text = kScenario;
  text.replace(text.find("test_halt_bodies"), 16, "no_such_event");
  const std::string path = pavilion::testing::WriteFile(dir, "bad.yaml", text);
  try {
    LoadScenarioFile(path);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("events[0].type"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("push"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pavilion::scenarios
