#include "scenarios/output/canvas.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace pavilion::scenarios {
namespace {

using Vec2 = Eigen::Vector2d;

// Sides of the polygon an ellipse is drawn as.
constexpr int kEllipseSides = 64;

// The figure's boxes: inset from the image's corner, padding inside, white at
// kBoxOpacity with a border of kBoxBorder (chosen to read on any floor).
constexpr int kCornerInsetPx = 6;
constexpr int kBoxPaddingPx = 5;
constexpr double kBoxOpacity = 0.85;
constexpr Rgb kBoxBorder{130, 130, 130};
constexpr Rgb kInk{0, 0, 0};
// Legend rows: a symbol kSymbolWidthPx wide, then the label.
constexpr int kRowHeightPx = 13;
constexpr int kSymbolWidthPx = 24;
constexpr int kSymbolGapPx = 6;
// Scale bar: label, a gap, then end ticks kBarTickPx high with the bar
// kBarThicknessPx thick along their foot.
constexpr int kLabelGapPx = 3;
constexpr int kBarTickPx = 7;
constexpr int kBarThicknessPx = 3;
// Neighbouring pixels whose channels differ by more than this in sum are
// detail that a box should not cover.
constexpr int kDetailThreshold = 48;

}  // namespace

void Canvas::LinePx(const Vec2& a, const Vec2& b, const Rgb& c, double width_px) {
  const double len = (b - a).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(len * 2.0)));
  const double h = 0.5 * width_px;
  for (int i = 0; i <= steps; ++i) {
    const Vec2 p = a + (b - a) * (static_cast<double>(i) / steps);
    for (int y = static_cast<int>(std::floor(p.y() - h + 0.5));
         y <= static_cast<int>(std::floor(p.y() + h - 0.5)); ++y) {
      for (int x = static_cast<int>(std::floor(p.x() - h + 0.5));
           x <= static_cast<int>(std::floor(p.x() + h - 0.5)); ++x) {
        Put(x, y, c);
      }
    }
  }
}

void Canvas::DiscPx(const Vec2& q, double r, const Rgb& c) {
  for (int y = static_cast<int>(std::floor(q.y() - r)); y <= static_cast<int>(q.y() + r); ++y) {
    for (int x = static_cast<int>(std::floor(q.x() - r)); x <= static_cast<int>(q.x() + r); ++x) {
      const double dx = x + 0.5 - q.x(), dy = y + 0.5 - q.y();
      if (dx * dx + dy * dy <= r * r) Put(x, y, c);
    }
  }
}

void Canvas::RingPx(const Vec2& q, double r, const Rgb& c, double width_px) {
  const int n = std::max(16, static_cast<int>(r * 2.0));
  for (int i = 0; i < n; ++i) {
    const double t0 = 2.0 * std::numbers::pi * i / n, t1 = 2.0 * std::numbers::pi * (i + 1) / n;
    LinePx(q + r * Vec2(std::cos(t0), std::sin(t0)), q + r * Vec2(std::cos(t1), std::sin(t1)), c,
           width_px);
  }
}

void Canvas::SquarePx(const Vec2& q, double half, const Rgb& c) {
  for (int y = static_cast<int>(std::floor(q.y() - half));
       y <= static_cast<int>(std::floor(q.y() + half)); ++y) {
    for (int x = static_cast<int>(std::floor(q.x() - half));
         x <= static_cast<int>(std::floor(q.x() + half)); ++x) {
      Put(x, y, c);
    }
  }
}

void Canvas::DiamondPx(const Vec2& q, double half, const Rgb& fill, const Rgb& outline) {
  for (int y = static_cast<int>(std::floor(q.y() - half));
       y <= static_cast<int>(std::floor(q.y() + half)); ++y) {
    for (int x = static_cast<int>(std::floor(q.x() - half));
         x <= static_cast<int>(std::floor(q.x() + half)); ++x) {
      const double m = std::abs(x + 0.5 - q.x()) + std::abs(y + 0.5 - q.y());
      if (m <= half) Put(x, y, m > half - 1.5 ? outline : fill);
    }
  }
}

