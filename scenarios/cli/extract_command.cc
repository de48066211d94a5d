#include "scenarios/cli/extract_command.h"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/features/beacon_extraction.h"
#include "core/features/line_extraction.h"
#include "core/features/scene_description.h"
#include "core/features/split_and_merge.h"
#include "core/geometry/planar_section.h"
#include "core/math/chi_square.h"
#include "core/types/image.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/datasets/carmen_log.h"
#include "scenarios/output/png.h"
#include "scenarios/output/raster.h"
#include "scenarios/output/scan_log.h"
#include "scenarios/scoring/extraction_scoring.h"
#include "sim/world/world.h"

namespace pavilion::cli {
namespace {

using scenarios::Rgb;

// Additive covariance floor for real CARMEN logs (§2.2.1.3): the logged SICK
// scanners have range errors correlated along a wall (calibration, surface,
// incidence) that white per-reading noise does not model. Assumed values, of
// the order of the thesis' repeatability figures (§3.2.4: sigma_r = 5 mm,
// sigma_alpha = 0.2 deg).
constexpr double kCarmenRangeSigmaM = 0.01;
constexpr double kCarmenRSigmaFloorM = 0.005;
constexpr double kCarmenAlphaSigmaFloorRad = 0.2 * std::numbers::pi / 180.0;

// The split-and-merge baseline's thresholds in units of the preset's sigma_rho,
// as core/features/split_and_merge.h motivates its SICK LMS 200 defaults: split
// and merge at 5 sigma, gaps from 3 sigma.
constexpr double kSplitThresholdSigmas = 5.0;
constexpr double kMergeThresholdSigmas = 5.0;
constexpr double kGapMinSigmas = 3.0;

// Probability of the endpoints' error ellipses; chi^2(2) quantile 5.991.
constexpr double kEllipseProbability = 0.95;

// Picture: the longer side of the plot and its blank margin, pixels.
constexpr int kImageLongSidePx = 1000;
constexpr int kImageMarginPx = 30;
constexpr double kPointRadiusPx = 1.8;
constexpr double kSegmentWidthPx = 4.0;
constexpr double kEndpointRadiusPx = 2.5;
constexpr double kGridSpacingM = 1.0;  // light grid lines every metre
// Text: caption and scene description above the plot, labels on it.
constexpr int kTextScale = 2;           // font pixels are 2 x 2 image pixels
constexpr int kTextMarginPx = 12;       // around the text band
constexpr int kCaptionGapPx = 10;       // between the caption and the scene description
constexpr double kLabelOffsetPx = 14;   // segment numbers stand this far behind the segment
constexpr double kSymbolOffsetPx = 26;  // scene symbols this far towards the sensor

const char kScanLogMagic[] = "PAVSCAN1";

// One scan to extract from, with a label for the listing.
struct LabelledScan {
  std::string label;
  core::LaserScan scan;
  core::LaserScanTruth truth;  // scans.bin only; empty when not logged
};

struct LoadedLog {
  std::string description;               // one line: format, scans, angular step
  bool real = false;                     // a CARMEN log (real sensor: covariance floor on)
  std::vector<std::string> element_ids;  // scans.bin: element ids in truth index order
  std::vector<LabelledScan> scans;
};

bool HasScanLogMagic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  char magic[sizeof kScanLogMagic - 1] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == static_cast<std::streamsize>(sizeof magic) &&
         std::equal(magic, magic + sizeof magic, kScanLogMagic);
}

LoadedLog LoadCarmen(const ExtractArgs& args) {
  if (!args.robot.empty() || !args.sensor.empty()) {
    throw std::runtime_error("--robot and --sensor apply to Pavilion scan logs only, not to '" +
                             args.log + "'");
  }
  scenarios::CarmenLog log = scenarios::ReadCarmenLog(args.log);
  const scenarios::CarmenAngleStepDecision decision = scenarios::DecideCarmenAngleStep(log);
  scenarios::SetCarmenAngleStep(decision.step, &log);
  LoadedLog out;
  out.real = true;
  out.description =
      "CARMEN log " + args.log + ": " + std::to_string(log.scans.size()) + " scans, angular step " +
      (decision.step == scenarios::CarmenAngleStep::kFovOverN ? "180/n" : "180/(n-1)") +
      " (docs/carmen_logs.md)";
  out.scans.reserve(log.scans.size());
  for (scenarios::CarmenScan& s : log.scans) {
    char label[64];
    std::snprintf(label, sizeof label, "line %d, t = %.3f s", s.line, s.stamp_s);
    out.scans.push_back({label, std::move(s.scan), {}});
  }
  return out;
}

LoadedLog LoadScanLog(const ExtractArgs& args) {
  scenarios::ScanLog log = scenarios::ReadScanLog(args.log);
  LoadedLog out;
  out.element_ids = std::move(log.element_ids);
  for (scenarios::ScanLogRecord& r : log.records) {
    if (!args.robot.empty() && r.robot != args.robot) continue;
    if (!args.sensor.empty() && r.scan.sensor_id != args.sensor) continue;
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.3f", r.scan.stamp_s);
    out.scans.push_back({r.robot + "/" + r.scan.sensor_id + ", t = " + stamp + " s",
                         std::move(r.scan), std::move(r.truth)});
  }
  out.description = "Pavilion scan log " + args.log + ": " + std::to_string(out.scans.size()) +
                    " of " + std::to_string(log.records.size()) + " scans";
  if (!args.robot.empty()) out.description += ", robot " + args.robot;
  if (!args.sensor.empty()) out.description += ", sensor " + args.sensor;
  if (out.scans.empty()) {
    throw std::runtime_error(args.log + ": no scans" +
                             (args.robot.empty() && args.sensor.empty()
                                  ? std::string()
                                  : " of the given --robot/--sensor"));
  }
  return out;
}

const std::map<std::string, core::LineExtractionOptions (*)()>& Presets() {
  static const std::map<std::string, core::LineExtractionOptions (*)()> presets = {
      {"sick_lms200", &core::LineExtractionOptions::SickLms200},
      {"sick_pls100", &core::LineExtractionOptions::SickPls100},
      {"accurange3000", &core::LineExtractionOptions::AccuRange3000},
      {"leuze_rs3", &core::LineExtractionOptions::LeuzeRs3},
  };
  return presets;
}

std::vector<std::string> PresetNames() {
  std::vector<std::string> names;
  for (const auto& [name, make] : Presets()) names.push_back(name);
  return names;
}

core::LineExtractionOptions OptionsFor(const ExtractArgs& args, bool real) {
  core::LineExtractionOptions options = Presets().at(args.preset)();
  if (real) {
    if (args.preset == "sick_lms200") options.range_sigma_m = kCarmenRangeSigmaM;
    options.r_sigma_floor_m = kCarmenRSigmaFloorM;
    options.alpha_sigma_floor_rad = kCarmenAlphaSigmaFloorRad;
  }
  return options;
}

// The baseline on the same sensor model as `lines`: thresholds scaled to its
// sigma_rho, the same minimum length, covariance floor and endpoint bearing sigma.
core::SplitAndMergeOptions BaselineOptionsFor(const core::LineExtractionOptions& lines) {
  core::SplitAndMergeOptions o = core::SplitAndMergeOptions::SickLms200();
  o.range_sigma_m = lines.range_sigma_m;
  o.split_threshold_m = kSplitThresholdSigmas * lines.range_sigma_m;
  o.merge_threshold_m = kMergeThresholdSigmas * lines.range_sigma_m;
  o.gap_min_m = kGapMinSigmas * lines.range_sigma_m;
  o.min_length_m = lines.min_length_m;
  o.alpha_sigma_floor_rad = lines.alpha_sigma_floor_rad;
  o.r_sigma_floor_m = lines.r_sigma_floor_m;
  o.endpoint_bearing_sigma_rad = lines.endpoint_bearing_sigma_rad;
  return o;
}

double Degrees(double rad) { return rad * 180.0 / std::numbers::pi; }

// --- Ground truth -------------------------------------------------------------

struct GroundTruth {
  core::PlanarSection section;
  std::string description;  // one line: world, height, how much of the truth it covers
};

// Builds the world's section at the beam height and rewrites every scan's truth
// element indices (the log's element order) to section indices by element id.
// Elements the world lacks (the scenario's bodies and robots) become -1: no wall.
GroundTruth PrepareGroundTruth(const ExtractArgs& args, LoadedLog* log) {
  for (std::size_t k = 0; k < log->scans.size(); ++k) {
    const LabelledScan& s = log->scans[k];
    const std::size_t n = s.scan.readings.size();
    if (s.truth.true_range_m.size() != n || s.truth.element.size() != n ||
        s.truth.world_from_sensor.size() != n) {
      throw std::runtime_error(args.log + ": scan " + std::to_string(k) + " (" + s.label +
                               ") has no ground truth; --score needs scans logged with truth "
                               "(docs/scan_log.md)");
    }
  }
  const std::string path = scenarios::ResolveWorldPath(args.score_world);
  sim::World world(scenarios::LoadWorldFile(path), sim::WorldOptions{});
  GroundTruth truth;
  truth.section = world.SectionAt(args.beam_height_m);

  std::map<std::string, int> section_index;
  for (std::size_t i = 0; i < truth.section.elements.size(); ++i) {
    section_index.emplace(truth.section.elements[i].id, static_cast<int>(i));
  }
  std::vector<int> to_section(log->element_ids.size(), -1);
  for (std::size_t i = 0; i < log->element_ids.size(); ++i) {
    const auto it = section_index.find(log->element_ids[i]);
    if (it != section_index.end()) to_section[i] = it->second;
  }
  std::int64_t hits = 0;
  std::int64_t hits_in_world = 0;
  for (std::size_t k = 0; k < log->scans.size(); ++k) {
    for (int& e : log->scans[k].truth.element) {
      if (e < 0) continue;
      if (static_cast<std::size_t>(e) >= to_section.size()) {
        throw std::runtime_error(args.log + ": scan " + std::to_string(k) + " names element " +
                                 std::to_string(e) + " but the log lists " +
                                 std::to_string(to_section.size()) + " element ids");
      }
      ++hits;
      e = to_section[e];
      if (e >= 0) ++hits_in_world;
    }
  }
  if (hits > 0 && hits_in_world == 0) {
    throw std::runtime_error("none of the elements hit in " + args.log +
                             " is an element of world " + path +
                             ": --score needs the world the scenario ran in");
  }
  char figures[256];
  std::snprintf(figures, sizeof figures,
                " at beam height %.2f m: %zu segments, %zu circles; %.1f%% of the %lld rays that "
                "hit something hit its elements (the rest: the scenario's bodies and robots, no "
                "walls)",
                args.beam_height_m, truth.section.segments.size(), truth.section.circles.size(),
                hits > 0 ? 100.0 * static_cast<double>(hits_in_world) / hits : 0.0,
                static_cast<long long>(hits));
  truth.description = "ground truth: world " + path + figures;
  return truth;
}

// --- Extraction methods and their summaries -----------------------------------

struct Method {
  std::string name;
  std::function<std::vector<core::Segment>(const core::LaserScan&)> extract;
  // Per run:
  std::vector<double> time_us;  // one per scan
  std::size_t lines = 0;
  scenarios::ExtractionScoreAccumulator score;
};

double Mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  if (v.size() % 2 == 1) return v[mid];
  return 0.5 * (v[mid] + *std::max_element(v.begin(), v.begin() + mid));
}

