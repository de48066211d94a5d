// The crowd's input: a scenario's `crowd:` block (scenarios/config/crowd_reader.h),
// `outputs.people_rate_hz`, and the stations' `attraction` in world files.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/validate.h"
#include "scenarios/config/world_loader.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

// A 16 m square hall inside a 20 m floor with entrance and exit areas,
// stations of several attractions, a dock and places that do not fit a crowd.
const std::string kWorld =
    "kind: world\n"
    "name: crowd_hall\n"
    "materials:\n"
    "  concrete:\n"
    "    friction: 0.8\n"
    "floor:\n"
    "  min: [-10, -10]\n"
    "  max: [10, 10]\n"
    "  material: concrete\n"
    "walls:\n"
    "  - id: outline\n"
    "    points: [[-8, -8], [8, -8], [8, 8], [-8, 8]]\n"
    "    closed: true\n"
    "    thickness: 0.2\n"
    "    height: 2.5\n"
    "    material: concrete\n"
    "places:\n"
    "  visitor_spawn:\n"
    "    area: [[-7, -7], [-5, -7], [-5, -5], [-7, -5]]\n"
    "  visitor_exit:\n"
    "    area: [[5, 5], [7, 5], [7, 7], [5, 7]]\n"
    "  gate_in:\n"
    "    area: [[-7, 5], [-5, 5], [-5, 7], [-7, 7]]\n"
    "  gate_out:\n"
    "    area: [[5, -7], [7, -7], [7, -5], [5, -5]]\n"
    "  hall:\n"
    "    area: [[-7, -7], [7, -7], [7, 7], [-7, 7]]\n"
    "  beyond:\n"
    "    area: [[8.5, 0], [9.5, 0], [10.5, 1]]\n"
    "  centre:\n"
    "    pose: [0, 0, 0]\n"
    "  station_a: {pose: [2, 0, 0], attraction: 2.5}\n"
    "  station_b: {pose: [-2, 0, 3.1416]}\n"
    "  station_closed: {pose: [0, 3, 0], attraction: 0}\n"
    "  showcase: {pose: [0, -3, 1.5708], station: true, attraction: 0.5}\n"
    "  dock_1: {pose: [6, 0, 0]}\n";

// A scenario on kWorld with the `visitor` and `skin` materials, `extra` appended.
std::string ScenarioWith(const std::string& extra) {
  return "kind: scenario\n"
         "name: crowd_run\n"
         "duration_s: 10\n"
         "world: world.yaml\n"
         "materials:\n"
         "  visitor:\n"
         "    friction: 0.6\n"
         "  skin:\n"
         "    friction: 0.5\n" +
         extra;
}

// A `crowd:` block that sets every key to a value other than its default.
const std::string kFullCrowd =
    "crowd:\n"
    "  pool: 40\n"
    "  present: 12\n"
    "  max_present: 30\n"
    "  arrivals_per_hour: 200\n"
    "  entrance: gate_in\n"
    "  exit: gate_out\n"
    "  roam_area: hall\n"
    "  attractions: [station_b, showcase]\n"
    "  material: skin\n"
    "  visit: {min_exhibits: 2, max_exhibits: 4, dwell_mean_s: 45, dwell_std_s: 10,\n"
    "          visit_mean_s: 600, visit_std_s: 120, desired_speed_mean_mps: 1.2,\n"
    "          desired_speed_std_mps: 0.2, group_fraction: 0.25, min_group_size: 3,\n"
    "          max_group_size: 4}\n"
    "  behaviours: {curious: 0.1, crowding: 0.08, blocking: 0.04, following: 0.06,\n"
    "               pushing: 0.02, notice_range_m: 5, episode_mean_s: 20, cooldown_s: 90,\n"
    "               push_force_n: 150, push_duration_s: 0.4, kick_duration_s: 0.15}\n"
    "  body: {min_shoulder_radius_m: 0.19, max_shoulder_radius_m: 0.24,\n"
    "         min_leg_diameter_m: 0.11, max_leg_diameter_m: 0.14, hip_height_m: 0.9,\n"
    "         height_m: 1.75, hip_half_width_m: 0.1, mass_kg: 75, step_length_m: 0.7}\n"
    "  social_force: {relaxation_s: 0.6, person_strength_n: 2100, person_range_m: 0.09,\n"
    "                 anisotropy: 0.25, wall_strength_n: 1900, wall_range_m: 0.07,\n"
    "                 robot_strength_n: 2500, robot_range_m: 0.25, body_stiffness_npm: 1.0e5,\n"
    "                 sliding_friction_nspm2: 2.0e5, max_speed_factor: 1.4,\n"
    "                 social_rate_hz: 25, social_cutoff_m: 0.7, max_substep_s: 0.004,\n"
    "                 max_push_force_n: 250, contact_restitution: 0.35}\n"
    "  route_cell_m: 0.25\n"
    "  route_clearance_m: 0.35\n"
    "  watch_spots: 8\n";

