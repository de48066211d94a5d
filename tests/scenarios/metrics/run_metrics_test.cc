// metrics.json from the typed RunMetrics (schema 1): keys in their order,
// figures rounded as the file has them, fleet sums from the per-robot values.
#include "scenarios/metrics/run_metrics.h"

#include <gtest/gtest.h>

namespace pavilion::scenarios {
namespace {

RunMetrics Example() {
  RunMetrics m;
  m.scenario = "example";
  m.seed = 7;
  m.pavilion_version = "0.1.0";
  m.world = "small_lab";
  m.sim_duration_s = 12.5;
  m.physics_rate_hz = 200.0;
  m.ticks = 2500;
  m.bodies = {{"cart", 1.23456789, 2}, {"visitor", 0.5, 1}};
  RobotMetrics r;
  r.id = "r1";
  r.model = "pygmalion";
  r.distance_m = 3.0000004;
  r.scans = 40;
  r.fallback_scans = 3;
  r.odometry_final_heading_error_rad = -0.0;
  r.route = RouteMetrics{{"lab", "office_01"}, 12.34567, false, 12.5};
  m.robots = {r};
  m.laser_backend = "planar";
  m.event_counts = {{"run_started", 1}, {"push", 2}};
  return m;
}

TEST(RunMetricsTest, SerializesSchemaOneWithRoundedFigures) {
  const nlohmann::ordered_json j = MetricsToJson(Example());
  EXPECT_EQ(j["schema_version"], 1);
  EXPECT_EQ(j.begin().key(), "schema_version");
  EXPECT_EQ(j["physics"]["ticks"], 2500);
  EXPECT_DOUBLE_EQ(j["bodies"]["cart"]["distance_m"].get<double>(), 1.234568);
  EXPECT_DOUBLE_EQ(j["bodies_summary"]["distance_m"].get<double>(), 1.734568);
  EXPECT_EQ(j["bodies_summary"]["collisions"], 3);
  EXPECT_DOUBLE_EQ(j["robots"]["r1"]["distance_m"].get<double>(), 3.0);
  EXPECT_FALSE(
      std::signbit(j["robots"]["r1"]["odometry_final_error"]["heading_rad"].get<double>()));
  EXPECT_DOUBLE_EQ(j["robots"]["r1"]["route"]["length_m"].get<double>(), 12.346);
  EXPECT_FALSE(j["robots"]["r1"].contains("localization"));
  EXPECT_EQ(j["laser"]["fallback_scans"], 3);
  EXPECT_EQ(j["events"]["push"], 2);
}

TEST(RunMetricsTest, FleetFiguresSumTheParts) {
  const RunMetrics m = Example();
  EXPECT_DOUBLE_EQ(m.bodies_distance_m(), 1.73456789);
  EXPECT_EQ(m.bodies_collisions(), 3);
  EXPECT_EQ(m.scans(), 40);
  EXPECT_EQ(m.events(), 3);
  EXPECT_DOUBLE_EQ(RoundForJson(-0.0000001, 6), 0.0);
}

}  // namespace
}  // namespace pavilion::scenarios
