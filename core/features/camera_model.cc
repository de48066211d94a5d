#include "core/features/camera_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::core {
namespace {

// DistortPoint converges when a Newton step moves the point by at most this.
constexpr double kDistortTolerancePx = 1e-10;
constexpr int kMaxDistortIterations = 200;
// Bisection steps that isolate a polynomial root to double precision.
constexpr int kRootBisections = 200;
// Fixed-point bilinear weights: kWeightBits per axis, so that a product of
// the two axes' weights times a grey level fits 32 bits (255 * 2^22 < 2^30).
constexpr int kWeightBits = 11;
constexpr std::uint32_t kWeightOne = 1u << kWeightBits;
constexpr std::uint32_t kProductHalf = 1u << (2 * kWeightBits - 1);
constexpr int kMaxGrey = 255;

void Require(bool ok, const char* field, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("CameraIntrinsics.") + field + ": expected " +
                                expected);
  }
}

// 1 + k1 rho + k2 rho^2 + k3 rho^3 + k4 rho^4 with rho = r^2: eq. 3.23's factor.
double RadialFactor(const std::array<double, 4>& k, double rho) {
  return 1.0 + rho * (k[0] + rho * (k[1] + rho * (k[2] + rho * k[3])));
}

// Polynomial c[0] + c[1] x + ... + c[4] x^4.
using Poly4 = std::array<double, 5>;

double Evaluate(const Poly4& c, int degree, double x) {
  double v = 0.0;
  for (int i = degree; i >= 0; --i) v = v * x + c[i];
  return v;
}

// The real roots of a polynomial of degree <= 4 in [a, b], ascending: the
// roots of its derivative split [a, b] into monotone pieces, and each piece
// whose ends differ in sign holds one root, found by bisection.
std::vector<double> RootsIn(const Poly4& c, int degree, double a, double b) {
  while (degree > 0 && c[degree] == 0.0) --degree;
  if (degree == 0) return {};
  std::vector<double> points{a};
  if (degree > 1) {
    Poly4 derivative{};
    for (int i = 1; i <= degree; ++i) derivative[i - 1] = i * c[i];
    for (double x : RootsIn(derivative, degree - 1, a, b)) points.push_back(x);
  }
  points.push_back(b);
  std::vector<double> roots;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    double lo = points[i], hi = points[i + 1];
    double f_lo = Evaluate(c, degree, lo);
    const double f_hi = Evaluate(c, degree, hi);
    if (f_lo == 0.0) {
      if (roots.empty() || roots.back() != lo) roots.push_back(lo);
      continue;
    }
    if ((f_lo < 0.0) == (f_hi < 0.0) || f_hi == 0.0) continue;
    for (int k = 0; k < kRootBisections && hi - lo > 0.0; ++k) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      const double f_mid = Evaluate(c, degree, mid);
      if ((f_mid < 0.0) == (f_lo < 0.0)) {
        lo = mid;
        f_lo = f_mid;
      } else {
        hi = mid;
      }
    }
    roots.push_back(0.5 * (lo + hi));
  }
  if (Evaluate(c, degree, b) == 0.0 && (roots.empty() || roots.back() != b)) roots.push_back(b);
  return roots;
}

// The distorted radius (in focal lengths) at which dr_u/dr_d, the polynomial
// 1 + 3 k1 rho + 5 k2 rho^2 + 7 k3 rho^3 + 9 k4 rho^4 in rho = r_d^2, first
// reaches zero: eq. 3.23 is a bijection on the disc inside it. Infinity when
// it never does (the Cauchy bound encloses every root).
double FoldRadius(const std::array<double, 4>& k) {
  const Poly4 slope{1.0, 3.0 * k[0], 5.0 * k[1], 7.0 * k[2], 9.0 * k[3]};
  int degree = 4;
  while (degree > 0 && slope[degree] == 0.0) --degree;
  if (degree == 0) return std::numeric_limits<double>::infinity();
  double bound = 0.0;
  for (int i = 0; i < degree; ++i) bound = std::max(bound, std::abs(slope[i] / slope[degree]));
  const std::vector<double> roots = RootsIn(slope, degree, 0.0, 1.0 + bound);
  for (double rho : roots) {
    if (rho > 0.0) return std::sqrt(rho);
  }
  return std::numeric_limits<double>::infinity();
}

