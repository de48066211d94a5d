#include "sim/render/offscreen_renderer.h"

// clang-format off
#include <GL/osmesa.h>
#include <GL/gl.h>
// clang-format on

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace pavilion::sim {
namespace {

constexpr int kMaxLlvmpipeThreads = 32;
constexpr int kDepthBits = 24;

// Process-wide llvmpipe set-up: Mesa creates one pipe screen, reading
// LP_NUM_THREADS, at the first OSMesa context of the process.
struct LlvmpipeState {
  std::mutex mutex;
  int threads = kDefaultLlvmpipeThreads;
  bool screen_created = false;
};

LlvmpipeState& Llvmpipe() {
  static LlvmpipeState state;
  return state;
}

// Creates a context, setting the environment first if this is the first.
OSMesaContext CreateContext() {
  LlvmpipeState& lp = Llvmpipe();
  std::lock_guard<std::mutex> lock(lp.mutex);
  if (!lp.screen_created) {
    setenv("GALLIUM_DRIVER", "llvmpipe", 1);
    setenv("LP_NUM_THREADS", std::to_string(lp.threads).c_str(), 1);
  }
  OSMesaContext context = OSMesaCreateContextExt(OSMESA_RGBA, kDepthBits, 0, 0, nullptr);
  if (context == nullptr) {
    throw std::runtime_error(
        "OffscreenRenderer: OSMesa could not create an RGBA context with a 24-bit depth buffer "
        "(is Mesa's libOSMesa with llvmpipe installed?)");
  }
  lp.screen_created = true;
  return context;
}

// GL's projection of the camera: the eye frame (x right, y up, looking along
// -z) is the camera frame (x forward, y left, z up) turned, and the frustum
// maps u = c_u - f y / x to window x = u and v = c_v - f z / x to window
// y = H - v (GL's rows run bottom up; the buffer is read top down). Window
// coordinates and image coordinates share pixel centres at half integers.
Eigen::Matrix4d ProjectionMatrix(const RenderView& view) {
  const core::CameraIntrinsics& c = view.intrinsics;
  const double w = c.width_px, h = c.height_px, f = c.focal_px;
  const double n = view.near_m, fa = view.far_m;
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = 2.0 * f / w;
  p(0, 2) = 1.0 - 2.0 * c.center_u_px / w;
  p(1, 1) = 2.0 * f / h;
  p(1, 2) = 2.0 * c.center_v_px / h - 1.0;
  p(2, 2) = -(fa + n) / (fa - n);
  p(2, 3) = -2.0 * fa * n / (fa - n);
  p(3, 2) = -1.0;
  return p;
}

Eigen::Matrix4d EyeFromWorld(const RenderView& view) {
  Eigen::Matrix4d eye_from_camera = Eigen::Matrix4d::Zero();
  eye_from_camera(0, 1) = -1.0;  // x_eye = -y
  eye_from_camera(1, 2) = 1.0;   // y_eye = z
  eye_from_camera(2, 0) = -1.0;  // z_eye = -x
  eye_from_camera(3, 3) = 1.0;
  return eye_from_camera * view.world_from_camera.inverse(Eigen::Isometry).matrix();
}

void SetArrays(const std::vector<ShadedVertex>& v) {
  glVertexPointer(3, GL_FLOAT, sizeof(ShadedVertex), &v[0].x);
  glColorPointer(4, GL_UNSIGNED_BYTE, sizeof(ShadedVertex), v[0].rgba.data());
}

void DrawList(const std::vector<ShadedVertex>& v) {
  if (v.empty()) return;
  SetArrays(v);
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(v.size()));
}

// Opaque solids with back faces culled, then two-sided meshes.
void DrawOpaque(const TriangleLists& lists) {
  glEnable(GL_CULL_FACE);
  DrawList(lists.opaque);
  glDisable(GL_CULL_FACE);
  DrawList(lists.two_sided);
}

void DrawTranslucent(const std::vector<ShadedVertex>& v) {
  glEnable(GL_CULL_FACE);
  DrawList(v);
}

// Luminance (ITU-R BT.601) in thousandths, 299 R + 587 G + 114 B, with the
// 500 that rounds half up folded into the red table: exact integers.
struct LumaTables {
  std::array<std::uint32_t, 256> r, g, b;
};

const LumaTables& Luma() {
  static const LumaTables tables = [] {
    LumaTables t;
    for (std::uint32_t c = 0; c < 256; ++c) {
      t.r[c] = 299u * c + 500u;
      t.g[c] = 587u * c;
      t.b[c] = 114u * c;
    }
    return t;
  }();
  return tables;
}

void Require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("RenderView.") + field + " " + what);
}

}  // namespace

