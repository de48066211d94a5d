#include "scenarios/cli/extract_command.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/features/beacon_extraction.h"
#include "core/features/line_extraction.h"
#include "core/features/scene_description.h"
#include "core/types/image.h"
#include "scenarios/carmen_log.h"
#include "scenarios/png.h"
#include "scenarios/scan_log.h"

namespace pavilion::cli {
namespace {

// Additive covariance floor for real CARMEN logs (§2.2.1.3): the logged SICK
// scanners have range errors correlated along a wall (calibration, surface,
// incidence) that white per-reading noise does not model. Assumed values, of
// the order of the thesis' repeatability figures (§3.2.4: sigma_r = 5 mm,
// sigma_alpha = 0.2 deg).
constexpr double kCarmenRangeSigmaM = 0.01;
constexpr double kCarmenRSigmaFloorM = 0.005;
constexpr double kCarmenAlphaSigmaFloorRad = 0.2 * std::numbers::pi / 180.0;

// Probability of the endpoints' error ellipses; chi^2(2) quantile 5.991.
constexpr double kEllipseProbability = 0.95;

// Picture: the longer side of the image and the blank margin, pixels.
constexpr int kImageLongSidePx = 1000;
constexpr int kImageMarginPx = 30;
constexpr double kPointRadiusPx = 1.8;
constexpr double kSegmentWidthPx = 4.0;
constexpr double kEndpointRadiusPx = 2.5;
constexpr int kEllipseVertices = 96;
constexpr double kGridSpacingM = 1.0;  // light grid lines every metre

const char kScanLogMagic[] = "PAVSCAN1";

using Rgb = std::array<std::uint8_t, 3>;

// One scan to extract from, with a label for the listing.
struct LabelledScan {
  std::string label;
  core::LaserScan scan;
};

struct LoadedLog {
  std::string description;  // one line: format, scans, angular step
  bool real = false;        // a CARMEN log (real sensor: covariance floor on)
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
    out.scans.push_back({label, std::move(s.scan)});
  }
  return out;
}

LoadedLog LoadScanLog(const ExtractArgs& args) {
  scenarios::ScanLog log = scenarios::ReadScanLog(args.log);
  LoadedLog out;
  for (scenarios::ScanLogRecord& r : log.records) {
    if (!args.robot.empty() && r.robot != args.robot) continue;
    if (!args.sensor.empty() && r.scan.sensor_id != args.sensor) continue;
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "%.3f", r.scan.stamp_s);
    out.scans.push_back(
        {r.robot + "/" + r.scan.sensor_id + ", t = " + stamp + " s", std::move(r.scan)});
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

double Degrees(double rad) { return rad * 180.0 / std::numbers::pi; }

// --- A small rasterizer -----------------------------------------------------

void SetPixel(core::RgbImage* image, int x, int y, const Rgb& color) {
  if (x < 0 || y < 0 || x >= image->width || y >= image->height) return;
  const std::size_t i = (static_cast<std::size_t>(y) * image->width + x) * 3;
  image->pixels[i] = color[0];
  image->pixels[i + 1] = color[1];
  image->pixels[i + 2] = color[2];
}

void FillDisc(core::RgbImage* image, const Eigen::Vector2d& center_px, double radius_px,
              const Rgb& color) {
  const int x0 = static_cast<int>(std::floor(center_px.x() - radius_px));
  const int x1 = static_cast<int>(std::ceil(center_px.x() + radius_px));
  const int y0 = static_cast<int>(std::floor(center_px.y() - radius_px));
  const int y1 = static_cast<int>(std::ceil(center_px.y() + radius_px));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const double dx = x + 0.5 - center_px.x();
      const double dy = y + 0.5 - center_px.y();
      if (dx * dx + dy * dy <= radius_px * radius_px) SetPixel(image, x, y, color);
    }
  }
}

// A line `width_px` wide (at least one pixel), stamped as discs every half pixel.
void DrawLine(core::RgbImage* image, const Eigen::Vector2d& a_px, const Eigen::Vector2d& b_px,
              double width_px, const Rgb& color) {
  const double length = (b_px - a_px).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(2.0 * length)));
  const double radius = std::max(0.5, 0.5 * width_px);
  for (int i = 0; i <= steps; ++i) {
    FillDisc(image, a_px + (b_px - a_px) * (static_cast<double>(i) / steps), radius, color);
  }
}

// Outline of {p : (p - c)^T covariance^-1 (p - c) = chi2}, covariance in pixels^2.
void DrawEllipse(core::RgbImage* image, const Eigen::Vector2d& center_px,
                 const Eigen::Matrix2d& covariance_px2, double chi2, const Rgb& color) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(covariance_px2);
  const Eigen::Vector2d semi_axes =
      (chi2 * eig.eigenvalues().cwiseMax(0.0)).cwiseSqrt().cwiseMax(1.0);  // >= 1 px: visible
  Eigen::Vector2d previous = Eigen::Vector2d::Zero();
  for (int i = 0; i <= kEllipseVertices; ++i) {
    const double t = 2.0 * std::numbers::pi * i / kEllipseVertices;
    const Eigen::Vector2d p = center_px + eig.eigenvectors().col(0) * semi_axes(0) * std::cos(t) +
                              eig.eigenvectors().col(1) * semi_axes(1) * std::sin(t);
    if (i > 0) DrawLine(image, previous, p, 1.0, color);
    previous = p;
  }
}

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