double ScansPerSecond(const Method& m) {
  const double total_us = Mean(m.time_us) * static_cast<double>(m.time_us.size());
  return total_us > 0.0 ? 1e6 * static_cast<double>(m.time_us.size()) / total_us : 0.0;
}

// One method: the summary as `key: value` lines.
void PrintSummary(const Method& m, bool scored) {
  const std::size_t scans = m.time_us.size();
  std::printf("scans: %zu\n", scans);
  std::printf("lines per scan: %.2f mean (%zu lines)\n",
              static_cast<double>(m.lines) / static_cast<double>(scans), m.lines);
  std::printf("time per scan: %.1f us mean, %.1f us median, %.1f us max (%.0f scans/s)\n",
              Mean(m.time_us), Median(m.time_us),
              *std::max_element(m.time_us.begin(), m.time_us.end()), ScansPerSecond(m));
  if (!scored) return;
  const scenarios::ExtractionFigures f = m.score.Figures();
  std::printf("walls in view: %d, found %d: TP rate %.4f (modelled surfaces %d of %d: %.4f)\n",
              f.walls_in_view, f.walls_found, f.true_positive_rate, f.modelled_walls_found,
              f.modelled_walls_in_view, f.modelled_true_positive_rate);
  std::printf("extracted: %d, false positives %d: FP rate %.4f\n", f.extracted, f.false_positives,
              f.false_positive_rate);
  std::printf(
      "matches: %d: sigma delta-r %.2f mm (mean %.2f mm), sigma delta-alpha %.3f deg (mean "
      "%.3f deg)\n",
      f.matches, 1e3 * f.sigma_delta_r_m, 1e3 * f.mean_delta_r_m, Degrees(f.sigma_delta_alpha_rad),
      Degrees(f.mean_delta_alpha_rad));
  std::printf("in 95%% gate: %.4f (%d of %d matches)\n", f.in_gate_fraction, f.matches_in_gate,
              f.matches);
}