// One axis of a bilinear tap: the first index to read and the weights of it
// and the next, for true neighbours first and first + 1 (weights kWeightOne -
// w_next and w_next) in an axis of n pixels, black outside. False if both
// neighbours are outside.
bool AxisTap(int first, std::uint32_t w_next, int n, int* index, std::uint16_t* w_a,
             std::uint16_t* w_b) {
  const auto w_first = static_cast<std::uint16_t>(kWeightOne - w_next);
  const auto w_second = static_cast<std::uint16_t>(w_next);
  if (first < -1 || first > n - 1) return false;
  if (n == 1) {  // first is -1 or 0; the second read (step 0) has weight 0
    *index = 0;
    *w_a = first == 0 ? w_first : w_second;
    *w_b = 0;
  } else if (first == -1) {
    *index = 0;
    *w_a = w_second;
    *w_b = 0;
  } else if (first == n - 1) {
    *index = n - 2;
    *w_a = 0;
    *w_b = w_first;
  } else {
    *index = first;
    *w_a = w_first;
    *w_b = w_second;
  }
  return true;
}

// The bilinear taps of DistortImage: output pixel (u, v)'s centre corrected by
// eq. 3.23 (as UndistortPoint), in the pinhole image's pixel-centre
// coordinates (pixel i's centre at i), with fixed-point weights.
class LensSampling {
 public:
  explicit LensSampling(const CameraIntrinsics& camera) : LensSampling(camera, camera) {}
  // Samples a pinhole image of `source`'s size and principal point (same focal length).
  LensSampling(const CameraIntrinsics& camera, const CameraIntrinsics& source)
      : k_(camera.radial),
        cu_(camera.center_u_px),
        cv_(camera.center_v_px),
        inv_f2_(1.0 / (camera.focal_px * camera.focal_px)),
        out_width_(camera.width_px),
        shift_u_(source.center_u_px - camera.center_u_px),
        shift_v_(source.center_v_px - camera.center_v_px),
        width_(source.width_px),
        height_(source.height_px) {}

  // The corrected centres of row v's pixels (x, y interleaved), in a loop
  // without branches.
  void Row(int v, std::vector<double>* xy) const {
    xy->resize(2 * static_cast<std::size_t>(out_width_));
    double* out = xy->data();
    const double dv = v + 0.5 - cv_;
    for (int u = 0; u < out_width_; ++u) {
      const double du = u + 0.5 - cu_;
      const double s = RadialFactor(k_, (du * du + dv * dv) * inv_f2_);
      out[2 * u] = cu_ + shift_u_ + du * s - 0.5;
      out[2 * u + 1] = cv_ + shift_v_ + dv * s - 0.5;
    }
  }

  // The tap at corrected centre (x, y); Tap has the fields of
  // DistortionMap::Tap. All weights zero: black.
  template <typename Tap>
  void Fill(double x, double y, Tap* tap) const {
    *tap = Tap{};
    if (!(x >= -1.0 && x < width_ && y >= -1.0 && y < height_)) return;
    int x0 = static_cast<int>(x + 1.0) - 1, y0 = static_cast<int>(y + 1.0) - 1;  // floor
    auto wx = static_cast<std::uint32_t>((x - x0) * kWeightOne + 0.5);
    auto wy = static_cast<std::uint32_t>((y - y0) * kWeightOne + 0.5);
    if (wx == kWeightOne) ++x0, wx = 0;
    if (wy == kWeightOne) ++y0, wy = 0;
    if (x0 >= 0 && x0 < width_ - 1 && y0 >= 0 && y0 < height_ - 1) {  // all four inside
      tap->base = y0 * width_ + x0;
      tap->left = static_cast<std::uint16_t>(kWeightOne - wx);
      tap->right = static_cast<std::uint16_t>(wx);
      tap->top = static_cast<std::uint16_t>(kWeightOne - wy);
      tap->bottom = static_cast<std::uint16_t>(wy);
      return;
    }
    int col = 0, row = 0;
    if (!AxisTap(x0, wx, width_, &col, &tap->left, &tap->right) ||
        !AxisTap(y0, wy, height_, &row, &tap->top, &tap->bottom)) {
      *tap = Tap{};
      return;
    }
    tap->base = row * width_ + col;
  }

