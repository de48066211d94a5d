#pragma once

// Off-screen pictures of the simulated world for the robots' cameras: Mesa's
// OSMesa (llvmpipe, no display, no GPU) rasterizes the world's flat-shaded
// triangles (sim/render/scene_triangles.h) through an ideal pinhole.
// No GL type appears here.

#include <Eigen/Geometry>
#include <memory>

#include "core/features/camera_model.h"
#include "core/types/image.h"
#include "sim/render/scene_triangles.h"
#include "sim/world/world.h"

namespace pavilion::sim {

// Where a camera is and what it images. The camera frame looks along +x with
// y to the left and z up (core/features/camera_model.h); a point (x, y, z) of
// it lands on the pinhole image at u = c_u - f y / x, v = c_v - f z / x, and
// pixel (u, v) shows the surface through its centre (u + 0.5, v + 0.5).
// `intrinsics.radial` is ignored: the picture is the undistorted pinhole
// image (core::DistortImage adds the lens).
struct RenderView {
  Eigen::Isometry3d world_from_camera = Eigen::Isometry3d::Identity();
  core::CameraIntrinsics intrinsics;
  double near_m = 0.05;  // nearest depth drawn, m, > 0
  double far_m = 60.0;   // farthest depth drawn, m, > near_m

  // Throws std::invalid_argument naming the field: finite pose, focal length
  // > 0, finite principal point, image size in [1, kMaxImageSidePx], depths.
  void Validate() const;
};

// Largest image side the renderer draws, px.
inline constexpr int kMaxImageSidePx = 4096;

// llvmpipe's rasterizer threads (LP_NUM_THREADS). Mesa 22.3's llvmpipe has
// one rasterizer per process, shared by every context behind a mutex: 0
// rasterizes in the calling thread, N > 0 adds N threads that rasterize the
// frames of every context. On one core the count makes no difference (640 x
// 480 expo_hall frames, render_bench pinned to a core: 3.2 ms with 0, 1 or 2
// threads); on several cores, threads > 0 let the rasterization of one frame
// use them. 0 (the default) starts no thread beyond the caller's. Pictures
// are bit-identical for every count.
inline constexpr int kDefaultLlvmpipeThreads = 0;

// Sets llvmpipe's thread count (LP_NUM_THREADS, and GALLIUM_DRIVER=llvmpipe)
// for the process. Mesa reads them once, when the first context is created:
// call before any OffscreenRenderer exists (else kDefaultLlvmpipeThreads is
// set then). Throws std::invalid_argument for threads outside [0, 32] and
// std::logic_error for a different count after the first context.
void ConfigureLlvmpipe(int threads);
// The count in force (or to be set at the first context).
int LlvmpipeThreads();

// One OSMesa context (RGBA, 24-bit depth) and its colour buffer, sized by
// each call. The world's static parts (floor, walls, boxes, cylinders, meshes)
// are compiled into display lists once per world; doors, bodies, people and
// robots are drawn at their state of each call. Pictures are deterministic:
// the same world state and view give the same bytes, from any renderer
// instance and thread. Each call makes the context current on the calling
// thread and releases it before returning, so a renderer may move between
// threads, one call at a time. Renderers on different threads may render
// concurrently (tested under Mesa 22.3: no process-wide lock needed); their
// rasterization shares llvmpipe's one rasterizer (see kDefaultLlvmpipeThreads).
// The world is only read, and must not be stepped during a call.
class OffscreenRenderer {
 public:
  // Creates the context; throws std::runtime_error when OSMesa cannot.
  OffscreenRenderer();
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // The world seen from `view`, rows top to bottom. Throws
  // std::invalid_argument for a bad view, std::runtime_error for GL errors.
  core::RgbImage RenderRgb(const World& world, const RenderView& view,
                           const RenderScene& scene = {});
  // The same picture in grey levels: round(0.299 R + 0.587 G + 0.114 B).
  core::GrayImage RenderGray(const World& world, const RenderView& view,
                             const RenderScene& scene = {});

  // Triangles of the last call (static and dynamic), a performance figure.
  std::size_t last_triangle_count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The pose of a camera on a robot: the robot's base pose on the floor
// composed with the camera link's mount (yaw after pitch after roll, URDF rpy).
Eigen::Isometry3d WorldFromMount(const core::Pose2& world_from_base, const MountSpec& mount);

}  // namespace pavilion::sim