// Several methods on the same scans: one row per figure, one column per method.
void PrintComparison(const std::vector<Method>& methods, bool scored) {
  constexpr int kLabelWidth = 28;
  constexpr int kColumnWidth = 17;
  auto row = [&](const char* label, const std::function<std::string(const Method&)>& value) {
    std::printf("%-*s", kLabelWidth, label);
    for (const Method& m : methods) std::printf("%*s", kColumnWidth, value(m).c_str());
    std::printf("\n");
  };
  auto fmt = [](const char* format, double x) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, format, x);
    return std::string(buffer);
  };
  auto figures = [](const Method& m) { return m.score.Figures(); };
  row("method", [](const Method& m) { return m.name; });
  row("scans", [&](const Method& m) { return std::to_string(m.time_us.size()); });
  row("lines per scan", [&](const Method& m) {
    return fmt("%.2f", static_cast<double>(m.lines) / static_cast<double>(m.time_us.size()));
  });
  row("time per scan, mean (us)", [&](const Method& m) { return fmt("%.1f", Mean(m.time_us)); });
  row("time per scan, median (us)",
      [&](const Method& m) { return fmt("%.1f", Median(m.time_us)); });
  row("time per scan, max (us)", [&](const Method& m) {
    return fmt("%.1f", *std::max_element(m.time_us.begin(), m.time_us.end()));
  });
  row("scans per second", [&](const Method& m) { return fmt("%.0f", ScansPerSecond(m)); });
  if (!scored) return;
  row("walls in view", [&](const Method& m) { return std::to_string(figures(m).walls_in_view); });
  row("walls found", [&](const Method& m) { return std::to_string(figures(m).walls_found); });
  row("TP rate", [&](const Method& m) { return fmt("%.4f", figures(m).true_positive_rate); });
  row("TP rate, modelled surfaces",
      [&](const Method& m) { return fmt("%.4f", figures(m).modelled_true_positive_rate); });
  row("extracted", [&](const Method& m) { return std::to_string(figures(m).extracted); });
  row("false positives",
      [&](const Method& m) { return std::to_string(figures(m).false_positives); });
  row("FP rate", [&](const Method& m) { return fmt("%.4f", figures(m).false_positive_rate); });
  row("matches", [&](const Method& m) { return std::to_string(figures(m).matches); });
  row("sigma delta-r (mm)",
      [&](const Method& m) { return fmt("%.2f", 1e3 * figures(m).sigma_delta_r_m); });
  row("sigma delta-alpha (deg)",
      [&](const Method& m) { return fmt("%.3f", Degrees(figures(m).sigma_delta_alpha_rad)); });
  row("in 95% gate", [&](const Method& m) { return fmt("%.4f", figures(m).in_gate_fraction); });
}