void Canvas::CrossPx(const Vec2& q, double half, const Rgb& c, double width_px) {
  LinePx(q - Vec2(half, 0.0), q + Vec2(half, 0.0), c, width_px);
  LinePx(q - Vec2(0.0, half), q + Vec2(0.0, half), c, width_px);
}

void Canvas::Ellipse(const Vec2& c_m, const Eigen::Matrix2d& covariance_m2, double chi2,
                     double magnification, const Rgb& c, double width_px) {
  // The covariance in pixels: x scaled, y scaled and flipped.
  const Eigen::Matrix2d s = Eigen::Vector2d(scale_, -scale_).asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(s * covariance_m2 * s.transpose());
  if (eig.info() != Eigen::Success) return;
  const Vec2 semi_axes =
      std::max(1.0, magnification) * (chi2 * eig.eigenvalues().cwiseMax(0.0)).cwiseSqrt();
  const Vec2 q = ToPx(c_m);
  Vec2 previous = Vec2::Zero();
  for (int i = 0; i <= kEllipseSides; ++i) {
    const double t = 2.0 * std::numbers::pi * i / kEllipseSides;
    const Vec2 p = q + eig.eigenvectors().col(0) * semi_axes(0) * std::cos(t) +
                   eig.eigenvectors().col(1) * semi_axes(1) * std::sin(t);
    if (i > 0) LinePx(previous, p, c, width_px);
    previous = p;
  }
}

double EllipseMajorAxisPx(const Eigen::Matrix2d& covariance_m2, double chi2, double px_per_m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(covariance_m2);
  return 2.0 * std::sqrt(chi2 * std::max(0.0, eig.eigenvalues().maxCoeff())) * px_per_m;
}

int EllipseMagnification(double major_axis_px) {
  if (!(major_axis_px > 0.0) || !std::isfinite(major_axis_px) ||
      major_axis_px >= kMinEllipseMajorPx) {
    return 1;
  }
  for (int decade = 1; decade <= 100000; decade *= 10) {
    for (const int step : {2, 5, 10}) {
      if (major_axis_px * step * decade >= kMagnifiedMajorPx) return step * decade;
    }
  }
  return 1000000;
}

ScaleBar ChooseScaleBar(double px_per_m, int image_width_px) {
  if (!(px_per_m > 0.0) || !std::isfinite(px_per_m) || image_width_px <= 0) {
    throw std::invalid_argument("ChooseScaleBar: px_per_m must be finite and > 0, width > 0");
  }
  const double aim_m = kScaleBarFraction * image_width_px / px_per_m;
  ScaleBar best;
  double best_distance = std::numeric_limits<double>::infinity();
  for (double decade = 1e-3; decade < 1e4 * 1.5; decade *= 10.0) {
    for (const double step : {1.0, 2.0, 5.0}) {
      const double length_m = step * decade;
      const double distance = std::abs(std::log(length_m / aim_m));
      if (length_m > 1e4 * 1.5 || !(distance < best_distance)) continue;
      best_distance = distance;
      best.length_m = length_m;
    }
  }
  best.length_px = static_cast<int>(std::lround(best.length_m * px_per_m));
  struct Unit {
    double m;
    const char* name;
  };
  for (const Unit unit : {Unit{1e3, "km"}, Unit{1.0, "m"}, Unit{1e-2, "cm"}, Unit{1e-3, "mm"}}) {
    if (best.length_m >= unit.m * (1 - 1e-9) || unit.m == 1e-3) {
      best.label = std::to_string(std::lround(best.length_m / unit.m)) + " " + unit.name;
      break;
    }
  }
  return best;
}

namespace {

// Pixels of `box` that differ by more than kDetailThreshold from their right
// or lower neighbour.
int DetailIn(const core::RgbImage& image, const PixelBox& box) {
  const auto at = [&](int x, int y) {
    return &image.pixels[(static_cast<std::size_t>(y) * image.width + x) * 3];
  };
  const auto differ = [](const std::uint8_t* a, const std::uint8_t* b) {
    return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]) > kDetailThreshold;
  };
  int detail = 0;
  for (int y = std::max(0, box.y); y < std::min(image.height, box.y + box.height); ++y) {
    for (int x = std::max(0, box.x); x < std::min(image.width, box.x + box.width); ++x) {
      const bool right = x + 1 < image.width && differ(at(x, y), at(x + 1, y));
      const bool down = y + 1 < image.height && differ(at(x, y), at(x, y + 1));
      if (right || down) ++detail;
    }
  }
  return detail;
}

