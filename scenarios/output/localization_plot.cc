#include "scenarios/output/localization_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>

#include "scenarios/output/raster.h"

namespace pavilion::scenarios {
namespace {

// Plot frame inside the picture (px): room for tick labels left and below, the
// legend above.
constexpr int kLeftMarginPx = 52;
constexpr int kRightMarginPx = 14;
constexpr int kTopMarginPx = 24;
constexpr int kBottomMarginPx = 34;
constexpr int kTickLengthPx = 4;
constexpr int kTargetTicks = 5;  // about this many ticks per axis
constexpr double kCmPerM = 100.0;

const Rgb kAxis = {40, 40, 40};
const Rgb kGrid = {225, 225, 225};
const Rgb kFrontal = {30, 90, 220};
const Rgb kLateral = {210, 40, 40};

// A round step (1, 2 or 5 times a power of ten) giving about kTargetTicks ticks over `span`.
double TickStep(double span) {
  const double raw = span / kTargetTicks;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * power >= raw) return m * power;
  }
  return 10.0 * power;
}

std::string Label(double value, double step) {
  char buf[32];
  const int decimals = step >= 1.0 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  std::snprintf(buf, sizeof buf, "%.*f", decimals, value);
  return buf;
}

}  // namespace

void TwoSigmaPlotOptions::Validate() const {
  if (width_px < 200 || width_px > 4000) {
    throw std::invalid_argument("TwoSigmaPlotOptions.width_px must be in [200, 4000]");
  }
  if (height_px < 120 || height_px > 4000) {
    throw std::invalid_argument("TwoSigmaPlotOptions.height_px must be in [120, 4000]");
  }
}

core::RgbImage PlotTwoSigmaOverTime(const std::vector<LocalizationCycle>& cycles,
                                    const TwoSigmaPlotOptions& options) {
  options.Validate();
  core::RgbImage image(options.width_px, options.height_px);
  const int x0 = kLeftMarginPx;
  const int x1 = options.width_px - kRightMarginPx;
  const int y0 = kTopMarginPx;  // top of the frame
  const int y1 = options.height_px - kBottomMarginPx;

  double t_max = 1.0;
  double v_max = 0.1;  // cm
  for (const LocalizationCycle& c : cycles) {
    t_max = std::max(t_max, c.time_s);
    v_max = std::max({v_max, kCmPerM * c.two_sigma_frontal_m, kCmPerM * c.two_sigma_lateral_m});
  }
  const double t_step = TickStep(t_max);
  const double v_step = TickStep(v_max);
  t_max = t_step * std::ceil(t_max / t_step);
  v_max = v_step * std::ceil(v_max / v_step);
  const auto to_px = [&](double t_s, double v_cm) {
    return Eigen::Vector2d(x0 + (x1 - x0) * t_s / t_max, y1 - (y1 - y0) * v_cm / v_max);
  };

  for (double v = 0.0; v <= v_max + 0.5 * v_step; v += v_step) {
    const Eigen::Vector2d p = to_px(0.0, v);
    DrawLine(&image, p, to_px(t_max, v), 1.0, kGrid);
    DrawLine(&image, p, p - Eigen::Vector2d(kTickLengthPx, 0), 1.0, kAxis);
    const std::string label = Label(v, v_step);
    const TextExtent e = MeasureText(label);
    DrawText(&image, x0 - kTickLengthPx - 3 - e.width_px, static_cast<int>(p.y()) - 3, label, 1,
             kAxis);
  }
  for (double t = 0.0; t <= t_max + 0.5 * t_step; t += t_step) {
    const Eigen::Vector2d p = to_px(t, 0.0);
    DrawLine(&image, p, p + Eigen::Vector2d(0, kTickLengthPx), 1.0, kAxis);
    const std::string label = Label(t, t_step);
    const TextExtent e = MeasureText(label);
    DrawText(&image, static_cast<int>(p.x()) - e.width_px / 2, y1 + kTickLengthPx + 3, label, 1,
             kAxis);
  }
  DrawLine(&image, to_px(0, 0), to_px(t_max, 0), 1.0, kAxis);
  DrawLine(&image, to_px(0, 0), to_px(0, v_max), 1.0, kAxis);
  const std::string x_title = "time (s)";
  DrawText(&image, (x0 + x1 - MeasureText(x_title).width_px) / 2,
           options.height_px - kGlyphHeightPx - 2, x_title, 1, kAxis);
  DrawText(&image, 4, 6, "2 sigma (cm)", 1, kAxis);

  int legend_x = x0 + 90;
  for (const auto& [name, color] : {std::pair<const char*, Rgb>{"frontal", kFrontal},
                                    std::pair<const char*, Rgb>{"lateral", kLateral}}) {
    FillRect(&image, legend_x, 9, 16, 3, color);
    DrawText(&image, legend_x + 20, 6, name, 1, kAxis);
    legend_x += 20 + MeasureText(name).width_px + 24;
  }

  for (std::size_t k = 1; k < cycles.size(); ++k) {
    const LocalizationCycle& a = cycles[k - 1];
    const LocalizationCycle& b = cycles[k];
    DrawLine(&image, to_px(a.time_s, kCmPerM * a.two_sigma_lateral_m),
             to_px(b.time_s, kCmPerM * b.two_sigma_lateral_m), 1.5, kLateral);
    DrawLine(&image, to_px(a.time_s, kCmPerM * a.two_sigma_frontal_m),
             to_px(b.time_s, kCmPerM * b.two_sigma_frontal_m), 1.5, kFrontal);
  }
  return image;
}

}  // namespace pavilion::scenarios
