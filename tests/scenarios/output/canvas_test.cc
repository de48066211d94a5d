// The furniture of the top-down figures (scenarios/output/canvas.h): the
// scale bar's round length and its drawn span, the legend's rows, the 95 %
// ellipse's span and magnification, the corners they take; and the font's
// pixels for their labels (scenarios/output/raster.h).
#include "scenarios/output/canvas.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/types/image.h"

namespace pavilion::scenarios {
namespace {

constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kBlack{0, 0, 0};

Rgb At(const core::RgbImage& image, int x, int y) {
  const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * 3;
  return {image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]};
}

core::RgbImage White(int width, int height) { return core::RgbImage(width, height, 255, 255, 255); }

// The metres a scale bar's label names ("5 m", "20 cm", "2 mm", "1 km").
double LabelMetres(const std::string& label) {
  const std::size_t space = label.find(' ');
  const double value = std::stod(label.substr(0, space));
  const std::string unit = label.substr(space + 1);
  if (unit == "km") return value * 1e3;
  if (unit == "m") return value;
  if (unit == "cm") return value * 1e-2;
  if (unit == "mm") return value * 1e-3;
  ADD_FAILURE() << "unknown unit in " << label;
  return 0.0;
}

// The scale bar is a round length (1, 2 or 5 times a power of ten) whose bar
// is the nearest such to a fifth of the width: between 20 %/sqrt(2.5) and
// 20 % sqrt(2.5) of it, its neighbours in the series no nearer.
TEST(ScaleBarTest, RoundLengthNearAFifthOfTheWidth) {
  for (const int width : {300, 900, 1400}) {
    for (double px_per_m = 0.05; px_per_m < 5000.0; px_per_m *= 1.37) {
      const ScaleBar bar = ChooseScaleBar(px_per_m, width);
      SCOPED_TRACE(std::to_string(width) + " px, " + std::to_string(px_per_m) + " px/m");
      const double decade = std::pow(10.0, std::floor(std::log10(bar.length_m) + 1e-9));
      const double step = bar.length_m / decade;
      EXPECT_TRUE(std::abs(step - 1) < 1e-9 || std::abs(step - 2) < 1e-9 ||
                  std::abs(step - 5) < 1e-9)
          << bar.length_m;
      EXPECT_EQ(bar.length_px, std::lround(bar.length_m * px_per_m));
      const double fraction = bar.length_m * px_per_m / width;
      EXPECT_GE(fraction, 0.2 / std::sqrt(2.5) - 1e-9);
      EXPECT_LE(fraction, 0.2 * std::sqrt(2.5) + 1e-9);
      EXPECT_NEAR(LabelMetres(bar.label), bar.length_m, 1e-9 * bar.length_m);
    }
  }
  // The office floor at 900 px (18.4 px/m) and a few more, with their labels.
  EXPECT_EQ(ChooseScaleBar(18.4, 900).label, "10 m");
  EXPECT_EQ(ChooseScaleBar(45.9, 900).label, "5 m");
  EXPECT_EQ(ChooseScaleBar(100.0, 900).label, "2 m");
  EXPECT_EQ(ChooseScaleBar(2000.0, 500).label, "5 cm");
  EXPECT_EQ(ChooseScaleBar(50000.0, 1000).label, "5 mm");
  EXPECT_EQ(ChooseScaleBar(0.1, 1000).label, "2 km");
  EXPECT_THROW(ChooseScaleBar(0.0, 900), std::invalid_argument);
  EXPECT_THROW(ChooseScaleBar(std::nan(""), 900), std::invalid_argument);
  EXPECT_THROW(ChooseScaleBar(10.0, 0), std::invalid_argument);
}

// The longest run of black pixels in a row of `box`: the bar; its row and
// first pixel.
int LongestBlackRun(const core::RgbImage& image, const PixelBox& box, int* row, int* first) {
  int best = 0;
  for (int y = box.y; y < box.y + box.height; ++y) {
    int run = 0;
    for (int x = box.x; x < box.x + box.width; ++x) {
      run = At(image, x, y) == kBlack ? run + 1 : 0;
      if (run > best) {
        best = run;
        *row = y;
        *first = x - run + 1;
      }
    }
  }
  return best;
}

// Drawn, the bar spans its label's metres times px_per_m (to a pixel), at
// the layout's place, inside its box.
TEST(ScaleBarTest, DrawnBarSpansItsLabelsMetres) {
  for (const double px_per_m : {18.4, 28.5, 45.9, 100.0, 333.3}) {
    SCOPED_TRACE(px_per_m);
    core::RgbImage image = White(900, 500);
    const FigureLayout layout = AnnotateFigure(&image, px_per_m, {});
    int row = -1, first = -1;
    const int run = LongestBlackRun(image, layout.scale_bar_box, &row, &first);
    EXPECT_NEAR(run, LabelMetres(layout.scale_bar.label) * px_per_m, 1.0);
    EXPECT_EQ(first, layout.bar_x);
    EXPECT_EQ(row, layout.bar_y - 2);  // the bar's top row: the first found
    EXPECT_EQ(layout.legend_box.width, 0);
    // In the bottom left corner of an empty picture, inside it.
    EXPECT_LT(layout.scale_bar_box.x, 20);
    EXPECT_GT(layout.scale_bar_box.y, 500 - 60);
    EXPECT_LE(layout.scale_bar_box.y + layout.scale_bar_box.height, 500);
  }
}

// A label drawn alone, to compare a legend row with.
core::RgbImage TextAlone(const std::string& text, int width, int height, int x, int y) {
  core::RgbImage image = White(width, height);
  DrawText(&image, x, y, text, 1, kBlack);
  return image;
}

// The legend holds one row per entry, in order: in each row's text column
// the black pixels are exactly those of its label drawn alone; no row more.
TEST(LegendTest, OneRowPerEntryWithItsLabel) {
  const std::vector<LegendEntry> legend{
      {"true path", LegendSymbol::kLine, {20, 60, 220}},
      {"vertical edge", LegendSymbol::kCross, {0, 0, 0}},
      {"visitor", LegendSymbol::kDisc, {107, 60, 30}, {225, 180, 150}},
      {"last update, 95 % ellipse x20", LegendSymbol::kEllipse, {0, 100, 30}}};
  core::RgbImage image = White(600, 400);
  const FigureLayout layout = AnnotateFigure(&image, 50.0, legend);
  const PixelBox& box = layout.legend_box;
  // Top right, 13 px a row.
  EXPECT_EQ(box.x + box.width, 600 - 6);
  EXPECT_EQ(box.y, 6);
  EXPECT_EQ(box.height, 2 * 5 + 4 * 13 - 4);
  const int text_x = box.x + 5 + 24 + 6;
  for (std::size_t i = 0; i < legend.size(); ++i) {
    SCOPED_TRACE(legend[i].label);
    const int top = box.y + 5 + 13 * static_cast<int>(i);
    const core::RgbImage alone = TextAlone(legend[i].label, 600, 400, text_x, top);
    int black = 0;
    for (int y = top; y < top + 13; ++y) {
      for (int x = text_x; x < box.x + box.width - 1; ++x) {
        EXPECT_EQ(At(image, x, y) == kBlack, At(alone, x, y) == kBlack) << x << "," << y;
        black += At(image, x, y) == kBlack;
      }
    }
    EXPECT_GT(black, 10);
    // Its symbol: some pixel of the symbol column in the entry's colour.
    bool symbol = false;
    for (int y = top; y < top + 11; ++y) {
      for (int x = box.x + 5; x < text_x - 6; ++x)
        symbol = symbol || At(image, x, y) == legend[i].colour;
    }
    EXPECT_TRUE(symbol);
  }
  // Below the last row, only the box's white and its border.
  for (int x = text_x; x < box.x + box.width - 1; ++x) {
    EXPECT_NE(At(image, x, box.y + box.height - 2), kBlack);
  }
}

// The legend takes the corner with the least detail (top right first), the
// scale bar another; both stay inside, neither overlaps the other, and
// outside their boxes the picture is untouched.
TEST(LegendTest, QuietestCornersLeaveThePictureAlone) {
  core::RgbImage image = White(500, 300);
  // A chequerboard over the right half: detail everywhere there.
  for (int y = 0; y < 300; ++y) {
    for (int x = 250; x < 500; ++x) {
      if ((x / 2 + y / 2) % 2 == 0) SetPixel(&image, x, y, kBlack);
    }
  }
  const core::RgbImage before = image;
  const FigureLayout layout =
      AnnotateFigure(&image, 40.0, {{"estimate", LegendSymbol::kLine, {30, 160, 60}}});
  const PixelBox& legend = layout.legend_box;
  const PixelBox& bar = layout.scale_bar_box;
  EXPECT_EQ(legend.x, 6);  // top left: the right half is busy
  EXPECT_EQ(legend.y, 6);
  EXPECT_EQ(bar.x, 6);  // bottom left
  EXPECT_EQ(bar.y + bar.height, 300 - 6);
  EXPECT_LE(legend.y + legend.height, bar.y);
  const auto inside = [](const PixelBox& b, int x, int y) {
    return x >= b.x && x < b.x + b.width && y >= b.y && y < b.y + b.height;
  };
  int changed_outside = 0;
  for (int y = 0; y < 300; ++y) {
    for (int x = 0; x < 500; ++x) {
      if (!inside(legend, x, y) && !inside(bar, x, y)) {
        changed_outside += At(image, x, y) != At(before, x, y);
      }
    }
  }
  EXPECT_EQ(changed_outside, 0);
}

// The pixels drawn in `image` (not white).
std::vector<Eigen::Vector2d> InkCentres(const core::RgbImage& image) {
  std::vector<Eigen::Vector2d> ink;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      if (At(image, x, y) != kWhite) ink.emplace_back(x + 0.5, y + 0.5);
    }
  }
  return ink;
}