void RenderView::Validate() const {
  Require(world_from_camera.matrix().allFinite(), "world_from_camera", "must be finite");
  const core::CameraIntrinsics& c = intrinsics;
  Require(c.width_px >= 1 && c.width_px <= kMaxImageSidePx, "intrinsics.width_px",
          "must be in [1, 4096]");
  Require(c.height_px >= 1 && c.height_px <= kMaxImageSidePx, "intrinsics.height_px",
          "must be in [1, 4096]");
  Require(std::isfinite(c.focal_px) && c.focal_px > 0.0, "intrinsics.focal_px",
          "must be finite and > 0");
  Require(std::isfinite(c.center_u_px) && std::isfinite(c.center_v_px), "intrinsics.center",
          "must be finite");
  Require(std::isfinite(near_m) && near_m > 0.0, "near_m", "must be finite and > 0");
  Require(std::isfinite(far_m) && far_m > near_m, "far_m", "must be finite and > near_m");
}

void ConfigureLlvmpipe(int threads) {
  if (threads < 0 || threads > kMaxLlvmpipeThreads) {
    throw std::invalid_argument("ConfigureLlvmpipe: threads must be in [0, 32]");
  }
  LlvmpipeState& lp = Llvmpipe();
  std::lock_guard<std::mutex> lock(lp.mutex);
  if (lp.screen_created && threads != lp.threads) {
    throw std::logic_error("ConfigureLlvmpipe: llvmpipe already runs with " +
                           std::to_string(lp.threads) +
                           " threads (set before the first OffscreenRenderer)");
  }
  lp.threads = threads;
}

int LlvmpipeThreads() {
  LlvmpipeState& lp = Llvmpipe();
  std::lock_guard<std::mutex> lock(lp.mutex);
  return lp.threads;
}

struct OffscreenRenderer::Impl {
  OSMesaContext context = nullptr;
  std::vector<std::uint8_t> buffer;  // RGBA, rows top down (OSMESA_Y_UP off)
  int width = 0;
  int height = 0;

  // Static geometry of the world last drawn, in display lists.
  const World* world = nullptr;
  std::uint64_t digest = 0;
  GLuint lists = 0;  // lists: opaque, translucent
  std::size_t static_triangles = 0;
  bool static_translucent = false;

  TriangleLists dynamic;  // reused per call
  std::size_t last_triangles = 0;

  void Render(const World& world, const RenderView& view, const RenderScene& scene);
  void UpdateStatic(const World& world);
  void SetState(const RenderView& view, const RenderScene& scene);
};

void OffscreenRenderer::Impl::UpdateStatic(const World& w) {
  const std::uint64_t d = StaticSceneDigest(w.description());
  if (lists != 0 && world == &w && digest == d) return;
  TriangleLists tris;
  AppendStaticScene(w.description(), &tris);
  if (lists == 0) lists = glGenLists(2);
  if (lists == 0) throw std::runtime_error("OffscreenRenderer: glGenLists failed");
  glNewList(lists, GL_COMPILE);
  DrawOpaque(tris);
  glEndList();
  glNewList(lists + 1, GL_COMPILE);
  DrawTranslucent(tris.translucent);
  glEndList();
  world = &w;
  digest = d;
  static_triangles = tris.triangle_count();
  static_translucent = !tris.translucent.empty();
}

