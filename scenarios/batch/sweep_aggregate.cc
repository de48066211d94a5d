#include "scenarios/batch/sweep_aggregate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <stdexcept>

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

constexpr const char* kResultsFormat = "pavilion-sweep-results";
constexpr int kResultsVersion = 1;
constexpr const char* kNoExpectationsNote =
    "no run wrote expectations.json (the scenario has no expect: block)";
// The continued fraction of the incomplete beta: relative tolerance, iteration
// cap (enough for a, b up to ~1e7), and the floor of Lentz's method.
constexpr double kBetaEpsilon = 1e-16;
constexpr int kBetaMaxIterations = 20000;
constexpr double kBetaTiny = 1e-300;
// Bisection of the t quantile: stop at this relative width.
constexpr double kQuantileRelativeWidth = 1e-15;
// The two-sided confidence of the reported interval.
constexpr double kIntervalQuantile = 0.975;

// The continued fraction of I_x(a, b) (modified Lentz; Numerical Recipes betacf).
double BetaContinuedFraction(double a, double b, double x) {
  const double qab = a + b;
  const double qap = a + 1.0;
  const double qam = a - 1.0;
  double c = 1.0;
  double d = 1.0 - qab * x / qap;
  if (std::fabs(d) < kBetaTiny) d = kBetaTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= kBetaMaxIterations; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kBetaTiny) d = kBetaTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kBetaTiny) c = kBetaTiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kBetaTiny) d = kBetaTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kBetaTiny) c = kBetaTiny;
    d = 1.0 / d;
    const double step = d * c;
    h *= step;
    if (std::fabs(step - 1.0) < kBetaEpsilon) break;
  }
  return h;
}

// P(T > t) for t >= 0: 0.5 I_{dof/(dof+t^2)}(dof/2, 1/2), accurate far in the tail.
double StudentTUpperTail(double t, double dof) {
  return 0.5 * RegularizedIncompleteBeta(0.5 * dof, 0.5, dof / (dof + t * t));
}

void Flatten(const nlohmann::json& node, const std::string& path,
             std::map<std::string, double>* out) {
  const auto child = [&path](const std::string& key) {
    return path.empty() ? key : path + "." + key;
  };
  if (node.is_number()) {
    const double v = node.get<double>();
    if (std::isfinite(v)) (*out)[path] = v;
  } else if (node.is_object()) {
    for (const auto& [key, value] : node.items()) Flatten(value, child(key), out);
  } else if (node.is_array()) {
    std::set<std::string> ids;
    for (const auto& e : node) {
      if (!e.is_object() || !e.contains("id")) break;
      const auto& id = e["id"];
      if (!id.is_string() && !id.is_number_integer()) break;
      ids.insert(id.is_string() ? id.get<std::string>() : id.dump());
    }
    const bool by_id = !node.empty() && ids.size() == node.size();
    for (std::size_t i = 0; i < node.size(); ++i) {
      const auto& e = node[i];
      std::string key = std::to_string(i);
      if (by_id) key = e["id"].is_string() ? e["id"].get<std::string>() : e["id"].dump();
      Flatten(e, child(key), out);
    }
  }
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(path.string() + ": not valid JSON (" + e.what() + ")");
  }
}