// Writes kWorld (or `world`) and the scenario into the test folder; returns its path.
std::string WriteScenario(const std::string& scenario, const std::string& world = kWorld) {
  const fs::path dir = TestDir();
  WriteFile(dir, "world.yaml", world);
  return WriteFile(dir, "scenario.yaml", scenario);
}

// The one diagnostic of a scenario that must fail, after checking that
// ValidateFile reports the same.
Diagnostic OnlyError(const std::string& path) {
  std::vector<Diagnostic> diagnostics;
  try {
    LoadScenarioFile(path);
    ADD_FAILURE() << "LoadScenarioFile accepted " << path;
  } catch (const InputError& e) {
    diagnostics = e.diagnostics();
  }
  const std::vector<Diagnostic> validated = ValidateFile(path);
  EXPECT_EQ(validated.size(), diagnostics.size());
  for (std::size_t i = 0; i < std::min(validated.size(), diagnostics.size()); ++i) {
    EXPECT_EQ(validated[i].ToString(), diagnostics[i].ToString());
  }
  std::string all;
  for (const Diagnostic& d : diagnostics) all += d.ToString() + "\n";
  EXPECT_EQ(diagnostics.size(), 1u) << all;
  return diagnostics.empty() ? Diagnostic{} : diagnostics.front();
}

// Checks that the scenario `text` fails with one error at `key` on the line of `marker`.
void ExpectCrowdError(const std::string& text, const std::string& marker, const std::string& key,
                      const std::string& part) {
  SCOPED_TRACE(key);
  const std::string path = WriteScenario(text);
  const Diagnostic d = OnlyError(path);
  EXPECT_EQ(d.file, path);
  EXPECT_EQ(d.line, LineOf(text, marker)) << d.ToString();
  EXPECT_EQ(d.key_path, key) << d.ToString();
  EXPECT_TRUE(Contains(d.message, part));
}