// --- Picture ------------------------------------------------------------------

// Sensor frame (metres, y up) to pixels (y down), auto-scaled to a bounding box.
class View {
 public:
  View(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) : min_m_(min_m) {
    const Eigen::Vector2d extent = (max_m - min_m).cwiseMax(1e-3);
    const double usable = kImageLongSidePx - 2.0 * kImageMarginPx;
    scale_px_per_m_ = usable / extent.maxCoeff();
    width_px_ = static_cast<int>(std::ceil(extent.x() * scale_px_per_m_)) + 2 * kImageMarginPx;
    height_px_ = static_cast<int>(std::ceil(extent.y() * scale_px_per_m_)) + 2 * kImageMarginPx;
  }
  int width_px() const { return width_px_; }
  int height_px() const { return height_px_; }
  Eigen::Vector2d ToPixels(const Eigen::Vector2d& p_m) const {
    return {kImageMarginPx + (p_m.x() - min_m_.x()) * scale_px_per_m_,
            height_px_ - kImageMarginPx - (p_m.y() - min_m_.y()) * scale_px_per_m_};
  }
  // A direction (unit, y up) in pixels (y down).
  static Eigen::Vector2d DirectionToPixels(const Eigen::Vector2d& d) { return {d.x(), -d.y()}; }
  // Covariance of (x, y) in m^2 to pixels^2 (the y flip negates the cross term).
  Eigen::Matrix2d CovarianceToPixels(const Eigen::Matrix2d& c_m2) const {
    const Eigen::Matrix2d j = Eigen::Vector2d(scale_px_per_m_, -scale_px_per_m_).asDiagonal();
    return j * c_m2 * j.transpose();
  }

 private:
  Eigen::Vector2d min_m_;
  double scale_px_per_m_ = 1.0;
  int width_px_ = 0;
  int height_px_ = 0;
};

Eigen::Vector2d ReadingPoint(const core::LaserReading& r) {
  return {r.range_m * std::cos(r.bearing_rad), r.range_m * std::sin(r.bearing_rad)};
}