// An axis-aligned ellipse of covariance diag(0.04, 0.01) m^2 at 100 px/m
// spans 2 sqrt(5.991 * 0.04) m = 97.9 px across and 49.0 px down (to a pixel,
// between the centres of its outermost pixels), centred on its point.
TEST(EllipseTest, SpansItsAxesInPixels) {
  core::RgbImage image = White(400, 400);
  Canvas canvas(&image, {0.0, 4.0}, 100.0);
  const Eigen::Matrix2d covariance = Eigen::Vector2d(0.04, 0.01).asDiagonal();
  canvas.Ellipse({2.0, 2.0}, covariance, kChi2TwoDof95, 1.0, kBlack, 1.0);
  double x_min = 1e9, x_max = -1e9, y_min = 1e9, y_max = -1e9;
  for (const Eigen::Vector2d& p : InkCentres(image)) {
    x_min = std::min(x_min, p.x());
    x_max = std::max(x_max, p.x());
    y_min = std::min(y_min, p.y());
    y_max = std::max(y_max, p.y());
  }
  const double a = std::sqrt(kChi2TwoDof95 * 0.04) * 100.0;  // 48.95 px
  const double b = std::sqrt(kChi2TwoDof95 * 0.01) * 100.0;  // 24.48 px
  EXPECT_NEAR(x_max - x_min, 2.0 * a, 1.0);
  EXPECT_NEAR(y_max - y_min, 2.0 * b, 1.0);
  EXPECT_NEAR(0.5 * (x_min + x_max), 200.0, 1.0);
  EXPECT_NEAR(0.5 * (y_min + y_max), 200.0, 1.0);
  EXPECT_NEAR(EllipseMajorAxisPx(covariance, kChi2TwoDof95, 100.0), 2.0 * a, 1e-9);
}