// Confirms that a `crowd:` block fills every field of the scenario's CrowdSpec.
TEST(CrowdConfigTest, FullCrowdBlockFillsEveryField) {
  const std::string path =
      WriteScenario(ScenarioWith(kFullCrowd + "outputs: {people_rate_hz: 0.5}\n"));
  const Scenario s = LoadScenarioFile(path);
  EXPECT_TRUE(ValidateFile(path).empty());
  EXPECT_DOUBLE_EQ(s.outputs.people_rate_hz, 0.5);
  ASSERT_TRUE(s.crowd.has_value());
  const sim::CrowdSpec& c = *s.crowd;
  const sim::crowd::CrowdOptions& o = c.options;
  EXPECT_EQ(o.pool_size, 40);
  EXPECT_EQ(o.initial_present, 12);
  EXPECT_EQ(o.max_present, 30);
  EXPECT_DOUBLE_EQ(o.arrivals_per_hour, 200.0);
  EXPECT_DOUBLE_EQ(o.route_cell_m, 0.25);
  EXPECT_DOUBLE_EQ(o.route_clearance_m, 0.35);
  EXPECT_EQ(o.watch_spots, 8);
  EXPECT_EQ(o.visit.min_exhibits, 2);
  EXPECT_EQ(o.visit.max_exhibits, 4);
  EXPECT_DOUBLE_EQ(o.visit.dwell_mean_s, 45.0);
  EXPECT_DOUBLE_EQ(o.visit.dwell_std_s, 10.0);
  EXPECT_DOUBLE_EQ(o.visit.visit_mean_s, 600.0);
  EXPECT_DOUBLE_EQ(o.visit.visit_std_s, 120.0);
  EXPECT_DOUBLE_EQ(o.visit.desired_speed_mean_mps, 1.2);
  EXPECT_DOUBLE_EQ(o.visit.desired_speed_std_mps, 0.2);
  EXPECT_DOUBLE_EQ(o.visit.group_fraction, 0.25);
  EXPECT_EQ(o.visit.min_group_size, 3);
  EXPECT_EQ(o.visit.max_group_size, 4);
  EXPECT_DOUBLE_EQ(o.behaviours.curious, 0.1);
  EXPECT_DOUBLE_EQ(o.behaviours.crowding, 0.08);
  EXPECT_DOUBLE_EQ(o.behaviours.blocking, 0.04);
  EXPECT_DOUBLE_EQ(o.behaviours.following, 0.06);
  EXPECT_DOUBLE_EQ(o.behaviours.pushing, 0.02);
  EXPECT_DOUBLE_EQ(o.behaviours.notice_range_m, 5.0);
  EXPECT_DOUBLE_EQ(o.behaviours.episode_mean_s, 20.0);
  EXPECT_DOUBLE_EQ(o.behaviours.cooldown_s, 90.0);
  EXPECT_DOUBLE_EQ(o.behaviours.push_force_n, 150.0);
  EXPECT_DOUBLE_EQ(o.behaviours.push_duration_s, 0.4);
  EXPECT_DOUBLE_EQ(o.behaviours.kick_duration_s, 0.15);
  EXPECT_DOUBLE_EQ(o.body.min_shoulder_radius_m, 0.19);
  EXPECT_DOUBLE_EQ(o.body.max_shoulder_radius_m, 0.24);
  EXPECT_DOUBLE_EQ(o.body.min_leg_diameter_m, 0.11);
  EXPECT_DOUBLE_EQ(o.body.max_leg_diameter_m, 0.14);
  EXPECT_DOUBLE_EQ(o.body.hip_height_m, 0.9);
  EXPECT_DOUBLE_EQ(o.body.height_m, 1.75);
  EXPECT_DOUBLE_EQ(o.body.hip_half_width_m, 0.1);
  EXPECT_DOUBLE_EQ(o.body.mass_kg, 75.0);
  EXPECT_DOUBLE_EQ(o.body.step_length_m, 0.7);
  EXPECT_DOUBLE_EQ(o.social.relaxation_s, 0.6);
  EXPECT_DOUBLE_EQ(o.social.person_strength_n, 2100.0);
  EXPECT_DOUBLE_EQ(o.social.person_range_m, 0.09);
  EXPECT_DOUBLE_EQ(o.social.anisotropy, 0.25);
  EXPECT_DOUBLE_EQ(o.social.wall_strength_n, 1900.0);
  EXPECT_DOUBLE_EQ(o.social.wall_range_m, 0.07);
  EXPECT_DOUBLE_EQ(o.social.robot_strength_n, 2500.0);
  EXPECT_DOUBLE_EQ(o.social.robot_range_m, 0.25);
  EXPECT_DOUBLE_EQ(o.social.body_stiffness_npm, 1.0e5);
  EXPECT_DOUBLE_EQ(o.social.sliding_friction_nspm2, 2.0e5);
  EXPECT_DOUBLE_EQ(o.social.max_speed_factor, 1.4);
  EXPECT_DOUBLE_EQ(o.social.social_rate_hz, 25.0);
  EXPECT_DOUBLE_EQ(o.social.social_cutoff_m, 0.7);
  EXPECT_DOUBLE_EQ(o.social.max_substep_s, 0.004);
  EXPECT_DOUBLE_EQ(o.social.max_push_force_n, 250.0);
  EXPECT_DOUBLE_EQ(o.social.contact_restitution, 0.35);

  EXPECT_EQ(c.entrance, s.world.places.at("gate_in").area.value());
  EXPECT_EQ(c.exit, s.world.places.at("gate_out").area.value());
  EXPECT_EQ(c.roam_area, s.world.places.at("hall").area.value());
  ASSERT_EQ(c.attractions.size(), 2u);  // in the listed order
  EXPECT_EQ(c.attractions[0].name, "station_b");
  EXPECT_EQ(c.attractions[0].pose, (core::Pose2{-2, 0, 3.1416}));
  EXPECT_DOUBLE_EQ(c.attractions[0].weight, 1.0);
  EXPECT_EQ(c.attractions[1].name, "showcase");
  EXPECT_EQ(c.attractions[1].pose, (core::Pose2{0, -3, 1.5708}));
  EXPECT_DOUBLE_EQ(c.attractions[1].weight, 0.5);
  EXPECT_EQ(c.material, "skin");
  EXPECT_EQ(c.id_prefix, "visitor_");
}