void OffscreenRenderer::Impl::SetState(const RenderView& view, const RenderScene& scene) {
  glViewport(0, 0, width, height);
  glDisable(GL_DITHER);
  glDisable(GL_LIGHTING);
  glDisable(GL_BLEND);
  glShadeModel(GL_FLAT);
  glFrontFace(GL_CCW);
  glCullFace(GL_BACK);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixd(ProjectionMatrix(view).data());
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixd(EyeFromWorld(view).data());
  const auto& bg = scene.background_rgb;
  glClearColor(bg[0] / 255.0f, bg[1] / 255.0f, bg[2] / 255.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void OffscreenRenderer::Impl::Render(const World& w, const RenderView& view,
                                     const RenderScene& scene) {
  view.Validate();
  const int wpx = view.intrinsics.width_px, hpx = view.intrinsics.height_px;
  if (wpx != width || hpx != height) {
    buffer.assign(static_cast<std::size_t>(wpx) * hpx * 4, 0);
    width = wpx;
    height = hpx;
  }
  if (!OSMesaMakeCurrent(context, buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
    throw std::runtime_error("OffscreenRenderer: OSMesaMakeCurrent failed");
  }
  struct Release {
    ~Release() { OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0); }
  } release;
  OSMesaPixelStore(OSMESA_Y_UP, 0);
  dynamic.Clear();
  AppendDynamicScene(w, scene, &dynamic);
  SetState(view, scene);  // enables the client arrays the lists compile from
  UpdateStatic(w);
  glCallList(lists);
  DrawOpaque(dynamic);
  if (static_translucent || !dynamic.translucent.empty()) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glCallList(lists + 1);
    DrawTranslucent(dynamic.translucent);
  }
  glFinish();
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    throw std::runtime_error("OffscreenRenderer: GL error " + std::to_string(error));
  }
  last_triangles = static_triangles + dynamic.triangle_count();
}

OffscreenRenderer::OffscreenRenderer() : impl_(std::make_unique<Impl>()) {
  impl_->context = CreateContext();
}

OffscreenRenderer::~OffscreenRenderer() {
  if (impl_->context != nullptr) OSMesaDestroyContext(impl_->context);
}

core::RgbImage OffscreenRenderer::RenderRgb(const World& world, const RenderView& view,
                                            const RenderScene& scene) {
  impl_->Render(world, view, scene);
  core::RgbImage image(impl_->width, impl_->height);
  const std::uint8_t* src = impl_->buffer.data();
  std::uint8_t* dst = image.pixels.data();
  const std::size_t n = static_cast<std::size_t>(impl_->width) * impl_->height;
  for (std::size_t i = 0; i < n; ++i, src += 4, dst += 3) {
    dst[0] = src[0];
    dst[1] = src[1];
    dst[2] = src[2];
  }
  return image;
}

core::GrayImage OffscreenRenderer::RenderGray(const World& world, const RenderView& view,
                                              const RenderScene& scene) {
  impl_->Render(world, view, scene);
  core::GrayImage image(impl_->width, impl_->height);
  const std::uint8_t* src = impl_->buffer.data();
  const std::size_t n = static_cast<std::size_t>(impl_->width) * impl_->height;
  const LumaTables& t = Luma();
  for (std::size_t i = 0; i < n; ++i, src += 4) {
    image.pixels[i] = static_cast<std::uint8_t>((t.r[src[0]] + t.g[src[1]] + t.b[src[2]]) / 1000u);
  }
  return image;
}

std::size_t OffscreenRenderer::last_triangle_count() const { return impl_->last_triangles; }

Eigen::Isometry3d WorldFromMount(const core::Pose2& world_from_base, const MountSpec& mount) {
  const Eigen::Isometry3d base =
      Eigen::Translation3d(world_from_base.x_m, world_from_base.y_m, 0) *
      Eigen::AngleAxisd(world_from_base.theta_rad, Eigen::Vector3d::UnitZ());
  const Eigen::Isometry3d link = Eigen::Translation3d(mount.pose.x_m, mount.pose.y_m, mount.z_m) *
                                 Eigen::AngleAxisd(mount.pose.theta_rad, Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(mount.pitch_rad, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(mount.roll_rad, Eigen::Vector3d::UnitX());
  return base * link;
}

}  // namespace pavilion::sim