Json OptionalNumber(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

Json SummaryToJson(const MetricSummary& s) {
  Json ci = s.ci95_low ? Json::array({*s.ci95_low, *s.ci95_high}) : Json(nullptr);
  return Json{{"n", s.n},     {"mean", s.mean}, {"std", OptionalNumber(s.std)},
              {"min", s.min}, {"max", s.max},   {"ci95", ci}};
}

double Rate(int part, int whole) { return whole > 0 ? static_cast<double>(part) / whole : 0.0; }

Json CellExpectationsToJson(const CellAggregate& cell) {
  if (cell.runs_with_expectations == 0) return nullptr;
  Json by_name = Json::array();
  for (const ExpectationTally& t : cell.expectations) {
    by_name.push_back({{"name", t.name},
                       {"line", t.line},
                       {"pass", t.pass},
                       {"fail", t.fail},
                       {"missing", t.missing},
                       {"pass_rate", Rate(t.pass, t.pass + t.fail + t.missing)}});
  }
  return Json{{"runs", cell.runs_with_expectations},
              {"passed", cell.runs_passed},
              {"pass_rate", Rate(cell.runs_passed, cell.runs_with_expectations)},
              {"by_expectation", by_name}};
}

// Counts one run's expectations.json into its cell.
void TallyExpectations(const nlohmann::json& e, CellAggregate* cell) {
  ++cell->runs_with_expectations;
  if (e.value("passed", false) == true) ++cell->runs_passed;
  if (!e.contains("results") || !e["results"].is_array()) return;
  for (const auto& r : e["results"]) {
    if (!r.is_object()) continue;
    const std::string name = r.value("name", std::string("?"));
    const int line = r.contains("line") && r["line"].is_number_integer() ? r["line"].get<int>() : 0;
    auto it =
        std::find_if(cell->expectations.begin(), cell->expectations.end(),
                     [&](const ExpectationTally& t) { return t.name == name && t.line == line; });
    if (it == cell->expectations.end()) {
      cell->expectations.push_back({name, line, 0, 0, 0});
      it = cell->expectations.end() - 1;
    }
    const std::string status = r.value("status", std::string());
    if (status == "pass") {
      ++it->pass;
    } else if (status == "missing") {
      ++it->missing;
    } else {
      ++it->fail;
    }
  }
}

void SummarizeCell(CellAggregate* cell, const std::vector<const RunRecord*>& records) {
  std::set<std::string> names;
  for (const RunRecord* r : records) {
    for (const auto& [name, value] : r->metrics) names.insert(name);
  }
  for (const std::string& name : names) {
    std::vector<double>& all = cell->values[name];
    std::vector<double> present;
    for (const RunRecord* r : records) {
      const auto it = r->metrics.find(name);
      all.push_back(it == r->metrics.end() ? std::numeric_limits<double>::quiet_NaN() : it->second);
      if (it != r->metrics.end()) present.push_back(it->second);
    }
    cell->metrics[name] = Summarize(present);
  }
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string CsvNumber(const std::optional<double>& v) {
  if (!v) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", *v);
  return text;
}

}  // namespace

double RegularizedIncompleteBeta(double a, double b, double x) {
  if (!(a > 0.0) || !(b > 0.0) || !(x >= 0.0 && x <= 1.0)) {
    throw std::invalid_argument("incomplete beta: need a, b > 0 and x in [0, 1]");
  }
  if (x == 0.0 || x == 1.0) return x;
  const double front = std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) +
                                a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * BetaContinuedFraction(a, b, x) / a;
  return 1.0 - front * BetaContinuedFraction(b, a, 1.0 - x) / b;
}

double StudentTCdf(double t, double dof) {
  if (!(dof > 0.0) || std::isnan(t)) throw std::invalid_argument("Student t: need dof > 0");
  if (std::isinf(t)) return t > 0 ? 1.0 : 0.0;
  const double tail = StudentTUpperTail(std::fabs(t), dof);
  return t >= 0 ? 1.0 - tail : tail;
}