enum class Corner { kTopLeft, kTopRight, kBottomLeft, kBottomRight };

PixelBox BoxAt(const core::RgbImage& image, Corner corner, int width, int height) {
  const bool left = corner == Corner::kTopLeft || corner == Corner::kBottomLeft;
  const bool top = corner == Corner::kTopLeft || corner == Corner::kTopRight;
  return {left ? kCornerInsetPx : image.width - kCornerInsetPx - width,
          top ? kCornerInsetPx : image.height - kCornerInsetPx - height, width, height};
}

bool Overlap(const PixelBox& a, const PixelBox& b) {
  return a.width > 0 && b.width > 0 && a.x < b.x + b.width && b.x < a.x + a.width &&
         a.y < b.y + b.height && b.y < a.y + a.height;
}

// Of `preference`, the corner whose box holds the least detail and does not
// overlap `taken` (the first corner when every box does).
PixelBox QuietestBox(const core::RgbImage& image, int width, int height,
                     const std::array<Corner, 4>& preference, const PixelBox& taken) {
  PixelBox best = BoxAt(image, preference[0], width, height);
  int best_detail = -1;
  for (const Corner corner : preference) {
    const PixelBox box = BoxAt(image, corner, width, height);
    if (Overlap(box, taken)) continue;
    const int detail = DetailIn(image, box);
    if (best_detail < 0 || detail < best_detail) {
      best = box;
      best_detail = detail;
    }
  }
  return best;
}

// The white box with its border.
void DrawBox(core::RgbImage* image, const PixelBox& b) {
  BlendRect(image, b.x, b.y, b.width, b.height, {255, 255, 255}, kBoxOpacity);
  FillRect(image, b.x, b.y, b.width, 1, kBoxBorder);
  FillRect(image, b.x, b.y + b.height - 1, b.width, 1, kBoxBorder);
  FillRect(image, b.x, b.y, 1, b.height, kBoxBorder);
  FillRect(image, b.x + b.width - 1, b.y, 1, b.height, kBoxBorder);
}

// A legend row's symbol, centred on the row's mid-height at `left`.
void DrawSymbol(Canvas* canvas, const LegendEntry& e, int left, int top) {
  const Vec2 c(left + 0.5 * kSymbolWidthPx, top + 4.5);
  const Vec2 a(left + 1.0, c.y()), b(left + kSymbolWidthPx - 1.0, c.y());
  const double w = std::clamp(e.width_px, 1.0, 4.0);
  switch (e.symbol) {
    case LegendSymbol::kLine:
      canvas->LinePx(a, b, e.colour, w);
      break;
    case LegendSymbol::kTickedLine:
      canvas->LinePx(a, b, e.colour, w);
      canvas->LinePx(c, c - Vec2(0.0, 5.0), e.colour, 1.5);
      break;
    case LegendSymbol::kCross:
      canvas->CrossPx(c, 4.0, e.colour, 1.5);
      break;
    case LegendSymbol::kDiagonalCross:
      canvas->LinePx(c - Vec2(3.0, 3.0), c + Vec2(3.0, 3.0), e.colour, 1.0);
      canvas->LinePx(c - Vec2(3.0, -3.0), c + Vec2(3.0, -3.0), e.colour, 1.0);
      break;
    case LegendSymbol::kRing:
      canvas->RingPx(c, 4.5, e.colour, 1.5);
      break;
    case LegendSymbol::kDisc:
      canvas->DiscPx(c, 5.0, e.colour);
      canvas->DiscPx(c, 4.0, e.fill);
      break;
    case LegendSymbol::kPose:
      canvas->DiscPx(c, 5.0, e.fill);
      canvas->LinePx(c, c + Vec2(9.0, 0.0), e.colour, 1.5);
      break;
    case LegendSymbol::kSquare:
      canvas->SquarePx(c, 4.0, e.fill);
      break;
    case LegendSymbol::kDiamond:
      canvas->DiamondPx(c, 6.0, e.fill, e.colour);
      break;
    case LegendSymbol::kArea:
      FillRect(canvas->image(), left + 2, top, kSymbolWidthPx - 4, kGlyphHeightPx - 1, e.fill);
      break;
    case LegendSymbol::kEllipse: {
      Canvas px(canvas->image(), {0.0, 0.0}, 1.0);  // metres = pixels, y up = -y down
      px.Ellipse({c.x(), -c.y()}, Eigen::Vector2d(100.0, 16.0).asDiagonal(), 1.0, 1.0, e.colour, w);
      canvas->DiscPx(c, 1.5, e.colour);
      canvas->LinePx(c, c + Vec2(7.0, 0.0), e.colour, 1.5);
      break;
    }
  }
}

