#include "scenarios/batch/sweep_plan.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

// Plan file format name and version (docs/sweep.md).
constexpr const char* kPlanFormat = "pavilion-sweep-plan";
constexpr int kPlanVersion = 1;
// Digits of the seed in a run id (more when a seed needs them).
constexpr std::size_t kSeedDigits = 4;
// Digits of the cell index in a run id (more when the cell count needs them).
constexpr std::size_t kCellDigits = 2;
// Longest value shown by PlanDifference.
constexpr std::size_t kMaxShownChars = 60;

std::uint64_t ParseSeed(const std::string& text, const std::string& whole) {
  if (text.empty() || text.size() > 19 ||
      !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); })) {
    throw std::invalid_argument("--seeds '" + whole + "': '" + text +
                                "' is not a non-negative integer (e.g. 1-20 or 1,4,9)");
  }
  return std::stoull(text);
}

std::string Padded(std::uint64_t number, std::size_t digits) {
  std::string text = std::to_string(number);
  if (text.size() < digits) text.insert(0, digits - text.size(), '0');
  return text;
}

std::string Shown(const Json& value) {
  std::string text = value.is_string() ? value.get<std::string>() : value.dump();
  if (text.size() > kMaxShownChars) text = text.substr(0, kMaxShownChars - 3) + "...";
  return text;
}

// Seeds of a plan.json "sweep" object, compactly, for messages.
std::string ShownSeeds(const Json& seeds) {
  std::vector<std::uint64_t> list;
  for (const auto& s : seeds) {
    if (!s.is_number_unsigned()) return Shown(seeds);
    list.push_back(s.get<std::uint64_t>());
  }
  return SeedsText(list);
}

void CheckGrid(const SweepSpec& spec) {
  std::set<std::string> keys;
  for (const std::string& s : spec.set) keys.insert(s.substr(0, s.find('=')));
  std::set<std::string> grid_keys;
  for (const GridAxis& axis : spec.grid) {
    if (axis.key == "seed") {
      throw std::invalid_argument("--grid seed=...: give the seeds with --seeds");
    }
    if (!grid_keys.insert(axis.key).second) {
      throw std::invalid_argument("--grid " + axis.key + " is given twice");
    }
    if (keys.count(axis.key) != 0) {
      throw std::invalid_argument("'" + axis.key + "' is in both --grid and --set");
    }
  }
}

}  // namespace

std::vector<std::uint64_t> ParseSeeds(const std::string& text) {
  if (text.empty()) throw std::invalid_argument("--seeds is empty (e.g. 1-20 or 1,4,9)");
  std::vector<std::uint64_t> seeds;
  std::set<std::uint64_t> seen;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    std::size_t end = text.find(',', begin);
    if (end == std::string::npos) end = text.size();
    const std::string part = text.substr(begin, end - begin);
    const std::size_t dash = part.find('-');
    const std::uint64_t first = ParseSeed(part.substr(0, dash), text);
    const std::uint64_t last =
        dash == std::string::npos ? first : ParseSeed(part.substr(dash + 1), text);
    if (last < first)
      throw std::invalid_argument("--seeds '" + text + "': '" + part + "' runs backwards");
    if (last - first >= kMaxSweepRuns || seeds.size() + (last - first) >= kMaxSweepRuns) {
      throw std::invalid_argument("--seeds '" + text + "': more than " +
                                  std::to_string(kMaxSweepRuns) + " seeds");
    }
    for (std::uint64_t s = first; s <= last; ++s) {
      if (!seen.insert(s).second) {
        throw std::invalid_argument("--seeds '" + text + "': seed " + std::to_string(s) +
                                    " is given twice");
      }
      seeds.push_back(s);
    }
    begin = end + 1;
  }
  return seeds;
}

GridAxis ParseGridAxis(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw std::invalid_argument("--grid '" + text + "': expected key.path=v1,v2,...");
  }
  GridAxis axis;
  axis.key = text.substr(0, eq);
  std::size_t begin = eq + 1;
  while (begin <= text.size()) {
    std::size_t end = text.find(',', begin);
    if (end == std::string::npos) end = text.size();
    const std::string value = text.substr(begin, end - begin);
    if (value.empty()) throw std::invalid_argument("--grid '" + text + "': an empty value");
    if (std::find(axis.values.begin(), axis.values.end(), value) != axis.values.end()) {
      throw std::invalid_argument("--grid '" + text + "': value '" + value + "' is given twice");
    }
    axis.values.push_back(value);
    begin = end + 1;
  }
  return axis;
}

