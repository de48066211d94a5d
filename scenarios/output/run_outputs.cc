#include "scenarios/output/run_outputs.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "scenarios/output/canvas.h"
#include "scenarios/output/crowd_strip.h"
#include "scenarios/output/localization_plot.h"
#include "scenarios/output/output_files.h"
#include "scenarios/output/png.h"
#include "scenarios/output/report.h"
#include "sim/render/top_down_view.h"

namespace pavilion::scenarios {
namespace {

// Vertices of the polygon drawn for a band bubble.
constexpr int kBubbleVertices = 24;

// A robot's plan (magenta), elastic band with its bubbles (cyan) and the
// dynamic window's chosen arc (green), over the top-down view.
void AddNavigationTracks(const nav::NavigationPicture& p, std::vector<sim::TopDownTrack>* out) {
  for (std::size_t k = 0; k < p.band_centers.size(); ++k) {
    std::vector<Eigen::Vector2d> circle;
    for (int i = 0; i <= kBubbleVertices; ++i) {
      const double a = 2.0 * std::numbers::pi * i / kBubbleVertices;
      circle.push_back(p.band_centers[k] +
                       p.band_radii_m[k] * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    out->push_back({circle, {40, 190, 210}, 0.35, 1.0});
  }
  if (!p.plan.empty()) out->push_back({p.plan, {200, 40, 200}, 0.9, 2.0, "plan"});
  if (!p.band_centers.empty()) {
    out->push_back({p.band_centers, {20, 150, 190}, 1.0, 2.0, "elastic band"});
  }
  if (!p.dwa_arc.empty()) out->push_back({p.dwa_arc, {40, 200, 40}, 1.0, 3.0, "DWA arc"});
}

// The 95 % position ellipse (chi^2 with 2 dof) of a hypothesis as a closed
// polyline, and an arrow along its heading.
constexpr double kChi2Two95 = 5.991464547107979;
constexpr int kEllipseVertices = 48;
constexpr double kArrowM = 0.8;
constexpr double kMarkerM = 0.4;  // a ring around each pose, so that a tight ellipse is found

void AddPoseShape(const core::Pose2& pose, const Eigen::Matrix2d& covariance,
                  const std::array<std::uint8_t, 3>& rgb, std::vector<sim::TopDownTrack>* out) {
  const Eigen::Vector2d c = pose.translation();
  const Eigen::Vector2d tip =
      c + kArrowM * Eigen::Vector2d(std::cos(pose.theta_rad), std::sin(pose.theta_rad));
  out->push_back({{c, tip}, rgb, 1.0, 4.0});
  std::vector<Eigen::Vector2d> marker;
  for (int k = 0; k <= kEllipseVertices; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kEllipseVertices;
    marker.push_back(c + kMarkerM * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  out->push_back({marker, rgb, 1.0, 2.0});
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(covariance);
  if (eig.info() != Eigen::Success) return;
  const Eigen::Vector2d axes = (kChi2Two95 * eig.eigenvalues().cwiseMax(0.0)).cwiseSqrt();
  std::vector<Eigen::Vector2d> ring;
  for (int k = 0; k <= kEllipseVertices; ++k) {
    const double a = 2.0 * std::numbers::pi * k / kEllipseVertices;
    ring.push_back(c + eig.eigenvectors() *
                           Eigen::Vector2d(axes.x() * std::cos(a), axes.y() * std::sin(a)));
  }
  out->push_back({ring, rgb, 1.0, 1.5});
}

// The scenario's top-down picture of the whole floor.
sim::TopDownOptions TopDownView(const Scenario& scenario) {
  sim::TopDownOptions view;
  view.width_px = scenario.outputs.image_width_px;
  view.section_height_m = scenario.outputs.section_height_m;
  if (scenario.crowd) view.people_material = scenario.crowd->material;
  return view;
}

// snapshots/hypotheses_<robot>.png: the world from above with the hypotheses.
HypothesisFigure DrawHypotheses(const std::filesystem::path& out, const Scenario& scenario,
                                const sim::World& world, const std::string& robot_id,
                                const HypothesisSnapshot& snapshot) {
  std::vector<sim::TopDownTrack> shapes;
  for (std::size_t i = 0; i < snapshot.hypotheses.size(); ++i) {
    const nav::LocationHypothesis& h = snapshot.hypotheses[i];
    AddPoseShape(h.estimate.pose, h.estimate.covariance.topLeftCorner<2, 2>(),
                 i == 0 ? std::array<std::uint8_t, 3>{200, 0, 200}
                        : std::array<std::uint8_t, 3>{250, 210, 0},
                 &shapes);
  }
  AddPoseShape(snapshot.truth, Eigen::Matrix2d::Zero(), {20, 60, 220}, &shapes);
  const sim::TopDownOptions view = TopDownView(scenario);
  HypothesisFigure figure{robot_id, snapshot.time_s, static_cast<int>(snapshot.hypotheses.size()),
                          EncodePng(sim::RenderTopDown(world, shapes, view))};
  WriteFileAtomically((out / "snapshots" / ("hypotheses_" + robot_id + ".png")).string(),
                      std::string(figure.png.begin(), figure.png.end()));
  return figure;
}

// The world rectangle RenderTopDown draws without a window: the floor and
// its margin.
PictureExtent TopDownExtent(const sim::World& world, const sim::TopDownOptions& view) {
  const sim::Floor& floor = world.description().floor;
  return {floor.min_m.x() - view.margin_m, floor.min_m.y() - view.margin_m,
          floor.max_m.x() + view.margin_m, floor.max_m.y() + view.margin_m};
}

// The estimates of the robots' last localization cycles (up to a cycle before
// the end, so a moving robot has left them behind) with their 95 % position
// ellipses (thesis Figs. 4.3, 4.8): dark green, around a dot at the estimated
// position with a heading tick; one magnification for the whole picture
// (EllipseMagnification of the largest).
constexpr Rgb kLastEstimateRgb{0, 100, 30};
constexpr double kEllipseWidthPx = 2.0;
constexpr double kEstimateDotPx = 2.0;
constexpr double kEstimateTickPx = 10.0;

// Draws every localizing robot's last estimate with its ellipse over `image`;
// returns the legend's row for them, or none when no robot has a cycle.
std::optional<LegendEntry> DrawLastEstimates(const std::vector<RobotLocalization>& localizations,
                                             const sim::TopDownFrame& frame,
                                             core::RgbImage* image) {
  std::vector<const LocalizationCycle*> last;
  double major_px = 0.0;
  for (const RobotLocalization& l : localizations) {
    if (l.tracker == nullptr || l.tracker->cycle_count() == 0) continue;
    last.push_back(&l.tracker->last_cycle());
    major_px = std::max(major_px, EllipseMajorAxisPx(last.back()->covariance.topLeftCorner<2, 2>(),
                                                     kChi2TwoDof95, frame.px_per_m));
  }
  if (last.empty()) return std::nullopt;
  const int magnification = EllipseMagnification(major_px);
  Canvas canvas(image, frame.top_left_m, frame.px_per_m);
  for (const LocalizationCycle* c : last) {
    canvas.Ellipse(c->estimate.translation(), c->covariance.topLeftCorner<2, 2>(), kChi2TwoDof95,
                   magnification, kLastEstimateRgb, kEllipseWidthPx);
    const Eigen::Vector2d q = canvas.ToPx(c->estimate.translation());
    canvas.DiscPx(q, kEstimateDotPx, kLastEstimateRgb);
    const Eigen::Vector2d heading(std::cos(c->estimate.theta_rad),
                                  -std::sin(c->estimate.theta_rad));
    canvas.LinePx(q, q + kEstimateTickPx * heading, kLastEstimateRgb, kEllipseWidthPx);
  }
  std::string label = "last update, 95 % ellipse";
  if (magnification > 1) label += " x" + std::to_string(magnification);
  return LegendEntry{label, LegendSymbol::kEllipse, kLastEstimateRgb, kLastEstimateRgb,
                     kEllipseWidthPx};
}

// A place area's legend swatch: its colour at this opacity over white (an
// area's own 0.15 hardly shows in a small swatch); chosen.
constexpr double kMinSwatchAlpha = 0.4;

// A legend row for what RenderTopDown drew; a track's colour as it shows
// over white (its alpha applied).
LegendEntry ToLegendEntry(const sim::TopDownLegendItem& item) {
  Rgb faded = item.rgb;
  for (int k = 0; k < 3; ++k) {
    faded[k] = static_cast<std::uint8_t>(
        std::lround(item.alpha * item.rgb[k] + (1.0 - item.alpha) * 255.0));
  }
  switch (item.item) {
    case sim::TopDownItem::kTrack:
      return {item.label, LegendSymbol::kLine, faded, faded, std::max(2.0, item.width_px)};
    case sim::TopDownItem::kBody:
      return {item.label, LegendSymbol::kSquare, item.rgb, item.rgb};
    case sim::TopDownItem::kPerson:
      return {item.label, LegendSymbol::kDisc, item.outline, item.rgb};
    case sim::TopDownItem::kRobot:
      return {item.label, LegendSymbol::kPose, {0, 0, 0}, item.rgb};
    case sim::TopDownItem::kPlace:
      return {item.label, LegendSymbol::kPose, item.rgb, item.rgb};
    case sim::TopDownItem::kPlaceArea: {  // a swatch this faint would not show
      Rgb swatch = item.rgb;
      for (int k = 0; k < 3; ++k) {
        swatch[k] = static_cast<std::uint8_t>(
            std::lround(kMinSwatchAlpha * item.rgb[k] + (1.0 - kMinSwatchAlpha) * 255.0));
      }
      return {item.label, LegendSymbol::kArea, swatch, swatch};
    }
  }
  return {item.label};
}

// The tracks of the run's top-down picture: bodies' paths, then per robot its
// odometry, true path, estimate and navigation.
std::vector<sim::TopDownTrack> RunTracks(
    const std::vector<std::vector<Eigen::Vector2d>>& body_tracks,
    const std::vector<RobotTracks>& robot_tracks) {
  std::vector<sim::TopDownTrack> tracks;
  for (const auto& t : body_tracks) tracks.push_back({t, {200, 40, 40}, 0.4, 1.0, "body path"});
  for (const RobotTracks& r : robot_tracks) {
    tracks.push_back({r.odometry, {230, 150, 20}, 0.8, 1.0, "odometry"});  // the encoders' belief
    tracks.push_back({r.truth, {20, 60, 220}, 0.9, 1.0, "true path"});
    if (!r.estimate.empty()) {
      tracks.push_back({r.estimate, {30, 160, 60}, 0.7, 1.0, "estimate"});  // the localization's
    }
    if (r.navigation) AddNavigationTracks(*r.navigation, &tracks);
  }
  return tracks;
}

// snapshots/topdown_final.png: the world at the end with the tracks, the
// last updates' estimates with their ellipses, a scale bar and a legend.
core::RgbImage DrawRunTopDown(const sim::World& world, const sim::TopDownOptions& view,
                              const std::vector<std::vector<Eigen::Vector2d>>& body_tracks,
                              const std::vector<RobotTracks>& robot_tracks,
                              const std::vector<RobotLocalization>& localizations) {
  const std::vector<sim::TopDownTrack> tracks = RunTracks(body_tracks, robot_tracks);
  core::RgbImage image = sim::RenderTopDown(world, tracks, view);
  const sim::TopDownFrame frame = sim::TopDownFrameOf(world, view);
  std::vector<LegendEntry> legend;
  for (const sim::TopDownLegendItem& item : sim::TopDownLegend(world, tracks, view)) {
    legend.push_back(ToLegendEntry(item));
  }
  if (const auto estimates = DrawLastEstimates(localizations, frame, &image)) {
    auto robot = std::find_if(legend.begin(), legend.end(),
                              [](const LegendEntry& e) { return e.label == "robot"; });
    legend.insert(robot == legend.end() ? robot : robot + 1, *estimates);
  }
  AnnotateFigure(&image, frame.px_per_m, legend);
  return image;
}

// The run's output files present in `out` (the line files, metrics.json and
// the like; performance.json comes after the report), then `written`.
std::vector<std::string> OutputFiles(const std::filesystem::path& out,
                                     const std::vector<std::string>& written) {
  std::vector<std::string> files;
  for (const char* name : {"metrics.json", "expectations.json", "events.jsonl", "trajectories.csv",
                           "localization.csv", "scans.bin"}) {
    if (std::filesystem::exists(out / name)) files.push_back(name);
  }
  files.insert(files.end(), written.begin(), written.end());
  return files;
}

}  // namespace

void WriteSnapshotsAndReport(const std::filesystem::path& out, const Scenario& scenario,
                             const sim::World& world,
                             const std::vector<std::vector<Eigen::Vector2d>>& body_tracks,
                             const std::vector<RobotTracks>& robot_tracks,
                             const std::vector<RobotLocalization>& localizations,
                             const RunMetrics& metrics, const CrowdStrip* crowd_strip,
                             const SeriesDecimator* visitors_present,
                             const ExpectationResults* expectations,
                             const DeadlockFrame* first_deadlock,
                             const std::vector<SnapshotFrame>* camera_snapshots) {
  const sim::TopDownOptions view = TopDownView(scenario);
  ReportContent content;
  content.topdown_png =
      EncodePng(DrawRunTopDown(world, view, body_tracks, robot_tracks, localizations));
  content.topdown_extent = TopDownExtent(world, view);
  std::vector<std::string> written{"snapshots/topdown_final.png"};
  WriteFileAtomically((out / written.back()).string(),
                      std::string(content.topdown_png.begin(), content.topdown_png.end()));
  for (const RobotLocalization& l : localizations) {
    const std::vector<std::uint8_t> png = EncodePng(PlotTwoSigmaOverTime(l.tracker->plot_cycles()));
    written.push_back("snapshots/two_sigma_" + l.robot_id + ".png");
    WriteFileAtomically((out / written.back()).string(), std::string(png.begin(), png.end()));
  }
  for (std::size_t k = 0; k < robot_tracks.size() && k < scenario.robots.size(); ++k) {
    if (!robot_tracks[k].hypotheses) continue;
    content.hypothesis_figures.push_back(
        DrawHypotheses(out, scenario, world, scenario.robots[k].id, *robot_tracks[k].hypotheses));
    written.push_back("snapshots/hypotheses_" + scenario.robots[k].id + ".png");
  }
  if (crowd_strip) content.crowd_frames = crowd_strip->Write(out);
  for (const CrowdFrame& f : content.crowd_frames) written.push_back(f.path);
  if (first_deadlock) {
    const CrowdFrame& f = first_deadlock->frame;
    WriteFileAtomically((out / f.path).string(), std::string(f.png.begin(), f.png.end()));
    written.push_back(f.path);
    content.first_deadlock = *first_deadlock;
  }
  if (camera_snapshots) {
    for (const SnapshotFrame& f : *camera_snapshots) {
      WriteFileAtomically((out / f.path).string(), std::string(f.png.begin(), f.png.end()));
      written.push_back(f.path);
    }
    content.camera_snapshots = camera_snapshots;
  }
  std::vector<std::string> robot_order;
  for (const RobotEntry& r : scenario.robots) robot_order.push_back(r.id);
  const ReportSeries series = ReadReportSeries(out, robot_order);
  content.series = &series;
  content.visitors_present = visitors_present;
  content.expectations = expectations;
  content.files = OutputFiles(out, written);
  WriteFileAtomically((out / "report.html").string(), RenderReportHtml(scenario, metrics, content));
}

void WritePerformanceJson(const std::filesystem::path& out, const RunSummary& s, int threads,
                          const std::string& laser_backend) {
  nlohmann::ordered_json perf;
  perf["schema_version"] = 1;
  perf["wall_time_s"] = s.wall_time_s;
  perf["startup_s"] = s.startup_s;
  perf["real_time_factor"] = s.real_time_factor;
  perf["loop_cpu_s"] = s.loop_cpu_s;
  perf["peak_rss_mb"] = s.peak_rss_mb;
  perf["threads"] = threads;
  perf["physics_steps_per_s"] = s.physics_s > 0 ? static_cast<double>(s.ticks) / s.physics_s : 0.0;
  perf["laser_backend"] = laser_backend;
  perf["laser_rays"] = s.laser_rays;
  perf["laser_fallback_scans"] = s.laser_fallback_scans;
  if (s.estimator_cycles > 0) {
    // A localization cycle: deskewing, line extraction, matching and the
    // update of every scan it integrates (with that tick's odometry).
    perf["localization_us_per_cycle"] =
        1e6 * s.estimator_cycle_s / static_cast<double>(s.estimator_cycles);
  }
  if (s.estimator_ticks > 0) {
    // Every other tick of a localizing robot: the odometry prediction.
    perf["localization_us_per_odometry_tick"] =
        1e6 * s.estimator_tick_s / static_cast<double>(s.estimator_ticks);
  }
  if (s.robot_sim_s > 0) {
    // The robots' control steps per simulated robot-second (issue 14's budget:
    // 5.5 ms of CPU per robot and simulated second for the whole stack).
    perf["control_ms_per_robot_sim_s"] = 1e3 * s.control_s / s.robot_sim_s;
  }
  perf["laser_rays_per_s"] =
      s.sensors_s > 0 ? static_cast<double>(s.laser_rays) / s.sensors_s : 0.0;
  perf["stages_s"] = {{"startup", s.startup_s},
                      {"physics", s.physics_s},
                      {"sensors", s.sensors_s},
                      {"loop_other", s.loop_s - s.physics_s - s.sensors_s},
                      {"outputs", s.wall_time_s - s.startup_s - s.loop_s}};
  WriteFileAtomically((out / "performance.json").string(), perf.dump(2) + "\n");
}

}  // namespace pavilion::scenarios