// Confirms the defaults of an empty block: the struct's options, the pool as
// large as max_present, the visitor_spawn and visitor_exit areas, no roam area,
// every station but docks and closed ones, material "visitor"; and no crowd
// (and the people rate's default) without the block.
TEST(CrowdConfigTest, EmptyCrowdBlockTakesTheDefaults) {
  const Scenario none = LoadScenarioFile(WriteScenario(ScenarioWith("")));
  EXPECT_FALSE(none.crowd.has_value());
  EXPECT_DOUBLE_EQ(none.outputs.people_rate_hz, OutputOptions{}.people_rate_hz);

  const Scenario s = LoadScenarioFile(WriteScenario(ScenarioWith("crowd: {}\n")));
  ASSERT_TRUE(s.crowd.has_value());
  const sim::crowd::CrowdOptions defaults;
  const sim::crowd::CrowdOptions& o = s.crowd->options;
  EXPECT_EQ(o.pool_size, defaults.max_present);
  EXPECT_EQ(o.initial_present, defaults.initial_present);
  EXPECT_EQ(o.max_present, defaults.max_present);
  EXPECT_DOUBLE_EQ(o.arrivals_per_hour, defaults.arrivals_per_hour);
  EXPECT_EQ(o.visit.max_group_size, defaults.visit.max_group_size);
  EXPECT_DOUBLE_EQ(o.behaviours.curious, 0.0);
  EXPECT_DOUBLE_EQ(o.social.relaxation_s, defaults.social.relaxation_s);
  EXPECT_DOUBLE_EQ(o.body.mass_kg, defaults.body.mass_kg);
  EXPECT_EQ(s.crowd->entrance, s.world.places.at("visitor_spawn").area.value());
  EXPECT_EQ(s.crowd->exit, s.world.places.at("visitor_exit").area.value());
  EXPECT_TRUE(s.crowd->roam_area.empty());
  ASSERT_EQ(s.crowd->attractions.size(), 3u);  // by name
  EXPECT_EQ(s.crowd->attractions[0].name, "showcase");
  EXPECT_EQ(s.crowd->attractions[1].name, "station_a");
  EXPECT_DOUBLE_EQ(s.crowd->attractions[1].weight, 2.5);
  EXPECT_EQ(s.crowd->attractions[2].name, "station_b");
  EXPECT_EQ(s.crowd->material, "visitor");
}

// Confirms that entrance, exit and roam area may be inline polygons.
TEST(CrowdConfigTest, AreasMayBeInlinePolygons) {
  const Scenario s = LoadScenarioFile(
      WriteScenario(ScenarioWith("crowd:\n"
                                 "  entrance: [[-7, -7], [-6, -7], [-6, -6]]\n"
                                 "  exit: [[6, 6], [7, 6], [7, 7], [6, 7]]\n"
                                 "  roam_area: [[-7, -7], [7, -7], [7, 7], [-7, 7]]\n")));
  ASSERT_TRUE(s.crowd.has_value());
  EXPECT_EQ(s.crowd->entrance, (core::Polygon2{{-7, -7}, {-6, -7}, {-6, -6}}));
  EXPECT_EQ(s.crowd->exit.size(), 4u);
  EXPECT_EQ(s.crowd->roam_area[2], Eigen::Vector2d(7, 7));
}

