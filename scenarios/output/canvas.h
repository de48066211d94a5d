#pragma once

// A top-down canvas on an RgbImage: world metres to pixels (x right, y up in
// the world; y down in the image) and stamped shapes in pixel coordinates, all
// drawn with SetPixel of raster.h (clipped at the border); and the furniture of
// a top-down figure in the thesis' style: a scale bar, a legend of the symbols
// drawn, and 95 % position ellipses (magnified when tiny). Used by the robot
// map pictures (scenarios/maps/map_render.cc) and the run's top-down picture
// (scenarios/output/run_outputs.cc).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/types/image.h"
#include "scenarios/output/raster.h"

namespace pavilion::scenarios {

class Canvas {
 public:
  // `top_left_m` is the world point at the image's top-left corner.
  Canvas(core::RgbImage* image, const Eigen::Vector2d& top_left_m, double px_per_m)
      : image_(image), top_left_m_(top_left_m), scale_(px_per_m) {}

  Eigen::Vector2d ToPx(const Eigen::Vector2d& p) const {
    return {(p.x() - top_left_m_.x()) * scale_, (top_left_m_.y() - p.y()) * scale_};
  }
  double scale() const { return scale_; }  // px per m
  core::RgbImage* image() const { return image_; }

  void Put(int x, int y, const Rgb& c) { SetPixel(image_, x, y, c); }

  // A line between two pixel positions, `width_px` wide: squares stamped every
  // half pixel.
  void LinePx(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Rgb& c, double width_px);
  // The same between two world points.
  void Line(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m, const Rgb& c, double width_px) {
    LinePx(ToPx(a_m), ToPx(b_m), c, width_px);
  }
  // Pixels whose centre lies within r of q.
  void DiscPx(const Eigen::Vector2d& q, double r, const Rgb& c);
  // A circle of radius r around q as a polygon of at least 16 sides.
  void RingPx(const Eigen::Vector2d& q, double r, const Rgb& c, double width_px);
  // The square of half side `half` around q.
  void SquarePx(const Eigen::Vector2d& q, double half, const Rgb& c);
  // The diamond |dx| + |dy| <= half around q, its outer 1.5 px in `outline`.
  void DiamondPx(const Eigen::Vector2d& q, double half, const Rgb& fill, const Rgb& outline);
  // An upright cross (+) of half length `half` around q.
  void CrossPx(const Eigen::Vector2d& q, double half, const Rgb& c, double width_px);
  // The ellipse {p : (p - c)^T covariance_m2^-1 (p - c) = chi2} around the world
  // point c, its axes scaled by `magnification` (>= 1), as a polygon of 64 sides.
  void Ellipse(const Eigen::Vector2d& c_m, const Eigen::Matrix2d& covariance_m2, double chi2,
               double magnification, const Rgb& c, double width_px);

 private:
  core::RgbImage* image_;
  Eigen::Vector2d top_left_m_;
  double scale_;
};

// --- Ellipses ------------------------------------------------------------------

// chi^2 with 2 degrees of freedom at 95 %: the position ellipse of a pose.
inline constexpr double kChi2TwoDof95 = 5.991464547107979;

// The full major axis, in pixels, of the ellipse Canvas::Ellipse draws
// unmagnified at px_per_m: 2 sqrt(chi2 lambda_max) px_per_m.
double EllipseMajorAxisPx(const Eigen::Matrix2d& covariance_m2, double chi2, double px_per_m);

// Below this full major axis an ellipse is magnified (the thesis' figures
// draw theirs large enough to see), px; chosen.
inline constexpr double kMinEllipseMajorPx = 6.0;
// A magnified ellipse's major axis is at least this, px: about a robot's size
// in the run's picture; chosen.
inline constexpr double kMagnifiedMajorPx = 20.0;

// 1 for an ellipse of full major axis >= kMinEllipseMajorPx (or 0, or not
// finite: nothing to magnify); otherwise the smallest of 2, 5, 10, 20, 50, ...
// that makes it at least kMagnifiedMajorPx, 1000000 at most.
int EllipseMagnification(double major_axis_px);

// --- Scale bar ------------------------------------------------------------------

// A scale bar of a round length: 1, 2 or 5 times a power of ten metres.
struct ScaleBar {
  double length_m = 1.0;
  int length_px = 0;  // round(length_m * px_per_m)
  std::string label;  // "5 m", "20 cm", "2 mm"
};

// The part of the picture's width a scale bar aims at (15 to 25 %).
inline constexpr double kScaleBarFraction = 0.2;

// The round length (1 mm to 10 km) whose bar is nearest to kScaleBarFraction
// of image_width_px, nearest in ratio. Throws std::invalid_argument unless
// px_per_m is finite and > 0 and image_width_px > 0.
ScaleBar ChooseScaleBar(double px_per_m, int image_width_px);

// --- Legend ---------------------------------------------------------------------

// How a legend row shows its item (the symbols of the pictures).
enum class LegendSymbol {
  kLine,           // a line of `colour`, width_px wide (a path)
  kTickedLine,     // kLine with a tick at its middle (a map segment and its visible side)
  kCross,          // an upright cross of `colour` (a vertical edge)
  kDiagonalCross,  // a diagonal cross of `colour` (a ghost point)
  kRing,           // a circle of `colour` (a column)
  kDisc,           // a disc of `fill` outlined in `colour` (a visitor; a via node)
  kPose,           // a disc of `fill` with a heading tick of `colour` (a robot, a place)
  kSquare,         // a square of `fill` (a station, a body)
  kDiamond,        // a diamond of `fill` outlined in `colour` (a beacon)
  kArea,           // a rectangle of `fill` (an area)
  kEllipse,        // an ellipse of `colour` around a dot with a heading tick (an estimate)
};

struct LegendEntry {
  std::string label;  // printable ASCII
  LegendSymbol symbol = LegendSymbol::kLine;
  Rgb colour{0, 0, 0};
  Rgb fill{255, 255, 255};
  double width_px = 2.0;  // lines and rings
};

// --- A figure's furniture ---------------------------------------------------------

// A rectangle of pixels [x, x + width) x [y, y + height).
struct PixelBox {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
};

// Where AnnotateFigure put the scale bar and the legend (width 0: not drawn).
struct FigureLayout {
  ScaleBar scale_bar;
  PixelBox scale_bar_box;  // its white box: the label centred over the bar
  int bar_x = 0;           // the bar covers x in [bar_x, bar_x + length_px), ticks at both ends
  int bar_y = 0;           // its lowest row (it is 3 px thick)
  PixelBox legend_box;
};

// Draws a scale bar for px_per_m and, unless `legend` is empty, a legend of
// its entries (one row each, in order) over `image`, each in a box of white at
// 85 % opacity with a grey border, inset from a corner: the legend in the
// corner with the least detail (pixels differing from a neighbour) in its box,
// preferring the top right, top left, bottom right, bottom left; the scale
// bar likewise in another corner, preferring the bottom left.
FigureLayout AnnotateFigure(core::RgbImage* image, double px_per_m,
                            const std::vector<LegendEntry>& legend);

}  // namespace pavilion::scenarios