// Rotated by 30 degrees (world frame, y up) and magnified 10 times from a
// covariance 100 times smaller, the ellipse is the same: every pixel lies
// between the semi-axes from the centre, and its pixels reach the major
// axis' ends along (cos 30, -sin 30) in pixel axes, the minor's across.
TEST(EllipseTest, RotatedAndMagnifiedAlongItsAxes) {
  core::RgbImage image = White(400, 400);
  Canvas canvas(&image, {0.0, 4.0}, 100.0);
  const double t = 30.0 * std::numbers::pi / 180.0;
  Eigen::Matrix2d r;
  r << std::cos(t), -std::sin(t), std::sin(t), std::cos(t);
  const Eigen::Matrix2d small = r * Eigen::Vector2d(4e-4, 1e-4).asDiagonal() * r.transpose();
  canvas.Ellipse({2.0, 2.0}, small, kChi2TwoDof95, 10.0, kBlack, 1.0);
  const double a = std::sqrt(kChi2TwoDof95 * 0.04) * 100.0;
  const double b = std::sqrt(kChi2TwoDof95 * 0.01) * 100.0;
  const Eigen::Vector2d centre(200.0, 200.0);
  const Eigen::Vector2d major(std::cos(t), -std::sin(t)), minor(std::sin(t), std::cos(t));
  double reach_major = 0.0, reach_minor = 0.0;
  for (const Eigen::Vector2d& p : InkCentres(image)) {
    const double d = (p - centre).norm();
    EXPECT_GE(d, b - 1.0);
    EXPECT_LE(d, a + 1.0);
    reach_major = std::max(reach_major, std::abs((p - centre).dot(major)));
    reach_minor = std::max(reach_minor, std::abs((p - centre).dot(minor)));
  }
  EXPECT_NEAR(reach_major, a, 1.0);
  EXPECT_NEAR(reach_minor, b, 1.0);
}