// Confirms that the pool defaults to max_present, or to present when that is
// larger, and max_present to a pool that is given.
TEST(CrowdConfigTest, PoolAndMaxPresentDefaultToEachOther) {
  const Scenario a =
      LoadScenarioFile(WriteScenario(ScenarioWith("crowd: {present: 20, max_present: 35}\n")));
  EXPECT_EQ(a.crowd->options.pool_size, 35);
  const Scenario b =
      LoadScenarioFile(WriteScenario(ScenarioWith("crowd: {present: 150, max_present: 35}\n")));
  EXPECT_EQ(b.crowd->options.pool_size, 150);
  EXPECT_EQ(b.crowd->options.initial_present, 150);
  const Scenario c = LoadScenarioFile(WriteScenario(ScenarioWith("crowd: {pool: 20}\n")));
  EXPECT_EQ(c.crowd->options.pool_size, 20);
  EXPECT_EQ(c.crowd->options.max_present, 20);
  const Scenario d = LoadScenarioFile(WriteScenario(ScenarioWith("crowd: {pool: 300}\n")));
  EXPECT_EQ(d.crowd->options.max_present, 300);
}

// Confirms that a group larger than the pool is one error (CrowdOptions'
// Validate() reports it at the pool); none when no groups arrive.
TEST(CrowdConfigTest, ReportsGroupsLargerThanThePool) {
  const std::string text = ScenarioWith(
      "crowd:\n"
      "  pool: 3\n"
      "  max_present: 3\n"
      "  visit: {min_group_size: 2, max_group_size: 4}\n");
  ExpectCrowdError(text, "pool: 3", "crowd.pool", "max_group_size");
  ExpectCrowdError(ScenarioWith("crowd:\n  pool: 4\n  max_present: 4\n"), "pool: 4", "crowd.pool",
                   "max_group_size");
  const Scenario alone = LoadScenarioFile(WriteScenario(
      ScenarioWith("crowd: {pool: 3, max_present: 3, visit: {group_fraction: 0}}\n")));
  EXPECT_EQ(alone.crowd->options.pool_size, 3);
}

// Confirms that entrances and exits must be places of the world with an area on the floor.
TEST(CrowdConfigTest, ReportsBadEntranceAndExitPlaces) {
  ExpectCrowdError(ScenarioWith("crowd:\n  entrance: nowhere\n"), "entrance: nowhere",
                   "crowd.entrance", "no place 'nowhere'");
  ExpectCrowdError(ScenarioWith("crowd:\n  exit: centre\n"), "exit: centre", "crowd.exit",
                   "no area");
  ExpectCrowdError(ScenarioWith("crowd:\n  exit: beyond\n"), "exit: beyond", "crowd.exit",
                   "off the floor");
  ExpectCrowdError(ScenarioWith("crowd:\n  roam_area: station_a\n"), "roam_area: station_a",
                   "crowd.roam_area", "no area");
  ExpectCrowdError(ScenarioWith("crowd:\n  roam_area: [[0, 0], [12, 0], [0, 5]]\n"),
                   "roam_area:", "crowd.roam_area", "off the floor");
  ExpectCrowdError(ScenarioWith("crowd:\n  entrance: [[0, 0], [2, 0]]\n"),
                   "entrance:", "crowd.entrance", "at least 3");
  ExpectCrowdError(ScenarioWith("crowd:\n  exit: [[0, 0], [2, 0], [x, 1]]\n"),
                   "exit:", "crowd.exit[2][0]", "number");
  // The default entrance, missing from the world: reported at the block.
  std::string world = kWorld;
  world.replace(world.find("visitor_spawn"), 13, "front_door");
  const std::string text = ScenarioWith("crowd:\n  present: 5\n");
  const std::string path = WriteScenario(text, world);
  const Diagnostic d = OnlyError(path);
  EXPECT_EQ(d.line, LineOf(text, "crowd:"));
  EXPECT_EQ(d.key_path, "crowd.entrance");
  EXPECT_TRUE(Contains(d.message, "visitor_spawn"));
}