SweepPlan MakeSweepPlan(const SweepSpec& spec, std::vector<std::string> arguments) {
  CheckGrid(spec);
  if (spec.seeds.empty()) throw std::invalid_argument("--seeds names no seed");
  std::size_t cell_count = 1;
  for (const GridAxis& axis : spec.grid) {
    cell_count *= axis.values.size();
    if (cell_count * spec.seeds.size() > kMaxSweepRuns) {
      throw std::invalid_argument("the sweep has more than " + std::to_string(kMaxSweepRuns) +
                                  " runs");
    }
  }
  SweepPlan plan;
  plan.spec = spec;
  plan.arguments = std::move(arguments);
  const std::size_t cell_digits = std::max(kCellDigits, std::to_string(cell_count - 1).size());
  const std::uint64_t max_seed = *std::max_element(spec.seeds.begin(), spec.seeds.end());
  const std::size_t seed_digits = std::max(kSeedDigits, std::to_string(max_seed).size());
  for (std::size_t c = 0; c < cell_count; ++c) {
    SweepCell cell;
    cell.id = std::string("c").append(Padded(c, cell_digits));
    std::size_t rest = c;  // mixed-radix digits, the last axis fastest
    std::vector<std::pair<std::string, std::string>> settings(spec.grid.size());
    for (std::size_t a = spec.grid.size(); a-- > 0;) {
      const auto& values = spec.grid[a].values;
      settings[a] = {spec.grid[a].key, values[rest % values.size()]};
      rest /= values.size();
    }
    cell.settings = settings;
    for (const std::uint64_t seed : spec.seeds) {
      SweepRun run;
      run.id = cell.id + "-s" + Padded(seed, seed_digits);
      run.cell = c;
      run.seed = seed;
      run.overrides = spec.set;
      for (const auto& [key, value] : settings) run.overrides.push_back(key + "=" + value);
      plan.runs.push_back(std::move(run));
    }
    plan.cells.push_back(std::move(cell));
  }
  return plan;
}

std::vector<std::string> RunArguments(const SweepPlan& plan, const SweepRun& run) {
  std::vector<std::string> args = {"run", plan.spec.scenario, "--seed", std::to_string(run.seed)};
  for (const std::string& o : run.overrides) {
    args.push_back("--set");
    args.push_back(o);
  }
  if (plan.spec.duration_s > 0) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", plan.spec.duration_s);
    args.push_back("--duration");
    args.push_back(text);
  }
  return args;
}

std::string ScenarioDigest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::uint64_t hash = 14695981039346656037ull;  // FNV-1a 64 offset basis and prime
  for (const unsigned char c : bytes) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  char text[32];
  std::snprintf(text, sizeof text, "fnv1a64:%016llx", static_cast<unsigned long long>(hash));
  return text;
}

Json SweepIdentity(const SweepPlan& plan) {
  const SweepSpec& s = plan.spec;
  Json grid = Json::array();
  for (const GridAxis& axis : s.grid) grid.push_back({{"key", axis.key}, {"values", axis.values}});
  return Json{{"scenario", s.scenario},
              {"scenario_digest", s.scenario_digest},
              {"seeds", s.seeds},
              {"grid", grid},
              {"set", s.set},
              {"duration_s", s.duration_s > 0 ? Json(s.duration_s) : Json(nullptr)}};
}

Json PlanToJson(const SweepPlan& plan) {
  Json cells = Json::array();
  for (std::size_t c = 0; c < plan.cells.size(); ++c) {
    Json settings = Json::object();
    for (const auto& [key, value] : plan.cells[c].settings) settings[key] = value;
    Json runs = Json::array();
    for (const SweepRun& r : plan.runs) {
      if (r.cell == c) runs.push_back(r.id);
    }
    cells.push_back({{"id", plan.cells[c].id}, {"settings", settings}, {"runs", runs}});
  }
  Json runs = Json::array();
  for (const SweepRun& r : plan.runs) {
    runs.push_back({{"id", r.id},
                    {"cell", plan.cells[r.cell].id},
                    {"seed", r.seed},
                    {"overrides", r.overrides},
                    {"out", "runs/" + r.id},
                    {"args", RunArguments(plan, r)}});
  }
  return Json{
      {"format", kPlanFormat},        {"version", kPlanVersion}, {"arguments", plan.arguments},
      {"sweep", SweepIdentity(plan)}, {"cells", cells},          {"runs", runs}};
}

std::string PlanDifference(const nlohmann::json& existing, const SweepPlan& plan) {
  if (!existing.is_object() || existing.value("format", "") != kPlanFormat ||
      !existing.contains("sweep") || !existing["sweep"].is_object()) {
    return "its plan.json is not a sweep plan";
  }
  const Json now = SweepIdentity(plan);
  for (const auto& [key, value] : now.items()) {
    const nlohmann::json before = existing["sweep"].value(key, nlohmann::json());
    if (before == nlohmann::json(value)) continue;
    if (key == "scenario_digest") return "the scenario file changed since the plan was written";
    const bool seeds = key == "seeds";
    return key + ": " + (seeds ? ShownSeeds(before) : Shown(before)) + " before, " +
           (seeds ? ShownSeeds(value) : Shown(value)) + " now";
  }
  return "";
}

std::string SeedsText(const std::vector<std::uint64_t>& seeds) {
  std::string text;
  for (std::size_t i = 0; i < seeds.size();) {
    std::size_t j = i;
    while (j + 1 < seeds.size() && seeds[j + 1] == seeds[j] + 1) ++j;
    if (!text.empty()) text += ",";
    text += std::to_string(seeds[i]);
    if (j > i) text.append(j == i + 1 ? "," : "-").append(std::to_string(seeds[j]));
    i = j + 1;
  }
  return text;
}

}  // namespace pavilion::scenarios
