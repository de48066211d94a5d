#include "scenarios/realism/realism_comparison.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <utility>

#include "scenarios/datasets/carmen_log.h"
#include "scenarios/output/scan_log.h"

namespace pavilion::scenarios {
namespace {

constexpr double kMmPerM = 1000.0;

std::string Printf(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// Pads `text` on the left (right-aligned) or right to `width` characters.
std::string Pad(const std::string& text, std::size_t width, bool right_align = true) {
  if (text.size() >= width) return text;
  const std::string fill(width - text.size(), ' ');
  return right_align ? fill + text : text + fill;
}

std::string Mm(double metres) { return Printf("%.1f", metres * kMmPerM); }

std::string Ratio(double sim, double real) {
  return real > 0.0 ? Printf("%.2f", sim / real) : std::string("-");
}

std::string BinLabel(const ResidualBin& bin, bool last) {
  char text[64];
  std::snprintf(text, sizeof text, "[%g,%g%s m", bin.min_range_m, bin.max_range_m,
                last ? "]" : ")");
  return text;
}

// Per-log table columns (the name column widens for long names).
constexpr std::size_t kMinNameWidth = 20;
constexpr std::size_t kNumberWidth = 9;
constexpr std::size_t kCountWidth = 8;

std::string SummaryHeader(const std::vector<ResidualBin>& bins, std::size_t name_width) {
  std::string top = Pad("", name_width + 4 * kNumberWidth);
  std::string line = Pad("log", name_width, false) + Pad("scans", kNumberWidth) +
                     Pad("step mm", kNumberWidth) + Pad("no-ret", kNumberWidth) +
                     Pad("isolated", kNumberWidth);
  for (std::size_t b = 0; b < bins.size(); ++b) {
    top +=
        " | " + Pad(BinLabel(bins[b], b + 1 == bins.size()), kCountWidth + 2 * kNumberWidth, false);
    line +=
        " | " + Pad("n", kCountWidth) + Pad("med mm", kNumberWidth) + Pad("p90 mm", kNumberWidth);
  }
  return top + "\n" + line + "\n";
}

std::string SummaryRow(const std::string& name, std::size_t name_width, double step_m,
                       const ScanResidualStatistics& s) {
  std::string line = Pad(name, name_width, false) + Pad(std::to_string(s.scans), kNumberWidth) +
                     Pad(step_m > 0.0 ? Printf("%g", step_m * kMmPerM) : "-", kNumberWidth) +
                     Pad(Printf("%.4f", s.no_return_fraction), kNumberWidth) +
                     Pad(Printf("%.4f", s.isolated_fraction), kNumberWidth);
  for (const ResidualBin& bin : s.bins) {
    line += " | " + Pad(std::to_string(bin.count), kCountWidth) +
            Pad(Mm(bin.median_abs_m), kNumberWidth) + Pad(Mm(bin.p90_abs_m), kNumberWidth);
  }
  return line + "\n";
}

// Comparison table columns: a label, then per log real, sim, sim/real.
constexpr std::size_t kLabelWidth = 18;
constexpr std::size_t kCellWidth = 8;
constexpr std::size_t kRatioWidth = 6;

std::string ComparisonTable(const std::vector<LogStatistics>& real,
                            const SimulatedStatistics& sim) {
  std::string out = Pad("", kLabelWidth, false);
  std::string sub = Pad("", kLabelWidth, false);
  for (const LogStatistics& log : real) {
    out += " | " + Pad(log.name, 2 * kCellWidth + kRatioWidth, false);
    sub += " | " + Pad("real", kCellWidth) + Pad("sim", kCellWidth) + Pad("ratio", kRatioWidth);
  }
  out += "\n" + sub + "\n";
  // One row: a label, and per log the real value, the simulated value and
  // optionally their ratio.
  const auto row = [&](const std::string& label, auto real_of, auto sim_of, auto format,
                       bool ratio) {
    std::string line = Pad(label, kLabelWidth, false);
    for (std::size_t k = 0; k < real.size(); ++k) {
      const double r = real_of(real[k]);
      const double s = sim_of(sim.requantized[k], k);
      line += " | " + Pad(format(r), kCellWidth) + Pad(format(s), kCellWidth) +
              Pad(ratio ? Ratio(s, r) : "", kRatioWidth);
    }
    out += line + "\n";
  };
  const auto fraction = [](double v) { return Printf("%.4f", v); };
  const auto step_mm = [](double v) { return v > 0.0 ? Printf("%g", v * kMmPerM) : "-"; };
  row(
      "step mm", [](const LogStatistics& l) { return l.range_step.step_m; },
      [&](const ScanResidualStatistics&, std::size_t k) {
        return real[k].range_step.step_m > 0.0 ? real[k].range_step.step_m : sim.range_step.step_m;
      },
      step_mm, false);
  row(
      "no-return", [](const LogStatistics& l) { return l.residuals.no_return_fraction; },
      [](const ScanResidualStatistics& s, std::size_t) { return s.no_return_fraction; }, fraction,
      false);
  row(
      "isolated", [](const LogStatistics& l) { return l.residuals.isolated_fraction; },
      [](const ScanResidualStatistics& s, std::size_t) { return s.isolated_fraction; }, fraction,
      false);
  const std::size_t bins = real.empty() ? 0 : real.front().residuals.bins.size();
  for (std::size_t b = 0; b < bins; ++b) {
    const std::string label = BinLabel(real.front().residuals.bins[b], b + 1 == bins);
    const auto count = [](double v) { return Printf("%.0f", v); };
    row(
        label + " n",
        [b](const LogStatistics& l) { return static_cast<double>(l.residuals.bins[b].count); },
        [b](const ScanResidualStatistics& s, std::size_t) {
          return static_cast<double>(s.bins[b].count);
        },
        count, false);
    row(
        label + " med", [b](const LogStatistics& l) { return l.residuals.bins[b].median_abs_m; },
        [b](const ScanResidualStatistics& s, std::size_t) { return s.bins[b].median_abs_m; }, Mm,
        true);
    row(
        label + " p90", [b](const LogStatistics& l) { return l.residuals.bins[b].p90_abs_m; },
        [b](const ScanResidualStatistics& s, std::size_t) { return s.bins[b].p90_abs_m; }, Mm,
        true);
  }
  return out;
}

nlohmann::json BinJson(const ResidualBin& bin) {
  return {
      {"min_range_m", bin.min_range_m},   {"max_range_m", bin.max_range_m}, {"count", bin.count},
      {"median_abs_m", bin.median_abs_m}, {"p90_abs_m", bin.p90_abs_m},     {"rms_m", bin.rms_m}};
}

nlohmann::json StatisticsJson(const ScanResidualStatistics& s) {
  nlohmann::json bins = nlohmann::json::array();
  for (const ResidualBin& bin : s.bins) bins.push_back(BinJson(bin));
  return {{"scans", s.scans},
          {"readings", s.readings},
          {"no_returns", s.no_returns},
          {"isolated", s.isolated},
          {"no_return_fraction", s.no_return_fraction},
          {"isolated_fraction", s.isolated_fraction},
          {"runs", s.runs},
          {"run_readings", s.run_readings},
          {"bins", bins},
          {"all", BinJson(s.all)}};
}

// "…/intel-corrected.log.gz" -> "intel".
std::string ShortLogName(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  for (const std::string suffix : {".gz", ".log", "-corrected"}) {
    if (name.size() > suffix.size() && name.ends_with(suffix)) {
      name.resize(name.size() - suffix.size());
    }
  }
  return name;
}

nlohmann::json StepJson(const RangeStepEstimate& step) {
  return {{"step_m", step.step_m},
          {"on_grid_fraction", step.on_grid_fraction},
          {"valid_readings", step.valid_readings}};
}

}  // namespace

LogStatistics ComputeLogStatistics(const std::string& name, std::span<const core::LaserScan> scans,
                                   const ScanResidualOptions& options) {
  int beams = 0;
  for (const core::LaserScan& s : scans)
    beams = std::max(beams, static_cast<int>(s.readings.size()));
  return {name, beams, DetectRangeStep(scans), ComputeScanResiduals(scans, options)};
}

LogStatistics LoadCarmenLogStatistics(const std::string& path, const ScanResidualOptions& options) {
  CarmenLog log = ReadCarmenLog(path);
  if (log.scans.empty()) throw std::runtime_error(path + ": no FLASER scan (not a CARMEN log?)");
  SetCarmenAngleStep(DecideCarmenAngleStep(log).step, &log);
  std::vector<core::LaserScan> scans;
  scans.reserve(log.scans.size());
  for (CarmenScan& s : log.scans) scans.push_back(std::move(s.scan));
  return ComputeLogStatistics(ShortLogName(path), scans, options);
}

NamedScans LoadScanLogScans(const std::string& path) {
  ScanLog log = ReadScanLog(path);
  if (log.records.empty()) throw std::runtime_error(path + ": the scan log holds no scan");
  NamedScans out;
  out.name = path;
  out.scans.reserve(log.records.size());
  for (ScanLogRecord& r : log.records) out.scans.push_back(std::move(r.scan));
  return out;
}

RealismComparison CompareResiduals(const std::vector<LogStatistics>& real,
                                   const std::vector<NamedScans>& simulated,
                                   const ScanResidualOptions& options) {
  options.Validate();
  RealismComparison out;
  out.real = real;
  ScanResidualOptions raw_options = options;
  raw_options.requantize_step_m = 0.0;
  for (const NamedScans& scans : simulated) {
    SimulatedStatistics sim;
    sim.name = scans.name;
    sim.range_step = DetectRangeStep(scans.scans);
    sim.raw = ComputeScanResiduals(scans.scans, raw_options);
    int beams = 0;
    for (const core::LaserScan& s : scans.scans) {
      beams = std::max(beams, static_cast<int>(s.readings.size()));
    }
    // Each distinct (step, thinning) once.
    std::map<std::pair<double, int>, ScanResidualStatistics> by_key;
    for (const LogStatistics& log : real) {
      const double step_m = std::max(log.range_step.step_m, 0.0);
      const int keep =
          log.beams > 0 ? std::max(1, static_cast<int>(std::lround(double(beams) / log.beams))) : 1;
      auto it = by_key.find({step_m, keep});
      if (it == by_key.end()) {
        ScanResidualOptions matched = raw_options;
        matched.requantize_step_m = step_m;
        matched.keep_every = keep;
        it =
            by_key.emplace(std::make_pair(step_m, keep), ComputeScanResiduals(scans.scans, matched))
                .first;
      }
      sim.requantized.push_back(it->second);
    }
    out.simulated.push_back(std::move(sim));
  }
  return out;
}

std::string FormatRealismReport(const RealismComparison& comparison) {
  std::vector<ResidualBin> bins;
  if (!comparison.real.empty()) bins = comparison.real.front().residuals.bins;
  if (bins.empty() && !comparison.simulated.empty()) bins = comparison.simulated.front().raw.bins;
  std::string out = "Residuals of long walls, |perpendicular residual| to a TLS line per run\n";
  std::size_t name_width = kMinNameWidth;
  for (const LogStatistics& log : comparison.real) {
    name_width = std::max(name_width, log.name.size() + 2);
  }
  for (const SimulatedStatistics& sim : comparison.simulated) {
    name_width = std::max(name_width, sim.name.size() + 8);
  }
  out += SummaryHeader(bins, name_width);
  for (const LogStatistics& log : comparison.real) {
    out += SummaryRow(log.name, name_width, log.range_step.step_m, log.residuals);
  }
  for (const SimulatedStatistics& sim : comparison.simulated) {
    out += SummaryRow(sim.name + " (raw)", name_width, sim.range_step.step_m, sim.raw);
  }
  for (const SimulatedStatistics& sim : comparison.simulated) {
    if (comparison.real.empty()) break;
    out += "\n" + sim.name +
           ": requantized to each log's range step and thinned to its beam spacing; ratio = "
           "sim / real\n";
    out += ComparisonTable(comparison.real, sim);
  }
  return out;
}

nlohmann::json RealismReportJson(const RealismComparison& comparison) {
  nlohmann::json real = nlohmann::json::array();
  for (const LogStatistics& log : comparison.real) {
    real.push_back({{"name", log.name},
                    {"range_step", StepJson(log.range_step)},
                    {"residuals", StatisticsJson(log.residuals)}});
  }
  nlohmann::json simulated = nlohmann::json::array();
  for (const SimulatedStatistics& sim : comparison.simulated) {
    nlohmann::json requantized = nlohmann::json::array();
    for (std::size_t k = 0; k < sim.requantized.size() && k < comparison.real.size(); ++k) {
      const LogStatistics& log = comparison.real[k];
      nlohmann::json ratios = nlohmann::json::array();
      for (std::size_t b = 0; b < sim.requantized[k].bins.size() && b < log.residuals.bins.size();
           ++b) {
        const ResidualBin& s = sim.requantized[k].bins[b];
        const ResidualBin& r = log.residuals.bins[b];
        ratios.push_back(
            {{"median", r.median_abs_m > 0.0 ? nlohmann::json(s.median_abs_m / r.median_abs_m)
                                             : nlohmann::json(nullptr)},
             {"p90", r.p90_abs_m > 0.0 ? nlohmann::json(s.p90_abs_m / r.p90_abs_m)
                                       : nlohmann::json(nullptr)}});
      }
      requantized.push_back({{"log", log.name},
                             {"requantize_step_m", log.range_step.step_m},
                             {"residuals", StatisticsJson(sim.requantized[k])},
                             {"ratio_sim_over_real", ratios}});
    }
    simulated.push_back({{"name", sim.name},
                         {"range_step", StepJson(sim.range_step)},
                         {"raw", StatisticsJson(sim.raw)},
                         {"requantized", requantized}});
  }
  return {{"real", real}, {"simulated", simulated}};
}

}  // namespace pavilion::scenarios