double StudentTQuantile(double p, double dof) {
  if (!(p > 0.0 && p < 1.0) || !(dof > 0.0) || !std::isfinite(dof)) {
    throw std::invalid_argument("Student t quantile: need p in (0, 1) and a finite dof > 0");
  }
  if (p == 0.5) return 0.0;
  if (p < 0.5) return -StudentTQuantile(1.0 - p, dof);
  const double tail = 1.0 - p;  // solve P(T > t) = tail; it falls as t grows
  double lo = 0.0;
  double hi = 1.0;
  while (StudentTUpperTail(hi, dof) > tail) {
    lo = hi;
    hi *= 2.0;
    if (!std::isfinite(hi)) return hi;
  }
  while (hi - lo > kQuantileRelativeWidth * hi) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (StudentTUpperTail(mid, dof) > tail ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

MetricSummary Summarize(const std::vector<double>& values) {
  if (values.empty()) throw std::invalid_argument("Summarize: no values");
  MetricSummary s;
  s.n = values.size();
  double sum = 0.0;
  for (double v : values) sum += v;
  s.mean = sum / static_cast<double>(s.n);
  s.min = *std::min_element(values.begin(), values.end());
  s.max = *std::max_element(values.begin(), values.end());
  if (s.n < 2) return s;
  double squares = 0.0;
  for (double v : values) squares += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(squares / static_cast<double>(s.n - 1));
  const double half = StudentTQuantile(kIntervalQuantile, static_cast<double>(s.n - 1)) * *s.std /
                      std::sqrt(static_cast<double>(s.n));
  s.ci95_low = s.mean - half;
  s.ci95_high = s.mean + half;
  return s;
}

std::map<std::string, double> FlattenMetrics(const nlohmann::json& metrics) {
  std::map<std::string, double> out;
  Flatten(metrics, "", &out);
  out.erase("schema_version");
  out.erase("seed");
  return out;
}

RunRecord ReadRunFolder(const std::string& folder, std::size_t run_index) {
  const std::filesystem::path dir(folder);
  RunRecord record;
  record.run = run_index;
  record.metrics = FlattenMetrics(ReadJsonFile(dir / "metrics.json"));
  if (std::filesystem::exists(dir / "expectations.json")) {
    record.expectations = ReadJsonFile(dir / "expectations.json");
  }
  return record;
}

SweepAggregate AggregateRuns(const SweepPlan& plan, const std::vector<RunRecord>& runs) {
  std::vector<const RunRecord*> sorted;
  for (const RunRecord& r : runs) sorted.push_back(&r);
  std::sort(sorted.begin(), sorted.end(),
            [](const RunRecord* a, const RunRecord* b) { return a->run < b->run; });
  SweepAggregate aggregate;
  aggregate.cells.resize(plan.cells.size());
  std::set<std::string> names;
  for (std::size_t c = 0; c < plan.cells.size(); ++c) {
    CellAggregate& cell = aggregate.cells[c];
    std::vector<const RunRecord*> records;
    for (const RunRecord* r : sorted) {
      if (plan.runs.at(r->run).cell != c) continue;
      records.push_back(r);
      cell.runs.push_back(r->run);
      if (r->expectations) TallyExpectations(*r->expectations, &cell);
    }
    SummarizeCell(&cell, records);
    for (const auto& [name, summary] : cell.metrics) names.insert(name);
    aggregate.any_expectations = aggregate.any_expectations || cell.runs_with_expectations > 0;
  }
  aggregate.metric_names.assign(names.begin(), names.end());
  return aggregate;
}

Json AggregateToJson(const SweepPlan& plan, const SweepAggregate& aggregate,
                     const SweepStatus& status) {
  Json cells = Json::array();
  for (std::size_t c = 0; c < plan.cells.size(); ++c) {
    const CellAggregate& cell = aggregate.cells[c];
    Json settings = Json::object();
    for (const auto& [key, value] : plan.cells[c].settings) settings[key] = value;
    Json run_ids = Json::array();
    for (std::size_t r : cell.runs) run_ids.push_back(plan.runs[r].id);
    Json metrics = Json::object();
    for (const auto& [name, summary] : cell.metrics) metrics[name] = SummaryToJson(summary);
    cells.push_back({{"id", plan.cells[c].id},
                     {"settings", settings},
                     {"runs", run_ids},
                     {"expectations", CellExpectationsToJson(cell)},
                     {"metrics", metrics}});
  }
  Json j = {{"format", kResultsFormat}, {"version", kResultsVersion}, {"plan", "plan.json"}};
  j["sweep"] = SweepIdentity(plan);
  j["runs"] = {{"planned", status.planned},
               {"finished", status.finished},
               {"failed", status.failed},
               {"not_run", status.not_run}};
  int with = 0;
  int passed = 0;
  for (const CellAggregate& cell : aggregate.cells) {
    with += cell.runs_with_expectations;
    passed += cell.runs_passed;
  }
  if (aggregate.any_expectations) {
    j["expectations"] = {{"runs", with}, {"passed", passed}, {"pass_rate", Rate(passed, with)}};
  } else {
    j["expectations"] = nullptr;
    j["expectations_note"] = kNoExpectationsNote;
  }
  j["cells"] = cells;
  return j;
}

std::string AggregateToCsv(const SweepPlan& plan, const SweepAggregate& aggregate) {
  std::string csv = "cell";
  const auto add = [&csv](const std::string& field) { csv.append(",").append(field); };
  for (const GridAxis& axis : plan.spec.grid) add(CsvField(axis.key));
  csv.append(",metric,n,mean,std,min,max,ci95_low,ci95_high\n");
  for (std::size_t c = 0; c < plan.cells.size(); ++c) {
    for (const auto& [name, s] : aggregate.cells[c].metrics) {
      csv.append(plan.cells[c].id);
      for (const auto& setting : plan.cells[c].settings) add(CsvField(setting.second));
      add(CsvField(name));
      add(std::to_string(s.n));
      for (const auto& v : {std::optional<double>(s.mean), s.std, std::optional<double>(s.min),
                            std::optional<double>(s.max), s.ci95_low, s.ci95_high}) {
        add(CsvNumber(v));
      }
      csv.append("\n");
    }
  }
  return csv;
}

}  // namespace pavilion::scenarios
