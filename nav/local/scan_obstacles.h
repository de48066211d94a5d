#pragma once

// The obstacle points the local planner and the dynamic window see (thesis
// §6.3.4): every valid reading of the latest scan of each laser — no memory
// beyond it — plus the map's ghost points injected as virtual readings. Scans
// are kept in the odometry frame, which moves smoothly with the robot, so a
// scan taken a few ticks ago still lands where it was seen.
//
// The dynamic window also gets a short memory of the blind zones: a reading
// of the last `blind_memory_s` of motion that no laser's field of view covers
// now (the sides of a robot with two lasers back to back, §6.3.5.1) stays an
// obstacle, so that a robot turning through a door does not sweep its corner
// into the door post it saw a moment ago. The memory ages only while the
// robot moves (its odometry pose changed by a millimetre or a milliradian
// between two scans), for at most kBlindMemoryCapS of standing: Robox that
// stood blocked 10-15 s beside the foil-wrapped column of expo_hall forgot it
// and swung a corner into it when they turned, while without the cap a robot
// that stopped kept a passer-by beside it for good (docs/benchmarks.md, "The
// hour"). A remembered reading deeper than kGhostInsideM inside the robot's
// polygon is where the robot now stands: what was seen there has gone (a
// robot that pressed into the other's recess and drove off), and is left out
// (docs/benchmarks.md, "Remembered under the hull"). The local grid keeps to
// the thesis: no memory.
//
// Ghost points mark invisible barriers (§6.3.1: glass, a low plinth, an exit)
// with points a map spacing apart (0.25 m in the derived maps). A polygon
// corner fits between two of them: an octagon's 135° corner reaches 5 cm past
// points 25 cm apart, more than the dynamic window's safety margin. The thesis
// injects ghost points "as virtual sensor readings"; a laser would read such a
// barrier at every beam, so the dynamic window sees the barrier filled: ghost
// points closer than `GhostBarrier::link_m` are joined and the join sampled
// every `fill_m`. A ghost point is also only as good as the estimate that
// places it and the tape measure that surveyed it, while a laser reading is
// measured from the robot itself: barriers are drawn `clearance_m` thick on
// either side (two rows beside each join, a ring around each point), so the
// dynamic window keeps its safety margin plus clearance_m from them. The
// local grid, whose robot-circle dilation closes such gaps anyway, gets the
// map's points alone.
//
// The blind zones also get the map's solids: its segments and round columns
// (MapOutline), placed by the belief as ghost points are, where no laser's
// field of view covers them now and within kOutlineReachM of the hull. The
// memory of readings cannot tell a pedestal from a robot that has gone; the
// map can. A Robox blocked for half a minute crept at 5-18 mm/s along a
// pedestal whose face beside its flank no laser saw and the memory had
// forgotten, and touched it (docs/benchmarks.md, "Blind sides from the map").

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/map/robot_map.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::nav {

// How the dynamic window fills the gaps between neighbouring ghost points.
struct GhostBarrier {
  // Ghost points closer than this are one barrier, m, [0, 2] (0: points
  // alone). Chosen: above the derived maps' 0.25 m spacing, below their
  // diagonal 0.35 m and any robot's width.
  double link_m = 0.3;
  // The join is sampled at most this far apart, m, [0.005, 1]. Chosen: a
  // square corner then reaches fill_m / 2 = 1.5 cm past the barrier, inside
  // the dynamic window's 2 cm safety margin.
  double fill_m = 0.03;
  // Drawn this much thicker on either side, m, [0, 0.2]. Chosen: the
  // estimate's 2σ in the hall (about 1 cm) plus the map's 5 mm survey noise
  // and the 5 mm at which the simulator counts a contact.
  double clearance_m = 0.02;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The map's ghost points and, between every two closer than `barrier.link_m`,
// points every `barrier.fill_m` or less (each join once, in index order): on
// the join or, with clearance_m > 0, on its two sides clearance_m away
// instead, with a ring of kGhostRingPoints around each ghost point.
// The positions of the map's ghost points, in map order.
std::vector<Eigen::Vector2d> GhostPositions(const core::RobotMap& map);

inline constexpr int kGhostRingPoints = 8;
std::vector<Eigen::Vector2d> FillGhostBarriers(std::span<const Eigen::Vector2d> ghosts,
                                               const GhostBarrier& barrier);

// The map's solids as points at most `spacing_m` apart: its segments and
// multi-segment members, and the outlines of its points and beacons with a
// radius (columns). Like the ghost barriers, they are drawn `clearance_m`
// off the solid, on the side a laser sees it from (segments: eq. B.4's
// visibility; their ends get a ring of that radius; columns: a larger
// radius), since the belief that places them is a centimetre or two off
// (docs/benchmarks.md: a Robox 1.5 cm off turned its flank into a showcase's
// face). `spacing_m` > 0, `clearance_m` in [0, 0.2].
std::vector<Eigen::Vector2d> MapOutline(const core::RobotMap& map, double spacing_m,
                                        double clearance_m = 0.0);

// The map outline's spacing, m. Chosen: as GhostBarrier::fill_m, a corner
// then reaches 1.5 cm between two points, inside the window's 2 cm margin.
inline constexpr double kOutlineSpacingM = 0.03;
// Outline points farther than this from the robot's polygon (its
// circumradius plus this) are left out, m: the blind zones that matter lie
// alongside the hull, and farther out a laser sees the solid anyway.
inline constexpr double kOutlineReachM = 0.5;

// A remembered reading is dropped this long after its scan even if the robot
// has not moved since, s.
inline constexpr double kBlindMemoryCapS = 20.0;

// A ghost point deeper than this inside the robot's polygon cannot be where
// the belief puts it (the robot would stand on the glass): InRobot leaves it
// out, so that a belief a few centimetres off does not freeze the dynamic
// window (a point deeper than its max_contact_depth_m forces braking for
// good). The bumper still reports the real panel. m; the window's default
// contact depth.
inline constexpr double kGhostInsideM = 0.02;

class ScanObstacles {
 public:
  // `footprint_in_robot`: the robot's polygon; readings inside it (the robot
  // seeing itself) are dropped. `ghosts_in_world`: the map's ghost points.
  ScanObstacles(std::vector<Eigen::Vector2d> footprint_in_robot,
                std::vector<Eigen::Vector2d> ghosts_in_world, double blind_memory_s = 1.0,
                const GhostBarrier& barrier = {});

  // The map's solids (MapOutline) the blind zones get, in the world frame.
  void SetMapOutline(std::span<const Eigen::Vector2d> outline_in_world);

  // Replaces the points of `scan`'s laser; `odom_from_robot` is the robot's
  // odometry pose when the scan arrived.
  void AddScan(const core::LaserScan& scan, const core::Pose2& odom_from_robot);

  // The laser points, the remembered blind-zone points, the filled ghost
  // barriers and the blind zones' map outline within `reach_m` of the robot,
  // in the robot frame (the dynamic
  // window's input). `world_from_robot` is the belief, `odom_from_robot` the odometry
  // pose, both now. Without `map_outline` the blind zones get no map solids
  // (a robot that is not localized: its belief would misplace them).
  void InRobot(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
               double reach_m, std::vector<Eigen::Vector2d>* points_in_robot,
               bool map_outline = true) const;
  // Appends the filled ghost barriers within `reach_m` of the robot, placed
  // by `world_from_robot`, in the robot frame (InRobot's barriers; a robot
  // that is not localized places them by each pose it may be at).
  void AppendGhostBarriers(const core::Pose2& world_from_robot, double reach_m,
                           std::vector<Eigen::Vector2d>* points_in_robot) const;
  // Drops the remembered blind-zone readings of scans before `stamp_s` (the
  // deadlock rule's: NavigationController::GatherDrivePoints).
  void ForgetBefore(double stamp_s);
  // The same within `reach_m` of the robot in the world frame (the local grid's input).
  void InWorld(const core::Pose2& odom_from_robot, const core::Pose2& world_from_robot,
               double reach_m, std::vector<Eigen::Vector2d>* points_in_world) const;

  std::size_t laser_points() const;

 private:
  struct LaserPoints {
    std::string sensor_id;
    std::vector<Eigen::Vector2d> in_odom;
    core::Pose2 sensor_from_robot;  // its mount, inverted once per scan
    // sensor_from_robot's rotation, its cosine and sine taken once per scan.
    core::PointTransform sensor_from_robot_points{core::Pose2{}};
    double min_bearing_rad = 0.0;  // the scan's field of view
    double max_bearing_rad = 0.0;
    double max_range_m = 0.0;
    // The field of view as a cone about its middle bearing, for Covered() to
    // decide most points without an arctangent: a point whose bearing is
    // more than kConeMarginRad inside (outside) the cone is in (out of) it;
    // only those nearer its edges take atan2. `cone` false when the view is
    // not one cone within atan2's (-π, π] (then every point takes atan2).
    bool cone = false;
    Eigen::Vector2d cone_axis{1.0, 0.0};
    double cos_surely_inside = 1.0;   // cos(half-width - margin)
    double cos_surely_outside = 1.0;  // cos(half-width + margin)
    double remembered_s = -1e9;       // motion clock of its last scan kept in memory_
    double stamp_s = 0.0;             // the time of the scan in_odom holds
  };
  struct Remembered {
    double stamp_s = 0.0;  // on the motion clock
    double taken_s = 0.0;  // scan time
    std::vector<Eigen::Vector2d> in_odom;
  };
  // True when a map point or remembered reading lies deeper than
  // kGhostInsideM inside the robot's polygon (robot frame).
  bool UnderRobot(const Eigen::Vector2d& q) const;
  // True when a laser's current field of view covers the point (robot frame).
  bool Covered(const Eigen::Vector2d& point_in_robot) const;
  static void SetCone(LaserPoints* laser);

  // Points in square buckets of kBucketM, row-major over origin .. + size * kBucketM.
  struct Buckets {
    static constexpr double kBucketM = 1.0;
    std::vector<std::vector<Eigen::Vector2d>> cells;
    Eigen::Vector2d origin = Eigen::Vector2d::Zero();
    Eigen::Vector2i size = Eigen::Vector2i::Zero();  // buckets along x, y

    explicit Buckets(std::span<const Eigen::Vector2d> points = {});
    // Calls visit(p) for every point within `reach_m` of `centre`.
    template <typename Visit>
    void ForEachNear(const Eigen::Vector2d& centre, double reach_m, Visit&& visit) const;
  };

  std::vector<Eigen::Vector2d> footprint_;
  bool footprint_convex_ = false;  // the ghost test of kGhostInsideM needs a convex polygon
  double footprint_radius_m_ = 0.0;
  std::vector<Eigen::Vector2d> ghosts_in_world_;
  Buckets barriers_;  // FillGhostBarriers(ghosts_in_world_)
  Buckets outline_;   // SetMapOutline's points
  double blind_memory_s_;
  // The motion clock: scan time during which the robot moved.
  double motion_clock_s_ = 0.0;
  std::optional<std::pair<double, core::Pose2>> last_scan_;  // stamp and odometry pose
  std::vector<LaserPoints> lasers_;
  std::vector<Remembered> memory_;  // earlier scans (thinned), oldest first
};

// Distance (m) from a convex polygon to the nearest of `points` (0 for a point
// inside it); +infinity without points.
double PolygonClearance(std::span<const Eigen::Vector2d> polygon,
                        std::span<const Eigen::Vector2d> points);

}  // namespace pavilion::nav