// `text` drawn at kTextScale centred on `center_px`.
void DrawLabel(core::RgbImage* image, const Eigen::Vector2d& center_px, const std::string& text,
               const Rgb& color) {
  const scenarios::TextExtent size = scenarios::MeasureText(text, kTextScale);
  scenarios::DrawText(image, static_cast<int>(std::lround(center_px.x() - 0.5 * size.width_px)),
                      static_cast<int>(std::lround(center_px.y() - 0.5 * size.height_px)), text,
                      kTextScale, color);
}

// The plot: a 1 m grid, the scan's valid points (grey), the sensor (blue, with
// its x axis), the segments (thick, coloured, numbered as in the listing, the
// number behind the wall), each endpoint's 95% error ellipse (red), and the
// scene's symbols (purple, on the sensor's side of the feature).
core::RgbImage DrawPlot(const core::LaserScan& scan, const std::vector<core::Segment>& segments,
                        const core::SceneDescription& scene) {
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();  // the sensor is always in view
  Eigen::Vector2d hi = Eigen::Vector2d::Zero();
  for (const core::LaserReading& r : scan.readings) {
    if (!r.valid) continue;
    lo = lo.cwiseMin(ReadingPoint(r));
    hi = hi.cwiseMax(ReadingPoint(r));
  }
  for (const core::Segment& s : segments) {
    for (const core::Point2Uncertain* e : {&s.first_endpoint, &s.last_endpoint}) {
      lo = lo.cwiseMin(e->position_m);
      hi = hi.cwiseMax(e->position_m);
    }
  }
  const View view(lo, hi);
  core::RgbImage image(view.width_px(), view.height_px());

  static constexpr std::array<Rgb, 6> kPalette = {{{0, 114, 178},
                                                   {0, 158, 115},
                                                   {230, 159, 0},
                                                   {204, 121, 167},
                                                   {86, 180, 233},
                                                   {120, 80, 40}}};
  const Rgb point_color = {90, 90, 90};
  const Rgb sensor_color = {20, 20, 200};
  const Rgb ellipse_color = {220, 0, 0};
  const Rgb grid_color = {230, 230, 230};
  const Rgb symbol_color = {128, 0, 160};

  for (double x = std::ceil(lo.x()); x <= hi.x(); x += kGridSpacingM) {
    scenarios::DrawLine(&image, view.ToPixels({x, lo.y()}), view.ToPixels({x, hi.y()}), 1.0,
                        grid_color);
  }
  for (double y = std::ceil(lo.y()); y <= hi.y(); y += kGridSpacingM) {
    scenarios::DrawLine(&image, view.ToPixels({lo.x(), y}), view.ToPixels({hi.x(), y}), 1.0,
                        grid_color);
  }
  for (const core::LaserReading& r : scan.readings) {
    if (r.valid) {
      scenarios::FillDisc(&image, view.ToPixels(ReadingPoint(r)), kPointRadiusPx, point_color);
    }
  }
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const core::Segment& s = segments[i];
    const Rgb& color = kPalette[i % kPalette.size()];
    const Eigen::Vector2d a = view.ToPixels(s.first_endpoint.position_m);
    const Eigen::Vector2d b = view.ToPixels(s.last_endpoint.position_m);
    scenarios::DrawLine(&image, a, b, kSegmentWidthPx, color);
    // The line's normal (cos alpha, sin alpha) points away from the sensor.
    const Eigen::Vector2d away =
        View::DirectionToPixels({std::cos(s.line.alpha_rad), std::sin(s.line.alpha_rad)});
    DrawLabel(&image, 0.5 * (a + b) + kLabelOffsetPx * away, std::to_string(i + 1), color);
  }
  const double chi2 = core::ChiSquare2Quantile(kEllipseProbability);
  for (const core::Segment& s : segments) {
    for (const core::Point2Uncertain* e : {&s.first_endpoint, &s.last_endpoint}) {
      scenarios::FillDisc(&image, view.ToPixels(e->position_m), kEndpointRadiusPx, ellipse_color);
      scenarios::DrawEllipse(&image, view.ToPixels(e->position_m),
                             view.CovarianceToPixels(e->covariance), chi2, ellipse_color);
    }
  }
  for (const core::SceneSymbol& symbol : scene.elements) {
    if (!symbol.location_m.allFinite() || !symbol.direction.allFinite()) continue;
    DrawLabel(&image,
              view.ToPixels(symbol.location_m) -
                  kSymbolOffsetPx * View::DirectionToPixels(symbol.direction),
              std::string(1, symbol.symbol), symbol_color);
  }
  const Eigen::Vector2d origin = view.ToPixels(Eigen::Vector2d::Zero());
  scenarios::DrawLine(&image, origin, view.ToPixels(Eigen::Vector2d(0.5, 0.0)), 2.0, sensor_color);
  scenarios::FillDisc(&image, origin, 5.0, sensor_color);
  return image;
}