// Confirms that behaviour fractions must each be in [0, 1] and sum to at most 1.
TEST(CrowdConfigTest, ReportsBadBehaviourFractions) {
  ExpectCrowdError(ScenarioWith("crowd:\n  behaviours:\n    curious: 1.5\n"), "curious: 1.5",
                   "crowd.behaviours.curious", "curious");
  ExpectCrowdError(ScenarioWith("crowd:\n  behaviours:\n    pushing: -0.1\n"), "pushing: -0.1",
                   "crowd.behaviours.pushing", "pushing");
  const std::string text = ScenarioWith(
      "crowd:\n"
      "  behaviours:\n"
      "    curious: 0.5\n"
      "    crowding: 0.4\n"
      "    blocking: 0.3\n");
  const Diagnostic d = OnlyError(WriteScenario(text));
  EXPECT_TRUE(d.key_path.starts_with("crowd.behaviours")) << d.ToString();
  EXPECT_GE(d.line, LineOf(text, "behaviours:"));
  EXPECT_LE(d.line, LineOf(text, "blocking: 0.3"));
}

// Confirms that attractions must name stations of the world, each once.
TEST(CrowdConfigTest, ReportsBadAttractions) {
  const std::string missing = ScenarioWith("crowd:\n  attractions: [station_a, station_zz]\n");
  ExpectCrowdError(missing, "attractions:", "crowd.attractions[1]", "no place 'station_zz'");
  const std::string plain = ScenarioWith("crowd:\n  attractions: [centre]\n");
  ExpectCrowdError(plain, "attractions:", "crowd.attractions[0]", "not a station");
  const std::string twice = ScenarioWith("crowd:\n  attractions: [station_a, station_a]\n");
  ExpectCrowdError(twice, "attractions:", "crowd.attractions[1]", "twice");
  const std::string not_list = ScenarioWith("crowd:\n  attractions: station_a\n");
  ExpectCrowdError(not_list, "attractions:", "crowd.attractions", "list");
}

// Confirms that unknown keys of the block and its sections are errors.
TEST(CrowdConfigTest, ReportsUnknownKeys) {
  ExpectCrowdError(ScenarioWith("crowd:\n  poole: 3\n"), "poole", "crowd.poole", "unknown");
  ExpectCrowdError(ScenarioWith("crowd:\n  visit:\n    dwell_s: 3\n"), "dwell_s",
                   "crowd.visit.dwell_s", "unknown");
  ExpectCrowdError(ScenarioWith("crowd:\n  social_force: {tau: 0.5}\n"), "tau",
                   "crowd.social_force.tau", "unknown");
}

// Confirms that counts and options out of range are reported at their key
// with their Validate() message.
TEST(CrowdConfigTest, ReportsOutOfRangeOptionsAtTheirKey) {
  ExpectCrowdError(ScenarioWith("crowd:\n  pool: 10\n  present: 11\n"), "present: 11",
                   "crowd.present", "present");
  ExpectCrowdError(ScenarioWith("crowd:\n  visit: {dwell_mean_s: -1}\n"), "dwell_mean_s",
                   "crowd.visit.dwell_mean_s", "dwell_mean_s");
  ExpectCrowdError(ScenarioWith("crowd:\n  body: {mass_kg: 0}\n"), "mass_kg", "crowd.body.mass_kg",
                   "mass_kg");
  ExpectCrowdError(ScenarioWith("crowd:\n  social_force: {anisotropy: 2}\n"), "anisotropy",
                   "crowd.social_force.anisotropy", "anisotropy");
  ExpectCrowdError(ScenarioWith("crowd:\n  watch_spots: 1.5\n"), "watch_spots", "crowd.watch_spots",
                   "integer");
  ExpectCrowdError(ScenarioWith("crowd: {}\noutputs: {people_rate_hz: -1}\n"), "people_rate_hz",
                   "outputs.people_rate_hz", "people_rate_hz");
}

// Confirms that the people's material must exist after the scenario's materials are merged.
TEST(CrowdConfigTest, ReportsAnUnknownMaterial) {
  ExpectCrowdError(ScenarioWith("crowd:\n  material: plush\n"), "material: plush", "crowd.material",
                   "unknown material 'plush'");
  std::string text = ScenarioWith("crowd: {}\n");
  text.replace(text.find("  visitor:\n"), 11, "  cloth:\n");  // no `visitor` material
  ExpectCrowdError(text, "crowd:", "crowd.material", "unknown material 'visitor'");
}