 private:
  std::array<double, 4> k_;
  double cu_, cv_, inv_f2_;
  int out_width_;             // the camera's image width
  double shift_u_, shift_v_;  // the source's principal point less the camera's
  int width_, height_;        // the source pinhole image's size
};

// One output grey level: the taps' weighted sum, rounded half up.
template <typename Tap>
std::uint8_t Sample(const std::uint8_t* src, const Tap& t, int dx, int dy) {
  const std::uint8_t* p = src + t.base;
  const std::uint32_t upper = p[0] * std::uint32_t{t.left} + p[dx] * std::uint32_t{t.right};
  const std::uint32_t lower = p[dy] * std::uint32_t{t.left} + p[dy + dx] * std::uint32_t{t.right};
  return static_cast<std::uint8_t>((upper * t.top + lower * t.bottom + kProductHalf) >>
                                   (2 * kWeightBits));
}

}  // namespace

CameraIntrinsics CameraIntrinsics::FromHorizontalFov(int width_px, int height_px, double hfov_rad) {
  Require(width_px >= 1, "width_px", "an integer >= 1");
  Require(height_px >= 1, "height_px", "an integer >= 1");
  if (!(std::isfinite(hfov_rad) && hfov_rad > 0.0 && hfov_rad < std::numbers::pi)) {
    throw std::invalid_argument(
        "CameraIntrinsics::FromHorizontalFov: hfov_rad: expected a value "
        "in (0, pi)");
  }
  CameraIntrinsics c;
  c.width_px = width_px;
  c.height_px = height_px;
  c.focal_px = 0.5 * width_px / std::tan(0.5 * hfov_rad);
  c.center_u_px = 0.5 * width_px;
  c.center_v_px = 0.5 * height_px;
  return c;
}

bool CameraIntrinsics::distorted() const {
  return std::any_of(radial.begin(), radial.end(), [](double k) { return k != 0.0; });
}

void CameraIntrinsics::Validate() const {
  Require(width_px >= 1, "width_px", "an integer >= 1");
  Require(height_px >= 1, "height_px", "an integer >= 1");
  Require(std::isfinite(focal_px) && focal_px > 0.0, "focal_px", "a finite value > 0");
  Require(std::isfinite(center_u_px), "center_u_px", "a finite value");
  Require(std::isfinite(center_v_px), "center_v_px", "a finite value");
  Require(std::all_of(radial.begin(), radial.end(), [](double k) { return std::isfinite(k); }),
          "radial", "finite coefficients");
}

Eigen::Vector2d UndistortPoint(const CameraIntrinsics& camera,
                               const Eigen::Vector2d& distorted_px) {
  const Eigen::Vector2d c(camera.center_u_px, camera.center_v_px);
  const Eigen::Vector2d d = distorted_px - c;
  const double rho = d.squaredNorm() / (camera.focal_px * camera.focal_px);
  return c + d * RadialFactor(camera.radial, rho);
}

Eigen::Matrix2d UndistortPointJacobian(const CameraIntrinsics& camera,
                                       const Eigen::Vector2d& distorted_px) {
  const Eigen::Vector2d d = distorted_px - Eigen::Vector2d(camera.center_u_px, camera.center_v_px);
  const double f2 = camera.focal_px * camera.focal_px;
  const double rho = d.squaredNorm() / f2;
  const auto& k = camera.radial;
  // d(factor)/d(rho) and d(rho)/d(d) = 2 d / f^2.
  const double dfactor = k[0] + rho * (2.0 * k[1] + rho * (3.0 * k[2] + rho * 4.0 * k[3]));
  return RadialFactor(k, rho) * Eigen::Matrix2d::Identity() +
         (2.0 * dfactor / f2) * d * d.transpose();
}

