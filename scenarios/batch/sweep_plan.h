#pragma once

// The plan of a parameter sweep (`pavilion sweep`, docs/sweep.md): grid cells
// (every combination of the grid's values) times seeds, one `pavilion run` per
// pair. The plan is written to DIR/plan.json before any run starts, so that a
// rerun can check it is the same sweep and a cluster backend can run it later.

#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace pavilion::scenarios {

// One grid parameter: a scenario key (as `--set key=value`) and its values.
struct GridAxis {
  std::string key;
  std::vector<std::string> values;  // >= 1, distinct, in the order given
};

// What a sweep runs: the command's arguments, parsed.
struct SweepSpec {
  std::string scenario;              // scenario file, absolute and normalized
  std::string scenario_digest;       // ScenarioDigest() of the file
  std::vector<std::uint64_t> seeds;  // >= 1, distinct, in the order given
  std::vector<GridAxis> grid;        // empty: one cell
  std::vector<std::string> set;      // "key=value" for every run, before the grid's
  double duration_s = -1.0;          // simulated s; <= 0: the scenario's
};

// One grid cell: a value for each grid key.
struct SweepCell {
  std::string id;  // "c00", "c01", ... (zero-padded to the cell count)
  std::vector<std::pair<std::string, std::string>> settings;  // (key, value), grid order
};

// One run: a cell and a seed.
struct SweepRun {
  std::string id;  // "<cell id>-s<seed, 4+ digits>", e.g. "c01-s0003"
  std::size_t cell = 0;
  std::uint64_t seed = 0;
  std::vector<std::string> overrides;  // "key=value": the spec's `set`, then the cell's
};

struct SweepPlan {
  SweepSpec spec;
  std::vector<std::string> arguments;  // the command line that made it (without the program)
  std::vector<SweepCell> cells;        // the grid's first key varies slowest
  std::vector<SweepRun> runs;          // cell by cell, seeds in order
};

// Largest sweep accepted (cells x seeds).
inline constexpr std::size_t kMaxSweepRuns = 100000;

// "1-20", "3", "1,4,9", "1-5,10-12" -> the seeds. Throws std::invalid_argument
// (empty, not a non-negative integer, a reversed range, a repeated seed, too many).
std::vector<std::uint64_t> ParseSeeds(const std::string& text);

// "key=v1,v2,..." -> the axis. Throws std::invalid_argument.
GridAxis ParseGridAxis(const std::string& text);

// The cells and runs of a spec. Throws std::invalid_argument for a grid key
// given twice or also in `set`, a `seed` grid key, or more than kMaxSweepRuns runs.
SweepPlan MakeSweepPlan(const SweepSpec& spec, std::vector<std::string> arguments);

// The arguments of `pavilion run` for one run, without the program and without
// `--out` (the runner adds `--out DIR/runs/<id>.tmp`).
std::vector<std::string> RunArguments(const SweepPlan& plan, const SweepRun& run);

// A digest of a file's bytes (FNV-1a, 64 bit, hex): a rerun notices an edited
// scenario file. Throws std::runtime_error when unreadable.
std::string ScenarioDigest(const std::string& path);

// The plan as written to plan.json (docs/sweep.md).
nlohmann::ordered_json PlanToJson(const SweepPlan& plan);

// The part of plan.json that must match for a rerun to continue a sweep (the
// "sweep" object: scenario, digest, seeds, grid, set, duration); --jobs and the
// spelling of the command line may differ.
nlohmann::ordered_json SweepIdentity(const SweepPlan& plan);

// Empty when `existing` (a plan.json read back) is the same sweep as `plan`;
// else a short description of the first difference ("seeds: 1-4 before, 1-8 now").
std::string PlanDifference(const nlohmann::json& existing, const SweepPlan& plan);

// Seeds written compactly: {1,2,3,7} -> "1-3,7".
std::string SeedsText(const std::vector<std::uint64_t>& seeds);

}  // namespace pavilion::scenarios