// Confirms that with a crowd no body, group member or robot may take an id of its people.
TEST(CrowdConfigTest, ReportsIdsThatCollideWithThePeople) {
  const std::string body = ScenarioWith(
      "crowd: {}\n"
      "bodies:\n"
      "  - id: visitor_cart\n"
      "    shape: {type: sphere, radius: 0.2}\n"
      "    mass_kg: 5\n"
      "    material: skin\n"
      "    pose: [0, 1, 0]\n");
  ExpectCrowdError(body, "id: visitor_cart", "bodies[0].id", "visitor_001");
  const std::string group = ScenarioWith(
      "crowd: {}\n"
      "groups:\n"
      "  - id: visitor\n"
      "    count: 2\n"
      "    shape: {type: sphere, radius: 0.2}\n"
      "    mass_kg: 5\n"
      "    material: skin\n"
      "    area: hall\n");
  ExpectCrowdError(group, "id: visitor", "groups[0].id", "visitor_000");
  // Without a crowd the same group is fine.
  std::string no_crowd = group;
  no_crowd.erase(no_crowd.find("crowd: {}\n"), 10);
  EXPECT_EQ(LoadScenarioFile(WriteScenario(no_crowd)).bodies.size(), 2u);
}

// Confirms that stations read their attraction (default 1) and that a negative
// or non-numeric attraction, or one on a place that is not a station, is an error.
TEST(CrowdConfigTest, WorldStationsReadTheirAttraction) {
  const fs::path dir = TestDir();
  const sim::WorldDescription w = LoadWorldFile(WriteFile(dir, "world.yaml", kWorld));
  EXPECT_DOUBLE_EQ(w.places.at("station_a").attraction, 2.5);
  EXPECT_DOUBLE_EQ(w.places.at("station_b").attraction, 1.0);
  EXPECT_DOUBLE_EQ(w.places.at("station_closed").attraction, 0.0);
  EXPECT_DOUBLE_EQ(w.places.at("showcase").attraction, 0.5);
  EXPECT_DOUBLE_EQ(w.places.at("dock_1").attraction, 1.0);

  // Replaces `from` by `to` and expects one error at `key` on the line of `marker`.
  const auto expect_error = [&](const std::string& from, const std::string& to,
                                const std::string& marker, const std::string& key,
                                const std::string& part) {
    SCOPED_TRACE(to);
    std::string text = kWorld;
    text.replace(text.find(from), from.size(), to);
    const std::string path = WriteFile(dir, "bad.yaml", text);
    std::vector<Diagnostic> diagnostics;
    try {
      LoadWorldFile(path);
      ADD_FAILURE() << "LoadWorldFile accepted " << to;
    } catch (const InputError& e) {
      diagnostics = e.diagnostics();
    }
    ASSERT_EQ(diagnostics.size(), 1u);
    EXPECT_EQ(diagnostics[0].file, path);
    EXPECT_EQ(diagnostics[0].line, LineOf(text, marker));
    EXPECT_EQ(diagnostics[0].key_path, key);
    EXPECT_TRUE(Contains(diagnostics[0].message, part));
    EXPECT_EQ(ValidateFile(path).size(), 1u);
  };
  expect_error("attraction: 2.5", "attraction: -1", "attraction: -1", "places.station_a.attraction",
               ">= 0");
  expect_error("attraction: 2.5", "attraction: lots", "attraction: lots",
               "places.station_a.attraction", "expected a number");
  expect_error("pose: [0, 0, 0]\n", "pose: [0, 0, 0]\n    attraction: 2\n", "attraction: 2\n",
               "places.centre.attraction", "only a station");
}

// Confirms that the shipped expo hall's stations draw visitors, the robot arena most.
TEST(CrowdConfigTest, ExpoHallStationsHaveAttractions) {
  const sim::WorldDescription w =
      LoadWorldFile(std::string(PAVILION_SOURCE_DIR) + "/worlds/expo_hall/world.yaml");
  double most = 0.0;
  std::string favourite;
  for (const auto& [name, place] : w.places) {
    if (!name.starts_with("station_")) continue;
    EXPECT_GT(place.attraction, 0.0) << name;
    if (place.attraction > most) {
      most = place.attraction;
      favourite = name;
    }
  }
  EXPECT_EQ(favourite, "station_13");
}

}  // namespace
}  // namespace pavilion::scenarios