// An ellipse whose major axis is under 6 px is magnified by the smallest of
// 2, 5, 10, 20, ... that brings it to 20 px; a larger one (or a degenerate
// one) is not.
TEST(EllipseTest, MagnificationOfTinyEllipses) {
  EXPECT_EQ(EllipseMagnification(6.0), 1);
  EXPECT_EQ(EllipseMagnification(40.0), 1);
  EXPECT_EQ(EllipseMagnification(5.9), 5);     // 29.5 px
  EXPECT_EQ(EllipseMagnification(4.0), 5);     // 20 px
  EXPECT_EQ(EllipseMagnification(2.2), 10);    // 22 px
  EXPECT_EQ(EllipseMagnification(0.11), 200);  // 22 px
  EXPECT_EQ(EllipseMagnification(0.0), 1);
  EXPECT_EQ(EllipseMagnification(std::nan("")), 1);
  EXPECT_EQ(EllipseMagnification(1e-9), 1000000);
}

// The scale bar's label "5 m" in the 5 x 9 font: the same pixels every time,
// glyph for glyph as drawn here ('#' ink), at the given corner.
TEST(FontTest, LabelPixelsAreDeterministic) {
  const std::vector<std::string> expected{"#####............",  //
                                          "#................",  //
                                          "####........##.#.",  //
                                          "....#.......#.#.#",  //
                                          "....#.......#.#.#",  //
                                          "#...#.......#...#",  //
                                          ".###........#...#",  //
                                          ".................",  //
                                          "................."};
  core::RgbImage image = White(30, 20);
  DrawText(&image, 3, 4, "5 m", 1, kBlack);
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 30; ++x) {
      const bool in = x >= 3 && x < 20 && y >= 4 && y < 13;
      const bool ink = in && expected[y - 4][x - 3] == '#';
      EXPECT_EQ(At(image, x, y) == kBlack, ink) << x << "," << y;
    }
  }
}

}  // namespace
}  // namespace pavilion::scenarios