PixelBox LegendSize(const std::vector<LegendEntry>& legend) {
  int text = 0;
  for (const LegendEntry& e : legend) text = std::max(text, MeasureText(e.label).width_px);
  const int rows = static_cast<int>(legend.size());
  return {0, 0, 2 * kBoxPaddingPx + kSymbolWidthPx + kSymbolGapPx + text,
          2 * kBoxPaddingPx + rows * kRowHeightPx - (kRowHeightPx - kGlyphHeightPx)};
}

void DrawLegend(core::RgbImage* image, const std::vector<LegendEntry>& legend,
                const PixelBox& box) {
  DrawBox(image, box);
  Canvas canvas(image, {0.0, 0.0}, 1.0);
  for (std::size_t i = 0; i < legend.size(); ++i) {
    const int top = box.y + kBoxPaddingPx + static_cast<int>(i) * kRowHeightPx;
    DrawSymbol(&canvas, legend[i], box.x + kBoxPaddingPx, top);
    DrawText(image, box.x + kBoxPaddingPx + kSymbolWidthPx + kSymbolGapPx, top, legend[i].label, 1,
             kInk);
  }
}

// The scale bar in `box`: its label centred over a bar with end ticks.
void DrawScaleBar(core::RgbImage* image, const PixelBox& box, FigureLayout* layout) {
  const ScaleBar& bar = layout->scale_bar;
  DrawBox(image, box);
  const int inner = box.width - 2 * kBoxPaddingPx;
  const int label_width = MeasureText(bar.label).width_px;
  DrawText(image, box.x + kBoxPaddingPx + (inner - label_width) / 2, box.y + kBoxPaddingPx,
           bar.label, 1, kInk);
  const int x0 = box.x + kBoxPaddingPx + (inner - bar.length_px) / 2;
  const int tick_top = box.y + kBoxPaddingPx + kGlyphHeightPx + kLabelGapPx;
  FillRect(image, x0, tick_top, 1, kBarTickPx, kInk);
  FillRect(image, x0 + bar.length_px - 1, tick_top, 1, kBarTickPx, kInk);
  FillRect(image, x0, tick_top + kBarTickPx - kBarThicknessPx, bar.length_px, kBarThicknessPx,
           kInk);
  layout->bar_x = x0;
  layout->bar_y = tick_top + kBarTickPx - 1;
}

}  // namespace

FigureLayout AnnotateFigure(core::RgbImage* image, double px_per_m,
                            const std::vector<LegendEntry>& legend) {
  FigureLayout layout;
  layout.scale_bar = ChooseScaleBar(px_per_m, image->width);
  if (!legend.empty()) {
    const PixelBox size = LegendSize(legend);
    layout.legend_box = QuietestBox(
        *image, size.width, size.height,
        {Corner::kTopRight, Corner::kTopLeft, Corner::kBottomRight, Corner::kBottomLeft}, {});
  }
  const int bar_width =
      std::max(layout.scale_bar.length_px, MeasureText(layout.scale_bar.label).width_px) +
      2 * kBoxPaddingPx;
  const int bar_height = 2 * kBoxPaddingPx + kGlyphHeightPx + kLabelGapPx + kBarTickPx;
  layout.scale_bar_box =
      QuietestBox(*image, bar_width, bar_height,
                  {Corner::kBottomLeft, Corner::kBottomRight, Corner::kTopLeft, Corner::kTopRight},
                  layout.legend_box);
  if (!legend.empty()) DrawLegend(image, legend, layout.legend_box);
  DrawScaleBar(image, layout.scale_bar_box, &layout);
  return layout;
}

}  // namespace pavilion::scenarios