// The plot under a text band: `caption` (black), then the scene description
// (grey), one line per symbol as SceneDescription::ToString writes it.
core::RgbImage DrawScan(const core::LaserScan& scan, const std::vector<core::Segment>& segments,
                        const core::SceneDescription& scene, const std::string& caption) {
  const core::RgbImage plot = DrawPlot(scan, segments, scene);
  std::string description = "scene: " + scene.ToString();
  while (!description.empty() && description.back() == '\n') description.pop_back();
  const scenarios::TextExtent caption_size = scenarios::MeasureText(caption, kTextScale);
  const scenarios::TextExtent scene_size = scenarios::MeasureText(description, kTextScale);
  const int band_px =
      kTextMarginPx + caption_size.height_px + kCaptionGapPx + scene_size.height_px + kTextMarginPx;
  const int width_px = std::max({plot.width, caption_size.width_px + 2 * kTextMarginPx,
                                 scene_size.width_px + 2 * kTextMarginPx});
  core::RgbImage image(width_px, band_px + plot.height);
  scenarios::DrawText(&image, kTextMarginPx, kTextMarginPx, caption, kTextScale, {0, 0, 0});
  scenarios::DrawText(&image, kTextMarginPx, kTextMarginPx + caption_size.height_px + kCaptionGapPx,
                      description, kTextScale, {70, 70, 70});
  scenarios::DrawLine(&image, Eigen::Vector2d(0.0, band_px - 1.0),
                      Eigen::Vector2d(width_px, band_px - 1.0), 1.0, {200, 200, 200});
  scenarios::Blit(plot, (width_px - plot.width) / 2, band_px, &image);
  return image;
}

core::SceneDescription SceneOf(const core::LaserScan& scan,
                               const std::vector<core::Segment>& segments,
                               std::vector<core::Beacon>* beacons) {
  // Beacons (§3.3) and the scene description (§3.5) of the same scan.
  *beacons = core::ExtractBeacons(scan, core::BeaconExtractionOptions{});
  return core::DescribeScene(segments, *beacons, core::SceneOptions{});
}

void PrintLines(const LabelledScan& s, std::size_t k, std::size_t count,
                const std::vector<core::Segment>& segments, double time_us) {
  int valid = 0;
  for (const core::LaserReading& r : s.scan.readings) valid += r.valid ? 1 : 0;
  std::printf("scan %zu of %zu (%s): %zu readings (%d valid), %zu lines in %.1f us\n", k, count,
              s.label.c_str(), s.scan.readings.size(), valid, segments.size(), time_us);
  std::printf("%4s %10s %8s %9s %8s %8s %6s %8s %8s %8s %8s\n", "#", "alpha_deg", "r_m",
              "s_alpha_deg", "s_r_mm", "length_m", "points", "x1_m", "y1_m", "x2_m", "y2_m");
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const core::Segment& g = segments[i];
    std::printf("%4zu %10.2f %8.3f %9.3f %8.2f %8.3f %6d %8.3f %8.3f %8.3f %8.3f\n", i + 1,
                Degrees(g.line.alpha_rad), g.line.r_m, Degrees(std::sqrt(g.line.covariance(0, 0))),
                1e3 * std::sqrt(g.line.covariance(1, 1)), g.length_m, g.point_count,
                g.first_endpoint.position_m.x(), g.first_endpoint.position_m.y(),
                g.last_endpoint.position_m.x(), g.last_endpoint.position_m.y());
  }
  std::vector<core::Beacon> beacons;
  const core::SceneDescription scene = SceneOf(s.scan, segments, &beacons);
  std::printf("beacons: %zu\n", beacons.size());
  std::printf("scene: %s\n", scene.ToString().c_str());
}

}  // namespace

