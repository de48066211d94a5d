#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/raycast/laser_hit_finder.h"
#include "sim/world/world.h"

namespace pavilion::sim {

struct PlanarCasterOptions {
  // Largest tilt of a scanner's beam plane (its robot pitched or rolled, e.g.
  // in a collision) for which the plane is cast in 2D; beyond it the scan's
  // readings of that tick are cast with Bullet (a fallback). Cylinders tilted
  // up to it are cut as circles, beyond it as ellipses. [0, π/4] rad; default 1°.
  double max_tilt_rad = 0.017453292519943295;
  // Edge of the uniform grid's cells (m), [0.05, 10]. Measured in expo_hall
  // (tests/bench/laser_bench.cc, 361-beam scans, 10 robots, 100 legs, CPU
  // time on a shared machine): 0.25 m 5.2 M rays/s, 0.5 m 7.5 M, 1 m 7.0–8.6 M,
  // 2 m 8.5 M — see planar_caster.cc for the choice.
  double cell_size_m = 0.5;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The world cut by one horizontal beam plane z = height_m, as a hit finder:
// the static elements' outlines (sliced once, again when a door moves) and the
// dynamic bodies' cross-sections (circles, convex polygons at their current
// transforms, refreshed once per tick), in uniform grids walked cell by cell
// along each ray (DDA). Intersections are exact in double precision; hits
// carry the element indices, points and normals World::CastRay would report.
// Transparent elements are left out; a ray starting inside a solid does not
// hit it (as World::CastRay). Mesh cuts are two-sided (open triangle meshes are
// hit from both sides in Bullet too), outlines of solids one-sided.
class PlanarSlice final : public LaserHitFinder {
 public:
  PlanarSlice(const World& world, double height_m, const PlanarCasterOptions& options);

  double height_m() const { return height_m_; }
  // Casts in this plane whatever the z of origin_m; the hit's point is at
  // origin_m's z. Not thread-safe while the slice is being updated.
  RayHit Cast(const Eigen::Vector3d& origin_m, const Eigen::Vector2d& direction, double max_range_m,
              int ignore_group) const override;
  const std::vector<core::SectionElement>& elements() const override;
  // The intersections are exact and the walk stops only past the range: yes.
  bool ShortRaysAgree() const override { return true; }
  // True when no dynamic element that the plane does not cut exactly (a
  // cylinder, box or chassis cut through its top or bottom) lies within
  // radius_m of center_m, the ignored group's aside:
  // then rays from center_m up to radius_m long are exact here.
  bool Covers(const Eigen::Vector2d& center_m, double radius_m, int ignore_group) const;

  // Re-slices the static geometry (doors in their current state).
  void UpdateStatic();
  // Re-cuts the dynamic bodies at their current transforms.
  void UpdateDynamic();

 private:
  struct Segment {
    Eigen::Vector2d a_m;
    Eigen::Vector2d edge_m;  // b - a; the solid is on its left
    int element = -1;
    int group = -1;
    bool two_sided = false;
    // In a cell's span: one past the last of the consecutive segments of
    // this one's group (Fill), for rays to skip their own robot's outline.
    int group_run_end = 0;
  };
  struct Circle {
    Eigen::Vector2d center_m;
    double radius_m = 0.0;
    double radius_sq = 0.0;
    int element = -1;
    int group = -1;
    // An ellipse (a tilted cylinder's cut, core::SectionCircle): squash < 1
    // along major_axis; radius_m / squash bounds it.
    Eigen::Vector2d major_axis{1.0, 0.0};
    double squash = 1.0;
  };
  // A cell's primitives: segments [segment_begin, segment_end), circles
  // [circle_begin, circle_end) of its Buckets; the four read together by the
  // walk (one load per cell and grid).
  struct CellSpans {
    int segment_begin = 0;
    int segment_end = 0;
    int circle_begin = 0;
    int circle_end = 0;
  };
  // Primitives bucketed by cell, in the order they were given.
  struct Buckets {
    std::vector<CellSpans> cells;
    std::vector<int> touched;  // the cells holding any, in first-touch order

    // Empties the cells the last fill touched (all of them on a new grid size).
    void Clear(int cell_count);
    // Turns the touched cells' counts (held in their ends) into begins, and
    // sizes the primitive arrays for them.
    void CountsToBegins();
    std::vector<Segment> segments;
    std::vector<Circle> circles;
  };
  struct Best;
  // An ellipse's frame scaled to its circle: v's component along the major
  // axis times the squash.
  static Eigen::Vector2d Unsquash(const Circle& c, const Eigen::Vector2d& v);
  // The hit `best` found, in the plane z = z_m.
  static RayHit ToHit(const Best& best, double z_m);

  void SetUpGrid(const core::PlanarSection& statics);
  void Fill(const std::vector<Segment>& segments, const std::vector<Circle>& circles,
            Buckets* buckets, std::vector<Segment>* outside_segments,
            std::vector<Circle>* outside_circles) const;
  bool CellRange(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, int* x0, int* y0, int* x1,
                 int* y1) const;
  void Split(const core::PlanarSection& section, bool statics, std::vector<Segment>* segments,
             std::vector<Circle>* circles) const;

  const World& world_;
  double height_m_;
  PlanarCasterOptions options_;
  int first_mesh_element_ = 0;
  int mesh_elements_ = 0;
  // The grid: cell (ix, iy) spans origin + cell·[ix, ix+1] × cell·[iy, iy+1].
  Eigen::Vector2d origin_m_{0, 0};
  double cell_m_ = 1.0;
  double inv_cell_ = 1.0;
  int nx_ = 1;
  int ny_ = 1;
  Buckets static_;
  Buckets dynamic_;
  // Dynamic primitives reaching beyond the grid: tested by every ray.
  std::vector<Segment> outside_segments_;
  std::vector<Circle> outside_circles_;
  std::vector<UncutElement> uncut_;
};

// Planar laser casting for the scanners of one world: one PlanarSlice per
// distinct beam height, kept up to date with the world.
class PlanarCaster {
 public:
  // `world` must outlive the caster. Throws std::invalid_argument for bad options.
  PlanarCaster(const World* world, PlanarCasterOptions options);

  const PlanarCasterOptions& options() const { return options_; }
  // Brings every slice to the world's current state: dynamic cross-sections
  // when the world has stepped since, static outlines when a door moved.
  // Cheap when nothing changed. Not thread-safe: bring the slices up to date
  // before the casts of a tick fan out. After moving bodies without a step
  // (a teleport), call Refresh().
  void Update();
  void Refresh();
  // The slice at a beam height, built on first use; calls Update() first.
  // Once the slices of every height in use exist and Update() has run after
  // the tick's step, SliceAt changes nothing and the slices are read-only:
  // scanners may then cast from several threads (the scenario runner's
  // worker pool). Rays are counted by the scanners (LaserScanner::rays_cast),
  // not here, so that casting writes nothing shared.
  const PlanarSlice& SliceAt(double height_m);

 private:
  const World* world_;
  PlanarCasterOptions options_;
  std::map<double, std::unique_ptr<PlanarSlice>> slices_;
  std::int64_t tick_ = -1;
  std::int64_t static_revision_ = 0;
};

}  // namespace pavilion::sim
