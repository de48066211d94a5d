// The plan of a sweep: seeds and grid parsing, cells x seeds, run ids, and the
// check that a rerun is the same sweep.
#include "scenarios/batch/sweep_plan.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace pavilion::scenarios;

SweepSpec Spec() {
  SweepSpec spec;
  spec.scenario = "/data/scenarios/office_tour.yaml";
  spec.scenario_digest = "fnv1a64:0123456789abcdef";
  spec.seeds = {1, 2, 3};
  spec.grid = {ParseGridAxis("robots.0.route.max_speed_mps=0.4,0.6"),
               ParseGridAxis("physics.rate_hz=100,200,400")};
  spec.set = {"outputs.scan_log=false"};
  spec.duration_s = 5.0;
  return spec;
}

// Seeds: ranges, lists and both; bad text is refused with the reason.
TEST(SweepPlanTest, ParsesSeeds) {
  EXPECT_EQ(ParseSeeds("1-4"), (std::vector<std::uint64_t>{1, 2, 3, 4}));
  EXPECT_EQ(ParseSeeds("7"), (std::vector<std::uint64_t>{7}));
  EXPECT_EQ(ParseSeeds("1,4,9"), (std::vector<std::uint64_t>{1, 4, 9}));
  EXPECT_EQ(ParseSeeds("0-2,10-11"), (std::vector<std::uint64_t>{0, 1, 2, 10, 11}));
  for (const char* bad : {"", "5-1", "1,,2", "a", "-3", "1-", "1,1", "1-3,2", "1.5", "1-200000"}) {
    EXPECT_THROW(ParseSeeds(bad), std::invalid_argument) << bad;
  }
  EXPECT_EQ(SeedsText({1, 2, 3, 7, 9, 10}), "1-3,7,9,10");
}

// A grid axis: a key and distinct values.
TEST(SweepPlanTest, ParsesGridAxes) {
  const GridAxis axis = ParseGridAxis("groups.0.count=10,20,40");
  EXPECT_EQ(axis.key, "groups.0.count");
  EXPECT_EQ(axis.values, (std::vector<std::string>{"10", "20", "40"}));
  for (const char* bad : {"key", "=1,2", "key=", "key=1,,2", "key=1,1"}) {
    EXPECT_THROW(ParseGridAxis(bad), std::invalid_argument) << bad;
  }
}

// Cells are every combination, the first key slowest; runs are cells x seeds
// with ids c<cell>-s<seed> and the overrides --set first, then the cell's.
TEST(SweepPlanTest, MakesCellsTimesSeeds) {
  const SweepPlan plan = MakeSweepPlan(Spec(), {"sweep", "x.yaml"});
  ASSERT_EQ(plan.cells.size(), 6u);
  ASSERT_EQ(plan.runs.size(), 18u);
  EXPECT_EQ(plan.cells[0].id, "c00");
  EXPECT_EQ(plan.cells[1].settings[0].second, "0.4");
  EXPECT_EQ(plan.cells[1].settings[1].second, "200");
  EXPECT_EQ(plan.cells[3].settings[0].second, "0.6");
  EXPECT_EQ(plan.cells[3].settings[1].second, "100");
  EXPECT_EQ(plan.runs[4].id, "c01-s0002");
  EXPECT_EQ(plan.runs[4].seed, 2u);
  EXPECT_EQ(plan.runs[4].overrides,
            (std::vector<std::string>{"outputs.scan_log=false", "robots.0.route.max_speed_mps=0.4",
                                      "physics.rate_hz=200"}));
  EXPECT_EQ(RunArguments(plan, plan.runs[4]),
            (std::vector<std::string>{"run", "/data/scenarios/office_tour.yaml", "--seed", "2",
                                      "--set", "outputs.scan_log=false", "--set",
                                      "robots.0.route.max_speed_mps=0.4", "--set",
                                      "physics.rate_hz=200", "--duration", "5"}));
  const auto json = PlanToJson(plan);
  EXPECT_EQ(json["format"], "pavilion-sweep-plan");
  EXPECT_EQ(json["runs"].size(), 18u);
  EXPECT_EQ(json["runs"][4]["out"], "runs/c01-s0002");
  EXPECT_EQ(json["cells"][3]["settings"]["physics.rate_hz"], "100");
  EXPECT_EQ(json["arguments"][0], "sweep");
}

// Without a grid: one cell; ids widen for large seeds and many cells.
TEST(SweepPlanTest, IdsWidenWhenNeeded) {
  SweepSpec spec = Spec();
  spec.grid.clear();
  spec.seeds = {12345};
  SweepPlan plan = MakeSweepPlan(spec, {});
  ASSERT_EQ(plan.cells.size(), 1u);
  EXPECT_TRUE(plan.cells[0].settings.empty());
  EXPECT_EQ(plan.runs[0].id, "c00-s12345");
  spec.grid = {ParseGridAxis("a=1,2,3,4,5,6,7,8,9,10,11"), ParseGridAxis("b=1,2,3,4,5,6,7,8,9,10")};
  plan = MakeSweepPlan(spec, {});
  EXPECT_EQ(plan.runs.back().id, "c109-s12345");
  EXPECT_EQ(plan.runs.front().id, "c000-s12345");
}

// A grid key given twice, also in --set, or `seed` is bad usage.
TEST(SweepPlanTest, RefusesConflictingKeys) {
  SweepSpec spec = Spec();
  spec.grid.push_back(ParseGridAxis("physics.rate_hz=50"));
  EXPECT_THROW(MakeSweepPlan(spec, {}), std::invalid_argument);
  spec = Spec();
  spec.set.push_back("physics.rate_hz=100");
  EXPECT_THROW(MakeSweepPlan(spec, {}), std::invalid_argument);
  spec = Spec();
  spec.grid = {ParseGridAxis("seed=1,2")};
  EXPECT_THROW(MakeSweepPlan(spec, {}), std::invalid_argument);
}

// A rerun continues only the same sweep: --jobs and spelling may differ, the
// seeds, grid, overrides, duration and scenario file may not.
TEST(SweepPlanTest, PlanDifferenceNamesWhatChanged) {
  const SweepPlan plan = MakeSweepPlan(Spec(), {"sweep", "--jobs", "1"});
  const nlohmann::json written = nlohmann::json::parse(PlanToJson(plan).dump());
  EXPECT_EQ(PlanDifference(written, MakeSweepPlan(Spec(), {"sweep", "--jobs", "4"})), "");
  SweepSpec more = Spec();
  more.seeds = {1, 2, 3, 4, 5};
  EXPECT_EQ(PlanDifference(written, MakeSweepPlan(more, {})), "seeds: 1-3 before, 1-5 now");
  SweepSpec longer = Spec();
  longer.duration_s = 6.0;
  EXPECT_EQ(PlanDifference(written, MakeSweepPlan(longer, {})), "duration_s: 5.0 before, 6.0 now");
  SweepSpec edited = Spec();
  edited.scenario_digest = "fnv1a64:fedcba9876543210";
  EXPECT_NE(PlanDifference(written, MakeSweepPlan(edited, {})).find("scenario file changed"),
            std::string::npos);
  SweepSpec grid = Spec();
  grid.grid.pop_back();
  EXPECT_EQ(PlanDifference(written, MakeSweepPlan(grid, {})).rfind("grid: ", 0), 0u);
  EXPECT_NE(PlanDifference(nlohmann::json::object(), plan), "");
}

}  // namespace