CLI::App* AddExtractCommand(CLI::App* app, ExtractArgs* args) {
  auto* extract = app->add_subcommand(
      "extract", "Extract lines (thesis §3.2) from the scans of a CARMEN or Pavilion scan log");
  extract->add_option("--log", args->log, "CARMEN log (.log, .log.gz) or Pavilion scans.bin")
      ->required();
  extract->add_option("--scan", args->scan, "List the lines of this scan only (0-based)")
      ->check(CLI::NonNegativeNumber);
  extract->add_option("--png", args->png,
                      "Picture of scan K (default 0): points, segments, 95% endpoint ellipses, "
                      "caption and scene description");
  extract->add_option("--preset", args->preset, "Extraction options preset")
      ->check(CLI::IsMember(PresetNames()))
      ->capture_default_str();
  extract->add_option("--robot", args->robot, "scans.bin: only this robot's scans");
  extract->add_option("--sensor", args->sensor, "scans.bin: only this laser's scans");
  auto* score = extract->add_option(
      "--score", args->score_world,
      "scans.bin: score the lines against the ground truth of this WORLD (name or path), the "
      "world the scenario ran in (docs/metrics.md)");
  extract
      ->add_option("--beam-height", args->beam_height_m,
                   "With --score: height of the laser scan plane (m); the robots' lasers are at "
                   "0.5 m")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str()
      ->needs(score);
  extract->add_flag("--compare", args->compare,
                    "Also run the split-and-merge baseline on the same scans; print both");
  extract->footer(
      "Without --scan prints a summary: scans, lines per scan, time per scan (mean, median,\n"
      "max; after one untimed warm-up run) and scans per second. --score adds the figures of\n"
      "docs/metrics.md against the world's section at --beam-height: walls in view and found\n"
      "(TP rate, also over surfaces the sensor model covers), extracted lines and false\n"
      "positives (FP rate), sigma of delta-r and delta-alpha over matches, and the fraction\n"
      "inside the 95% chi-square gate. Truth is matched to the world by element id; the\n"
      "scenario's bodies and robots are no walls. True lines are taken in the frame of each\n"
      "scan's first reading: a moving robot's scan distortion shows in delta-r, delta-alpha and\n"
      "the gate fraction. --compare also runs core::SplitAndMerge (split and merge at 5\n"
      "sigma_rho, gaps from 3 sigma_rho, ExtractLines' minimum length) and prints one column\n"
      "per method. The picture shows ExtractLines' segments. CARMEN logs get the log's angular\n"
      "step (docs/carmen_logs.md) and a covariance floor of 5 mm and 0.2 deg for correlated\n"
      "error; they have no ground truth.\n"
      "Examples:\n"
      "  pavilion extract --log ../shared/data/carmen/intel-corrected.log.gz\n"
      "  pavilion extract --log ../shared/data/carmen/intel-corrected.log.gz --scan 5 --png "
      "s5.png\n"
      "  pavilion run scenarios/expo_visitors.yaml --out out/demo\n"
      "  pavilion extract --log out/demo/scans.bin --score expo_hall --compare\n"
      "  pavilion extract --log out/demo/scans.bin --robot robox_1 --sensor front --scan 0 "
      "--png s0.png");
  return extract;
}

