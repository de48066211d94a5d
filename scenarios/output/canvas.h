#pragma once

// A top-down canvas on an RgbImage: world metres to pixels (x right, y up in
// the world; y down in the image) and stamped shapes in pixel coordinates, all
// drawn with SetPixel of raster.h (clipped at the border). Used by the robot
// map pictures (scenarios/maps/map_render.cc).

#include <Eigen/Core>

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

 private:
  core::RgbImage* image_;
  Eigen::Vector2d top_left_m_;
  double scale_;
};

}  // namespace pavilion::scenarios