Eigen::Vector2d DistortPoint(const CameraIntrinsics& camera,
                             const Eigen::Vector2d& undistorted_px) {
  const Eigen::Vector2d c(camera.center_u_px, camera.center_v_px);
  const Eigen::Vector2d d = undistorted_px - c;
  const double f = camera.focal_px;
  const double r_u = d.norm() / f;
  if (!camera.distorted() || r_u == 0.0) return undistorted_px;
  const auto& k = camera.radial;
  auto corrected = [&](double r) { return r * RadialFactor(k, r * r); };  // r_u(r_d)
  auto fail = [&](const std::string& why) {
    throw std::invalid_argument("DistortPoint: eq. 3.23 is not invertible at (" +
                                std::to_string(undistorted_px.x()) + ", " +
                                std::to_string(undistorted_px.y()) + ") px: " + why);
  };
  // Bracket the root on the principal branch [0, r_fold), where r_u(r_d) increases.
  double lo = 0.0;
  double hi = FoldRadius(k);
  if (std::isfinite(hi)) {
    if (corrected(hi) <= r_u) {
      fail("dr_u/dr_d <= 0 at r_d = " + std::to_string(hi) + " focal lengths");
    }
  } else {
    hi = r_u;
    for (int i = 0; corrected(hi) < r_u; ++i) {
      if (i > 60 || !std::isfinite(hi)) fail("no distorted radius maps there");
      hi *= 2.0;
    }
  }
  // Safeguarded Newton: a step leaving (lo, hi) is replaced by bisection.
  double r = std::clamp(r_u, lo, hi);
  for (int i = 0; i < kMaxDistortIterations; ++i) {
    const double e = corrected(r) - r_u;
    if (e == 0.0) break;
    (e < 0.0 ? lo : hi) = r;
    const double rho = r * r;
    const double slope =
        1.0 + rho * (3.0 * k[0] + rho * (5.0 * k[1] + rho * (7.0 * k[2] + rho * 9.0 * k[3])));
    double next = r - e / slope;
    if (!(slope > 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    const bool converged =
        std::abs(next - r) * f <= kDistortTolerancePx || (hi - lo) * f <= kDistortTolerancePx;
    r = next;
    if (converged) break;
  }
  return c + d * (r / r_u);
}

double BearingOfColumn(const CameraIntrinsics& camera, double undistorted_u_px) {
  return std::atan((camera.center_u_px - undistorted_u_px) / camera.focal_px);
}

double ColumnOfBearing(const CameraIntrinsics& camera, double bearing_rad) {
  return camera.center_u_px - camera.focal_px * std::tan(bearing_rad);
}

namespace {

CameraIntrinsics WithoutLens(CameraIntrinsics camera) {
  camera.radial = {0.0, 0.0, 0.0, 0.0};
  return camera;
}

}  // namespace

DistortionMap::DistortionMap(const CameraIntrinsics& camera)
    : DistortionMap(camera, WithoutLens(camera)) {}

DistortionMap::DistortionMap(const CameraIntrinsics& camera, const CameraIntrinsics& source)
    : width_(camera.width_px),
      height_(camera.height_px),
      source_width_(source.width_px),
      source_height_(source.height_px),
      identity_(!camera.distorted() && source.width_px == camera.width_px &&
                source.height_px == camera.height_px && source.center_u_px == camera.center_u_px &&
                source.center_v_px == camera.center_v_px) {
  camera.Validate();
  source.Validate();
  if (source.focal_px != camera.focal_px || source.distorted()) {
    throw std::invalid_argument(
        "DistortionMap: the source must be an undistorted pinhole of the camera's focal length");
  }
  if (identity_) return;
  taps_.resize(static_cast<std::size_t>(width_) * height_);
  const LensSampling lens(camera, source);
  std::vector<double> xy;
  for (int v = 0; v < height_; ++v) {
    lens.Row(v, &xy);
    Tap* row = taps_.data() + static_cast<std::size_t>(v) * width_;
    for (int u = 0; u < width_; ++u) lens.Fill(xy[2 * u], xy[2 * u + 1], &row[u]);
  }
}

GrayImage DistortionMap::Apply(const GrayImage& pinhole) const {
  GrayImage out;
  Apply(pinhole, &out);
  return out;
}

void DistortionMap::Apply(const GrayImage& pinhole, GrayImage* distorted) const {
  if (pinhole.width != source_width_ || pinhole.height != source_height_ ||
      pinhole.pixels.size() != static_cast<std::size_t>(source_width_) * source_height_) {
    throw std::invalid_argument(
        "DistortionMap::Apply: the pinhole image is " + std::to_string(pinhole.width) + " x " +
        std::to_string(pinhole.height) + ", the source's " + std::to_string(source_width_) + " x " +
        std::to_string(source_height_));
  }
  if (identity_) {
    *distorted = pinhole;
    return;
  }
  distorted->width = width_;
  distorted->height = height_;
  distorted->pixels.resize(static_cast<std::size_t>(width_) * height_);
  const std::uint8_t* src = pinhole.pixels.data();
  std::uint8_t* dst = distorted->pixels.data();
  const int dx = source_width_ > 1 ? 1 : 0;
  const int dy = source_height_ > 1 ? source_width_ : 0;
  const std::size_t n = taps_.size();
  for (std::size_t i = 0; i < n; ++i) dst[i] = Sample(src, taps_[i], dx, dy);
}

CameraIntrinsics PinholeSource(const CameraIntrinsics& camera) {
  camera.Validate();
  if (!camera.distorted()) return camera;
  // The corrected centres of the image's border pixels bound those of all
  // pixels (eq. 3.23 moves points radially and monotonically).
  double min_x = 0.0, min_y = 0.0;
  double max_x = camera.width_px - 1.0, max_y = camera.height_px - 1.0;
  const LensSampling lens(camera);
  std::vector<double> xy;
  for (int v = 0; v < camera.height_px; ++v) {
    lens.Row(v, &xy);
    const bool border_row = v == 0 || v == camera.height_px - 1;
    for (int u = 0; u < camera.width_px; ++u) {
      if (!border_row && u != 0 && u != camera.width_px - 1) continue;
      min_x = std::min(min_x, xy[2 * u]);
      max_x = std::max(max_x, xy[2 * u]);
      min_y = std::min(min_y, xy[2 * u + 1]);
      max_y = std::max(max_y, xy[2 * u + 1]);
    }
  }
  // One pixel more on each side for the bilinear taps.
  const int left = static_cast<int>(std::ceil(-min_x)) + 1;
  const int top = static_cast<int>(std::ceil(-min_y)) + 1;
  const int right = static_cast<int>(std::ceil(max_x - (camera.width_px - 1.0))) + 1;
  const int bottom = static_cast<int>(std::ceil(max_y - (camera.height_px - 1.0))) + 1;
  CameraIntrinsics source = camera;
  source.radial = {0.0, 0.0, 0.0, 0.0};
  source.width_px = camera.width_px + left + right;
  source.height_px = camera.height_px + top + bottom;
  source.center_u_px = camera.center_u_px + left;
  source.center_v_px = camera.center_v_px + top;
  return source;
}

// The same taps as DistortionMap's, applied as they are computed: no map.
GrayImage DistortImage(const GrayImage& pinhole, const CameraIntrinsics& camera) {
  camera.Validate();
  if (pinhole.width != camera.width_px || pinhole.height != camera.height_px ||
      pinhole.pixels.size() != static_cast<std::size_t>(pinhole.width) * pinhole.height) {
    throw std::invalid_argument(
        "DistortImage: the pinhole image is " + std::to_string(pinhole.width) + " x " +
        std::to_string(pinhole.height) + ", the camera's " + std::to_string(camera.width_px) +
        " x " + std::to_string(camera.height_px));
  }
  if (!camera.distorted()) return pinhole;
  GrayImage out(pinhole.width, pinhole.height);
  const LensSampling lens(camera);
  const int dx = pinhole.width > 1 ? 1 : 0;
  const int dy = pinhole.height > 1 ? pinhole.width : 0;
  struct {
    std::int32_t base = 0;
    std::uint16_t left = 0, right = 0, top = 0, bottom = 0;
  } tap;
  std::uint8_t* dst = out.pixels.data();
  std::vector<double> xy;
  for (int v = 0; v < pinhole.height; ++v) {
    lens.Row(v, &xy);
    for (int u = 0; u < pinhole.width; ++u) {
      lens.Fill(xy[2 * u], xy[2 * u + 1], &tap);
      *dst++ = Sample(pinhole.pixels.data(), tap, dx, dy);
    }
  }
  return out;
}

void AddImageNoise(double sigma_grey, RandomStream& stream, GrayImage* image) {
  if (!(std::isfinite(sigma_grey) && sigma_grey >= 0.0)) {
    throw std::invalid_argument("AddImageNoise: sigma_grey: expected a finite value >= 0");
  }
  if (image == nullptr) throw std::invalid_argument("AddImageNoise: image is null");
  if (sigma_grey == 0.0) return;
  for (std::uint8_t& p : image->pixels) {
    const double noisy = std::clamp(p + stream.Normal(0.0, sigma_grey), 0.0, double{kMaxGrey});
    p = static_cast<std::uint8_t>(noisy + 0.5);
  }
}

}  // namespace pavilion::core
