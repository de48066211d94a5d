#pragma once

// The camera model of §2.4: a pinhole with radial lens distortion, calibrated
// in the horizontal direction for vertical edges (§3.4). Image coordinates
// are in pixels with the origin at the top-left corner of the top-left pixel:
// pixel (u, v) covers [u, u + 1) x [v, v + 1). The camera frame looks along
// +x with y to the left and z up (the robot files' convention), so a point
// (x, y, z), x > 0, projects to the undistorted image point
//   u = c_u - f * y / x,   v = c_v - f * z / x.
// A vertical edge's bearing in the camera frame, positive to the left, is
//   phi = atan((c_u - u) / f)                                   (§3.4)
// with u its undistorted column.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/random/random_stream.h"
#include "core/types/image.h"

namespace pavilion::core {

struct CameraIntrinsics {
  int width_px = 640;          // Pulnix TM-9701, EIA 640 x 480 (§2.4)
  int height_px = 480;         // px
  double focal_px = 0.0;       // C_x of §3.4 (square pixels), px, > 0
  double center_u_px = 320.0;  // principal point c_u, px
  double center_v_px = 240.0;  // principal point c_v, px
  // Radial coefficients k1..k4 of eq. 3.23's correction, for the radius
  // r = |x_d - c| / f of a distorted point in focal lengths; all zero: no
  // distortion.
  std::array<double, 4> radial{0.0, 0.0, 0.0, 0.0};

  // A centred pinhole whose image spans `hfov_rad` horizontally:
  // f = (width / 2) / tan(hfov / 2), c = (width / 2, height / 2). Throws
  // std::invalid_argument unless hfov is in (0, pi) and the sizes are >= 1.
  static CameraIntrinsics FromHorizontalFov(int width_px, int height_px, double hfov_rad);
  bool distorted() const;  // any radial coefficient non-zero
  // Sizes >= 1, focal finite > 0, centre and radial coefficients finite.
  void Validate() const;  // throws std::invalid_argument naming the field
};

// Eq. 3.23: the corrected (undistorted) position of a distorted image point,
//   x = c + (x_d - c) (1 + k1 r^2 + k2 r^4 + k3 r^6 + k4 r^8).
Eigen::Vector2d UndistortPoint(const CameraIntrinsics& camera, const Eigen::Vector2d& distorted_px);
// J_undistorted_distorted = d(UndistortPoint)/d(distorted_px): propagates
// an edge pixel's position error through the calibration (§3.4).
Eigen::Matrix2d UndistortPointJacobian(const CameraIntrinsics& camera,
                                       const Eigen::Vector2d& distorted_px);
// The forward radial model: the distorted point whose correction by eq. 3.23
// is `undistorted_px` (its inverse, by safeguarded Newton's method on the
// radius, converged to 1e-10 px). Throws std::invalid_argument where eq. 3.23
// is not invertible: no distorted radius maps there, or the corrected radius
// r_u(r_d) = r_d (1 + k1 r_d^2 + ...) is not strictly increasing on [0, r_d]
// (dr_u/dr_d <= 0 somewhere between the centre and the point: a fold).
Eigen::Vector2d DistortPoint(const CameraIntrinsics& camera, const Eigen::Vector2d& undistorted_px);

// Bearing (rad, positive to the left) of an undistorted column, and back.
double BearingOfColumn(const CameraIntrinsics& camera, double undistorted_u_px);
double ColumnOfBearing(const CameraIntrinsics& camera, double bearing_rad);

// The image the lens forms from an ideal pinhole image (same size and
// intrinsics without distortion): each output pixel's centre is corrected by
// eq. 3.23 and the pinhole image is sampled there bilinearly between its pixel
// centres, pixels outside the image being black (0), so the border fades to
// black over one pixel. Weights are fixed-point (1/2048 px), the weighted sum
// integer and rounded half up. Without distortion the
// output is the input. Throws std::invalid_argument if the sizes differ or the
// camera is invalid. About 2 ms for 640 x 480; a sensor that distorts every
// frame keeps a DistortionMap (same result, a third of the time).
GrayImage DistortImage(const GrayImage& pinhole, const CameraIntrinsics& camera);

// The pinhole a lens' image is formed from: the camera without distortion,
// enlarged (principal point shifted) to cover the corrected position of every
// pixel of the camera's image, with one pixel to spare. A real lens sees
// beyond the ideal pinhole's frame; rendering this source avoids black
// borders, whose edges would pass for vertical edges.
CameraIntrinsics PinholeSource(const CameraIntrinsics& camera);

// DistortImage's sampling precomputed for one camera: built once (one eq. 3.23
// correction per pixel), applied to many frames (4 taps per pixel).
class DistortionMap {
 public:
  explicit DistortionMap(const CameraIntrinsics& camera);  // throws if invalid
  // Resamples pinhole images of `source` (PinholeSource(camera): the same
  // focal length, larger, so that no corrected pixel falls outside it and the
  // picture has no black border). Throws std::invalid_argument if either is
  // invalid or `source` is distorted or of another focal length.
  DistortionMap(const CameraIntrinsics& camera, const CameraIntrinsics& source);

  // Same as DistortImage(pinhole, camera); throws std::invalid_argument if
  // the pinhole image is not width x height.
  GrayImage Apply(const GrayImage& pinhole) const;
  // Writes into `distorted` (resized if needed), reusing its storage.
  void Apply(const GrayImage& pinhole, GrayImage* distorted) const;

  int width() const { return width_; }
  int height() const { return height_; }

 private:
  // Bilinear taps: pinhole pixels base, base + dx, base + dy, base + dx + dy
  // with weights (left, right) x (top, bottom) in 1/kWeightOne; a neighbour
  // outside the image has weight 0, all zero for a black pixel.
  struct Tap {
    std::int32_t base = 0;
    std::uint16_t left = 0, right = 0, top = 0, bottom = 0;
  };
  int width_ = 0;
  int height_ = 0;
  int source_width_ = 0;
  int source_height_ = 0;
  bool identity_ = true;
  std::vector<Tap> taps_;  // row-major, empty for the identity
};

// Adds the camera electronics' noise: zero-mean Gaussian grey levels of
// `sigma_grey`, rounded half up and clamped to [0, 255], one draw per pixel in
// row-major order (none for sigma 0). Throws std::invalid_argument unless
// sigma_grey is finite and >= 0.
void AddImageNoise(double sigma_grey, RandomStream& stream, GrayImage* image);

}  // namespace pavilion::core
