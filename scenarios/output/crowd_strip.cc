#include "scenarios/output/crowd_strip.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "scenarios/output/output_files.h"
#include "scenarios/output/png.h"
#include "scenarios/output/raster.h"
#include "sim/render/top_down_view.h"

namespace pavilion::scenarios {
namespace {

// Bounds that catch unit mistakes.
constexpr double kMaxDurationS = 1e9;
constexpr int kMaxFrames = 99;  // two-digit file numbers
constexpr double kMaxCropM = 1000.0;
constexpr int kMinSizePx = 50;  // RenderTopDown's narrowest picture
constexpr int kMaxSizePx = 2000;
constexpr double kMaxSectionHeightM = 100.0;
// Frame times are compared with the simulation clock's sums of steps.
constexpr double kDueToleranceS = 1e-9;
// The time stamped in a frame's top-left corner: its inset and white backing.
constexpr int kStampInsetPx = 3;
constexpr int kStampPaddingPx = 2;
constexpr Rgb kStampInk{20, 20, 20};
constexpr Rgb kStampBacking{255, 255, 255};

void Require(bool ok, const char* field, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("CrowdStripOptions.") + field + " must be " + expected);
  }
}

bool InRange(double v, double lo, double hi) { return v >= lo && v <= hi; }  // false for NaN

void StampCaption(const std::string& text, core::RgbImage* image) {
  const TextExtent extent = MeasureText(text);
  FillRect(image, kStampInsetPx - kStampPaddingPx, kStampInsetPx - kStampPaddingPx,
           extent.width_px + 2 * kStampPaddingPx, extent.height_px + 2 * kStampPaddingPx,
           kStampBacking);
  DrawText(image, kStampInsetPx, kStampInsetPx, text, 1, kStampInk);
}

}  // namespace

void CrowdStripOptions::Validate() const {
  Require(InRange(duration_s, 0.0, kMaxDurationS) && duration_s > 0.0, "duration_s",
          "in (0, 1e9] s");
  Require(frames >= 1 && frames <= kMaxFrames, "frames", "in [1, 99]");
  Require(InRange(crop_m, 0.0, kMaxCropM) && crop_m > 0.0, "crop_m", "in (0, 1000] m");
  Require(size_px >= kMinSizePx && size_px <= kMaxSizePx, "size_px", "in [50, 2000] px");
  Require(InRange(section_height_m, 0.0, kMaxSectionHeightM), "section_height_m", "in [0, 100] m");
}

CrowdStripOptions CrowdStripOptionsFor(const Scenario& scenario) {
  CrowdStripOptions options;
  options.duration_s = scenario.duration_s;
  options.section_height_m = scenario.outputs.section_height_m;
  if (scenario.crowd) options.people_material = scenario.crowd->material;
  return options;
}

Eigen::Vector2d CrowdStripCentre(const sim::World& world) {
  if (world.robot_count() > 0) return world.robot_state(0).pose.translation();
  const sim::Floor& floor = world.description().floor;
  return 0.5 * (floor.min_m + floor.max_m);
}

CrowdStrip::CrowdStrip(CrowdStripOptions options) : options_(std::move(options)) {
  options_.Validate();
}

double CrowdStrip::frame_time_s(int k) const {
  return (k + 0.5) * options_.duration_s / options_.frames;
}

bool CrowdStrip::Due(double t_s) const {
  return next_ < options_.frames && t_s + kDueToleranceS >= frame_time_s(next_);
}

void CrowdStrip::Capture(const sim::World& world, const Eigen::Vector2d& center_m, double t_s) {
  if (!Due(t_s)) return;
  int k = next_;
  while (k + 1 < options_.frames && t_s + kDueToleranceS >= frame_time_s(k + 1)) ++k;
  next_ = k + 1;
  frames_.push_back(Frame{
      k, t_s,
      RenderCrop(world, center_m, options_.crop_m, options_.size_px, options_.section_height_m,
                 options_.people_material, CrowdFrameCaption(t_s))});
}

core::RgbImage RenderCrop(const sim::World& world, const Eigen::Vector2d& center_m, double crop_m,
                          int size_px, double section_height_m, const std::string& people_material,
                          const std::string& caption) {
  sim::TopDownOptions view;
  view.width_px = size_px;
  view.section_height_m = section_height_m;
  view.draw_places = false;
  view.people_material = people_material;
  const Eigen::Vector2d half = Eigen::Vector2d::Constant(0.5 * crop_m);
  view.window = sim::TopDownWindow{center_m - half, center_m + half};
  core::RgbImage image = sim::RenderTopDown(world, {}, view);
  StampCaption(caption, &image);
  return image;
}

std::vector<CrowdFrame> CrowdStrip::Write(const std::filesystem::path& out_dir) const {
  std::vector<CrowdFrame> written;
  for (const Frame& f : frames_) {
    char name[32];
    std::snprintf(name, sizeof(name), "crowd_%02d.png", f.index + 1);
    const std::string path = std::string("snapshots/") + name;
    CrowdFrame frame{path, f.time_s, options_.crop_m, EncodePng(f.image)};
    WriteFileAtomically((out_dir / path).string(), std::string(frame.png.begin(), frame.png.end()));
    written.push_back(std::move(frame));
  }
  return written;
}

}  // namespace pavilion::scenarios