// A 1 m grid, the scan's valid points (grey), the sensor (blue, with its x axis), the
// segments (thick, coloured) and each endpoint's 95% error ellipse (red).
core::RgbImage DrawScan(const core::LaserScan& scan, const std::vector<core::Segment>& segments) {
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

  for (double x = std::ceil(lo.x()); x <= hi.x(); x += kGridSpacingM) {
    DrawLine(&image, view.ToPixels({x, lo.y()}), view.ToPixels({x, hi.y()}), 1.0, grid_color);
  }
  for (double y = std::ceil(lo.y()); y <= hi.y(); y += kGridSpacingM) {
    DrawLine(&image, view.ToPixels({lo.x(), y}), view.ToPixels({hi.x(), y}), 1.0, grid_color);
  }
  for (const core::LaserReading& r : scan.readings) {
    if (r.valid) FillDisc(&image, view.ToPixels(ReadingPoint(r)), kPointRadiusPx, point_color);
  }
  for (std::size_t i = 0; i < segments.size(); ++i) {
    DrawLine(&image, view.ToPixels(segments[i].first_endpoint.position_m),
             view.ToPixels(segments[i].last_endpoint.position_m), kSegmentWidthPx,
             kPalette[i % kPalette.size()]);
  }
  const double chi2 = core::ChiSquare2Quantile(kEllipseProbability);
  for (const core::Segment& s : segments) {
    for (const core::Point2Uncertain* e : {&s.first_endpoint, &s.last_endpoint}) {
      FillDisc(&image, view.ToPixels(e->position_m), kEndpointRadiusPx, ellipse_color);
      DrawEllipse(&image, view.ToPixels(e->position_m), view.CovarianceToPixels(e->covariance),
                  chi2, ellipse_color);
    }
  }
  const Eigen::Vector2d origin = view.ToPixels(Eigen::Vector2d::Zero());
  DrawLine(&image, origin, view.ToPixels(Eigen::Vector2d(0.5, 0.0)), 2.0, sensor_color);
  FillDisc(&image, origin, 5.0, sensor_color);
  return image;
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
  // Beacons (§3.3) and the scene description (§3.5) of the same scan.
  const std::vector<core::Beacon> beacons =
      core::ExtractBeacons(s.scan, core::BeaconExtractionOptions{});
  const core::SceneDescription scene = core::DescribeScene(segments, beacons, core::SceneOptions{});
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
                      "Picture of scan K (default 0): points, segments, 95% endpoint ellipses");
  extract->add_option("--preset", args->preset, "Extraction options preset")
      ->check(CLI::IsMember(PresetNames()))
      ->capture_default_str();
  extract->add_option("--robot", args->robot, "scans.bin: only this robot's scans");
  extract->add_option("--sensor", args->sensor, "scans.bin: only this laser's scans");
  extract->footer(
      "Without --scan prints a summary: scans, mean lines per scan, mean and max time per scan\n"
      "(ExtractLines only). CARMEN logs get the log's angular step (docs/carmen_logs.md) and a\n"
      "covariance floor of 5 mm and 0.2 deg for correlated error.\n"
      "Examples:\n"
      "  pavilion extract --log ../shared/data/carmen/intel-corrected.log.gz\n"
      "  pavilion extract --log ../shared/data/carmen/intel-corrected.log.gz --scan 5 --png "
      "s5.png\n"
      "  pavilion extract --log out/demo/scans.bin --robot robox --sensor front --scan 0");
  return extract;
}

int RunExtractCommand(const ExtractArgs& args) {
  const LoadedLog log = HasScanLogMagic(args.log) ? LoadScanLog(args) : LoadCarmen(args);
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
  const core::LineExtractionOptions options = OptionsFor(args, log.real);
  options.Validate();

  // The one scan that is listed or drawn: K, or 0 for --png without --scan.
  const std::size_t shown = args.scan >= 0 ? static_cast<std::size_t>(args.scan) : 0;
  std::vector<core::Segment> shown_segments;
  double shown_time_us = 0.0;
  std::size_t total_lines = 0;
  double total_us = 0.0;
  double max_us = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    if (args.scan >= 0 && k != shown) continue;
    const auto start = std::chrono::steady_clock::now();
    std::vector<core::Segment> segments = core::ExtractLines(log.scans[k].scan, options);
    const auto stop = std::chrono::steady_clock::now();
    const double us = std::chrono::duration<double, std::micro>(stop - start).count();
    total_lines += segments.size();
    total_us += us;
    max_us = std::max(max_us, us);
    if (k == shown) {
      shown_segments = std::move(segments);
      shown_time_us = us;
    }
  }

  std::printf("%s\n", log.description.c_str());
  std::printf(
      "preset %s: n_f = %d, d_m = %.1f, alpha = %.2f, sigma_rho = %.1f mm, floor %.1f mm "
      "and %.2f deg\n",
      args.preset.c_str(), options.window_size, options.fidelity_threshold, options.significance,
      1e3 * options.range_sigma_m, 1e3 * options.r_sigma_floor_m,
      Degrees(options.alpha_sigma_floor_rad));
  if (args.scan >= 0) {
    PrintLines(log.scans[shown], shown, count, shown_segments, shown_time_us);
  } else {
    std::printf("scans: %zu\n", count);
    std::printf("lines per scan: %.2f mean (%zu lines)\n", static_cast<double>(total_lines) / count,
                total_lines);
    std::printf("time per scan: %.1f us mean, %.1f us max\n", total_us / count, max_us);
  }
  if (!args.png.empty()) {
    scenarios::WritePng(args.png, DrawScan(log.scans[shown].scan, shown_segments));
    std::printf("png: %s (scan %zu)\n", args.png.c_str(), shown);
  }
  return 0;
}

}  // namespace pavilion::cli