namespace {

// The log of --log, checked against --score and --scan.
LoadedLog LoadLog(const ExtractArgs& args) {
  const bool scan_log = HasScanLogMagic(args.log);
  if (!args.score_world.empty() && !scan_log) {
    throw std::runtime_error("--score needs a Pavilion scan log (scans.bin) with ground truth; '" +
                             args.log + "' is not one (CARMEN logs have no ground truth)");
  }
  LoadedLog log = scan_log ? LoadScanLog(args) : LoadCarmen(args);
  if (log.scans.empty())
    throw std::runtime_error(args.log +
                             ": neither a Pavilion scan log (no PAVSCAN1 magic) nor a CARMEN log "
                             "with FLASER scans");
  const std::size_t count = log.scans.size();
  if (args.scan >= 0 && static_cast<std::uint64_t>(args.scan) >= count) {
    throw std::runtime_error("--scan " + std::to_string(args.scan) +
                             " is out of range: " + args.log + " has " + std::to_string(count) +
                             " scans (0.." + std::to_string(count - 1) + ")");
  }
  return log;
}

// What the methods found in the one scan that is listed or drawn.
struct ShownScan {
  std::size_t index = 0;
  std::vector<std::vector<core::Segment>> segments;  // per method
  std::vector<double> time_us;                       // per method
};

// Runs every method on the scans (K only with --scan), timing each and
// scoring it against `truth` when given.
ShownScan RunMethods(const ExtractArgs& args, const LoadedLog& log, const GroundTruth* truth,
                     std::vector<Method>& methods) {
  ShownScan shown;
  // The one scan that is listed or drawn: K, or 0 for --png without --scan.
  shown.index = args.scan >= 0 ? static_cast<std::size_t>(args.scan) : 0;
  // One untimed run of each method first: the first call's allocations and
  // page faults are no part of the time per scan.
  for (const Method& m : methods) m.extract(log.scans[shown.index].scan);
  shown.segments.resize(methods.size());
  shown.time_us.assign(methods.size(), 0.0);
  for (std::size_t k = 0; k < log.scans.size(); ++k) {
    if (args.scan >= 0 && k != shown.index) continue;
    const LabelledScan& s = log.scans[k];
    for (std::size_t m = 0; m < methods.size(); ++m) {
      const auto start = std::chrono::steady_clock::now();
      std::vector<core::Segment> segments = methods[m].extract(s.scan);
      const auto stop = std::chrono::steady_clock::now();
      const double us = std::chrono::duration<double, std::micro>(stop - start).count();
      methods[m].time_us.push_back(us);
      methods[m].lines += segments.size();
      if (truth != nullptr) {
        methods[m].score.Add(scenarios::ScoreExtraction(s.scan, s.truth, truth->section, segments));
      }
      if (k == shown.index) {
        shown.segments[m] = std::move(segments);
        shown.time_us[m] = us;
      }
    }
  }
  return shown;
}

// The log, the options of the methods and the ground truth used.
void PrintSettings(const ExtractArgs& args, const LoadedLog& log,
                   const core::LineExtractionOptions& options,
                   const core::SplitAndMergeOptions& baseline, const GroundTruth* truth) {
  std::printf("%s\n", log.description.c_str());
  std::printf(
      "preset %s: n_f = %d, d_m = %.1f, alpha = %.2f, sigma_rho = %.1f mm, floor %.1f mm "
      "and %.2f deg\n",
      args.preset.c_str(), options.window_size, options.fidelity_threshold, options.significance,
      1e3 * options.range_sigma_m, 1e3 * options.r_sigma_floor_m,
      Degrees(options.alpha_sigma_floor_rad));
  if (args.compare) {
    std::printf(
        "split-and-merge: split %.1f mm, merge %.1f mm, gaps %.1f mm + lambda %.1f deg, "
        "min %d points, min length %.2f m\n",
        1e3 * baseline.split_threshold_m, 1e3 * baseline.merge_threshold_m,
        1e3 * baseline.gap_min_m, Degrees(baseline.gap_lambda_rad), baseline.min_points,
        baseline.min_length_m);
  }
  if (truth != nullptr) std::printf("%s\n", truth->description.c_str());
}

// --png: the picture of the shown scan with ExtractLines' segments.
void WritePicture(const ExtractArgs& args, const LoadedLog& log, const ShownScan& shown) {
  const LabelledScan& s = log.scans[shown.index];
  std::vector<core::Beacon> beacons;
  const core::SceneDescription scene = SceneOf(s.scan, shown.segments.front(), &beacons);
  const std::string caption = std::filesystem::path(args.log).filename().string() + "  scan " +
                              std::to_string(shown.index) + " (" + s.label + ")  " +
                              std::to_string(shown.segments.front().size()) + " lines";
  scenarios::WritePng(args.png, DrawScan(s.scan, shown.segments.front(), scene, caption));
  std::printf("png: %s (scan %zu)\n", args.png.c_str(), shown.index);
}

}  // namespace

int RunExtractCommand(const ExtractArgs& args) {
  LoadedLog log = LoadLog(args);
  const std::size_t count = log.scans.size();
  const core::LineExtractionOptions options = OptionsFor(args, log.real);
  options.Validate();
  const core::SplitAndMergeOptions baseline = BaselineOptionsFor(options);
  if (args.compare) baseline.Validate();
  const bool scored = !args.score_world.empty();
  GroundTruth truth;
  if (scored) truth = PrepareGroundTruth(args, &log);

  std::vector<Method> methods;
  methods.push_back({"ExtractLines",
                     [&](const core::LaserScan& s) { return core::ExtractLines(s, options); },
                     {},
                     0,
                     {}});
  if (args.compare) {
    methods.push_back({"split-and-merge",
                       [&](const core::LaserScan& s) { return core::SplitAndMerge(s, baseline); },
                       {},
                       0,
                       {}});
  }
  const ShownScan shown = RunMethods(args, log, scored ? &truth : nullptr, methods);

  PrintSettings(args, log, options, baseline, scored ? &truth : nullptr);
  if (args.scan >= 0) {
    for (std::size_t m = 0; m < methods.size(); ++m) {
      if (methods.size() > 1) std::printf("%s:\n", methods[m].name.c_str());
      PrintLines(log.scans[shown.index], shown.index, count, shown.segments[m], shown.time_us[m]);
    }
  }
  if (args.scan < 0 || scored || args.compare) {
    if (args.scan >= 0) std::printf("summary of scan %zu:\n", shown.index);
    if (methods.size() == 1) {
      PrintSummary(methods.front(), scored);
    } else {
      PrintComparison(methods, scored);
    }
  }
  if (!args.png.empty()) WritePicture(args, log, shown);
  return 0;
}

}  // namespace pavilion::cli
