#include "sim/crowd/social_force.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

namespace pavilion::sim::crowd {
namespace {

// Side of the square cells that bin walls and agents, m: a little over a
// person's reach (diameter plus the long-range cutoff).
constexpr double kCellM = 1.2;
// Extra distance (m) kept in the contact lists beyond what agents can close
// at their capped speeds before the next refresh.
constexpr double kSkinMarginM = 0.1;
// The largest person radius the wall bins allow for, m.
constexpr double kMaxPersonRadiusM = 0.4;
// Slack on a lower bound of a distance against rounding (m).
constexpr double kGapBoundSlackM = 1e-9;

void Require(bool ok, const char* field, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("social_force.") + field + " " + what);
}

Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }

// The restitution of a head-on contact of damping ratio ζ whose force is
// held at zero rather than pull (a contact only pushes): in units of the
// spring's natural frequency and the approach speed, g'' = -(g + 2 ζ g')
// while that is a push; the body leaves with the speed it has when the push
// ends. (The linear damper's exp(-π ζ / √(1 - ζ²)) ignores the hold and
// gives back more: 0.32 for a ζ meant for 0.2.)
double RestitutionOf(double zeta) {
  constexpr double kH = 1e-3;  // of a period of 2π
  double g = 0.0, v = 1.0;
  const auto accel = [zeta](double gg, double vv) { return -(gg + 2.0 * zeta * vv); };
  for (int step = 0; step < 100000; ++step) {
    // Classical Runge-Kutta on (g, v).
    const double a1 = accel(g, v);
    const double a2 = accel(g + 0.5 * kH * v, v + 0.5 * kH * a1);
    const double a3 = accel(g + 0.5 * kH * (v + 0.5 * kH * a1), v + 0.5 * kH * a2);
    const double a4 = accel(g + kH * (v + 0.5 * kH * a2), v + kH * a3);
    g += kH * (v + kH * (a1 + a2 + a3) / 6.0);
    v += kH * (a1 + 2.0 * a2 + 2.0 * a3 + a4) / 6.0;
    if (g <= 0.0 || g + 2.0 * zeta * v <= 0.0) return std::max(0.0, -v);
  }
  return 0.0;
}

// The damping ratio whose contact gives back `restitution` (bisection; the
// restitution falls as ζ grows, towards 0 only as ζ → ∞: 0 is taken as ζ = 10,
// which gives back under 1 %).
double ContactDampingRatio(double restitution) {
  constexpr double kMaxZeta = 10.0;
  if (restitution >= 1.0) return 0.0;
  double lo = 0.0, hi = kMaxZeta;
  if (RestitutionOf(hi) >= restitution) return hi;
  for (int k = 0; k < 50; ++k) {
    const double mid = 0.5 * (lo + hi);
    (RestitutionOf(mid) > restitution ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

void SocialForceOptions::Validate() const {
  const auto in = [](double v, double lo, double hi) {
    return std::isfinite(v) && v >= lo && v <= hi;
  };
  Require(in(relaxation_s, 1e-3, 10), "relaxation_s", "must be in (0, 10]");
  Require(in(person_strength_n, 0, 1e5), "person_strength_n", "must be in [0, 1e5]");
  Require(in(person_range_m, 1e-4, 5), "person_range_m", "must be in (0, 5]");
  Require(in(anisotropy, 0, 1), "anisotropy", "must be in [0, 1]");
  Require(in(wall_strength_n, 0, 1e5), "wall_strength_n", "must be in [0, 1e5]");
  Require(in(wall_range_m, 1e-4, 5), "wall_range_m", "must be in (0, 5]");
  Require(in(robot_strength_n, 0, 1e5), "robot_strength_n", "must be in [0, 1e5]");
  Require(in(robot_range_m, 1e-4, 5), "robot_range_m", "must be in (0, 5]");
  Require(in(body_stiffness_npm, 0, 1e7), "body_stiffness_npm", "must be in [0, 1e7]");
  Require(in(sliding_friction_nspm2, 0, 1e7), "sliding_friction_nspm2", "must be in [0, 1e7]");
  Require(in(max_speed_factor, 1, 5), "max_speed_factor", "must be in [1, 5]");
  Require(in(social_rate_hz, 1e-3, 1000), "social_rate_hz", "must be in (0, 1000]");
  Require(in(social_cutoff_m, 1e-3, 10), "social_cutoff_m", "must be in (0, 10]");
  Require(in(max_substep_s, 1e-5, 0.05), "max_substep_s", "must be in (0, 0.05]");
  Require(in(max_push_force_n, 0, 1e4), "max_push_force_n", "must be in [0, 1e4]");
  Require(in(contact_restitution, 0, 1), "contact_restitution", "must be in [0, 1]");
}

Eigen::Vector2d ClosestPointOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                      const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return a;
  const double s = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + s * ab;
}

double SignedDistanceToConvex(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p,
                              Eigen::Vector2d* normal, Eigen::Vector2d* closest) {
  double best = std::numeric_limits<double>::infinity();
  bool inside = hull.size() >= 3;
  double least_depth = std::numeric_limits<double>::infinity();
  Eigen::Vector2d depth_normal{1, 0};
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d& b = hull[(i + 1) % hull.size()];
    const Eigen::Vector2d c = ClosestPointOnSegment(p, a, b);
    const double d = (p - c).norm();
    if (d < best) {
      best = d;
      *closest = c;
    }
    // Counter-clockwise: the outward normal is the edge direction turned -90°.
    const Eigen::Vector2d edge = b - a;
    const double len = edge.norm();
    if (len <= 0.0) continue;
    const Eigen::Vector2d outward(edge.y() / len, -edge.x() / len);
    const double side = (p - a).dot(outward);
    if (side > 0.0) inside = false;
    if (-side < least_depth) {
      least_depth = -side;
      depth_normal = outward;
    }
  }
  if (inside) {
    *normal = depth_normal;
    *closest = p + least_depth * depth_normal;
    return -least_depth;
  }
  *normal = best > 0.0 ? Eigen::Vector2d((p - *closest) / best) : depth_normal;
  return best;
}

SocialForceModel::SocialForceModel(SocialForceOptions options) : options_(options) {
  options_.Validate();
  contact_damping_ratio_ = ContactDampingRatio(options_.contact_restitution);
}

void SocialForceModel::SetWalls(std::vector<WallSegment> segments,
                                std::vector<WallCircle> circles) {
  segments_ = std::move(segments);
  std::stable_sort(segments_.begin(), segments_.end(),
                   [](const WallSegment& a, const WallSegment& b) { return a.group < b.group; });
  circles_ = std::move(circles);
  BuildWallGrid();
  Invalidate();
}

void SocialForceModel::SetPeriodicX(double min_x_m, double length_m) {
  periodic_min_x_m_ = min_x_m;
  periodic_length_m_ = length_m > 0.0 ? length_m : 0.0;
  Invalidate();
}

void SocialForceModel::SetRobots(std::vector<RobotObstacle> robots) {
  robots_ = std::move(robots);
  // The fastest a point of each hull moves: its translation plus the turn of
  // its farthest point from the reference.
  robot_sweep_mps_.clear();
  robot_reach_m_.clear();
  for (const RobotObstacle& robot : robots_) {
    double reach = 0.0;
    for (const Eigen::Vector2d& v : robot.hull_m)
      reach = std::max(reach, (v - robot.center_m).norm());
    robot_sweep_mps_.push_back(robot.velocity_mps.norm() + std::abs(robot.yaw_rate_radps) * reach);
    robot_reach_m_.push_back(reach);
  }
}

void SocialForceModel::BuildWallGrid() {
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const WallSegment& s : segments_) {
    lo = lo.cwiseMin(s.a_m).cwiseMin(s.b_m);
    hi = hi.cwiseMax(s.a_m).cwiseMax(s.b_m);
  }
  for (const WallCircle& c : circles_) {
    const Eigen::Vector2d r(c.radius_m, c.radius_m);
    lo = lo.cwiseMin(c.center_m - r);
    hi = hi.cwiseMax(c.center_m + r);
  }
  cell_segments_.clear();
  cell_circles_.clear();
  if (!(lo.x() <= hi.x())) {
    wall_grid_cols_ = wall_grid_rows_ = 0;
    return;
  }
  const double reach = kMaxPersonRadiusM + options_.social_cutoff_m + 1.0;
  wall_grid_min_m_ = lo.array() - reach;
  wall_grid_cols_ = static_cast<int>(std::ceil((hi.x() - lo.x() + 2 * reach) / kCellM)) + 1;
  wall_grid_rows_ = static_cast<int>(std::ceil((hi.y() - lo.y() + 2 * reach) / kCellM)) + 1;
  const std::size_t cells = static_cast<std::size_t>(wall_grid_cols_) * wall_grid_rows_;
  cell_segments_.assign(cells, {});
  cell_circles_.assign(cells, {});
  // A cell lists a wall when the wall comes within reach of any point of it.
  const double half_diagonal = kCellM * std::numbers::sqrt2 / 2;
  for (int row = 0; row < wall_grid_rows_; ++row) {
    for (int col = 0; col < wall_grid_cols_; ++col) {
      const Eigen::Vector2d center =
          wall_grid_min_m_ + kCellM * Eigen::Vector2d(col + 0.5, row + 0.5);
      const std::size_t cell = static_cast<std::size_t>(row) * wall_grid_cols_ + col;
      for (std::size_t s = 0; s < segments_.size(); ++s) {
        const double d =
            (center - ClosestPointOnSegment(center, segments_[s].a_m, segments_[s].b_m)).norm();
        if (d <= reach + half_diagonal) cell_segments_[cell].push_back(static_cast<int>(s));
      }
      for (std::size_t c = 0; c < circles_.size(); ++c) {
        const double d = (center - circles_[c].center_m).norm() - circles_[c].radius_m;
        if (d <= reach + half_diagonal) cell_circles_[cell].push_back(static_cast<int>(c));
      }
    }
  }
}

void SocialForceModel::RefreshSocial() {
  const SocialForceOptions& o = options_;
  const std::size_t n = agents_.size();
  social_force_n_.assign(n, Eigen::Vector2d::Zero());
  near_pairs_.clear();
  near_robots_.clear();
  near_segments_.resize(n);
  near_circles_.resize(n);
  for (auto& v : near_segments_) v.clear();
  for (auto& v : near_circles_) v.clear();
  // How far agents (and robots) can close in before the next refresh.
  double fastest = 0.0;
  for (const Agent& a : agents_) {
    if (a.active) fastest = std::max(fastest, o.max_speed_factor * a.free_speed_mps);
  }
  const double period = 1.0 / o.social_rate_hz;
  const double skin = kSkinMarginM + 2.0 * fastest * period;

  BinAgents();
  for (std::size_t k = 0; k < n; ++k) {
    const int i = static_cast<int>(k);
    if (!agents_[i].active) continue;
    social_force_n_[i] = PeopleForce(i, skin) + WallForce(i, skin) + RobotForce(i, skin, period);
  }
  since_social_s_ = 0.0;
}

void SocialForceModel::BinAgents() {
  const std::size_t n = agents_.size();
  const bool periodic = periodic_length_m_ > 0.0;
  // Bin the active agents (counting sort by cell).
  Eigen::Vector2d lo(std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const Agent& a : agents_) {
    if (!a.active) continue;
    lo = lo.cwiseMin(a.position_m);
    hi = hi.cwiseMax(a.position_m);
  }
  const bool any = lo.x() <= hi.x();
  // A periodic domain is binned whole, in at least three columns that wrap.
  double cell_w = kCellM;
  if (periodic) {
    lo.x() = periodic_min_x_m_;
    cell_w = periodic_length_m_ / std::max(3, static_cast<int>(periodic_length_m_ / kCellM));
  }
  const int cols = !any       ? 0
                   : periodic ? static_cast<int>(std::lround(periodic_length_m_ / cell_w))
                              : static_cast<int>((hi.x() - lo.x()) / cell_w) + 1;
  const int rows = any ? static_cast<int>((hi.y() - lo.y()) / kCellM) + 1 : 0;
  cell_start_.assign(static_cast<std::size_t>(cols) * rows + 1, 0);
  agent_cell_.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (!agents_[i].active) continue;
    const int col =
        std::min(cols - 1, static_cast<int>((agents_[i].position_m.x() - lo.x()) / cell_w));
    const int row = static_cast<int>((agents_[i].position_m.y() - lo.y()) / kCellM);
    agent_cell_[i] = row * cols + col;
    ++cell_start_[agent_cell_[i] + 1];
  }
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_agents_.assign(cell_start_.back(), -1);
  {
    std::vector<int> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      if (agent_cell_[i] >= 0) cell_agents_[fill[agent_cell_[i]]++] = static_cast<int>(i);
    }
  }

  bin_cols_ = cols;
  bin_rows_ = rows;
}

Eigen::Vector2d SocialForceModel::PeopleForce(int i, double skin) {
  const SocialForceOptions& o = options_;
  const Agent& a = agents_[i];
  const bool periodic = periodic_length_m_ > 0.0;
  const int cols = bin_cols_, rows = bin_rows_;
  Eigen::Vector2d f = Eigen::Vector2d::Zero();
  // The walker's heading, for the anisotropy: where it wants to go.
  Eigen::Vector2d heading = a.desired_velocity_mps;
  if (heading.squaredNorm() < 1e-12) heading = a.velocity_mps;
  const double heading_norm = heading.norm();
  const bool has_heading = heading_norm > 1e-6;
  if (has_heading) heading /= heading_norm;
  // People (HFV00 with the HMFB01 field of view).
  const int col = agent_cell_[i] % cols;
  const int row = agent_cell_[i] / cols;
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      const int r = row + dr;
      int c = col + dc;
      if (periodic) c = (c + cols) % cols;
      if (r < 0 || c < 0 || r >= rows || c >= cols) continue;
      const int cell = r * cols + c;
      for (int k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
        const int j = cell_agents_[k];
        if (j == i) continue;
        const Agent& b = agents_[j];
        const Eigen::Vector2d diff = Separation(a.position_m, b.position_m);
        const double d = diff.norm();
        const double gap = d - (a.radius_m + b.radius_m);
        if (gap < skin && i < j) near_pairs_.emplace_back(i, j);
        if (gap > o.social_cutoff_m || d <= 0.0) continue;
        const Eigen::Vector2d normal = diff / d;
        const double cos_phi = has_heading ? -normal.dot(heading) : 1.0;
        const double w = o.anisotropy + (1.0 - o.anisotropy) * 0.5 * (1.0 + cos_phi);
        f += o.person_strength_n * w * std::exp(-gap / o.person_range_m) * normal;
      }
    }
  }
  return f;
}

Eigen::Vector2d SocialForceModel::WallForce(int i, double skin) {
  const SocialForceOptions& o = options_;
  const Agent& a = agents_[i];
  Eigen::Vector2d f = Eigen::Vector2d::Zero();
  // Walls: the nearest segment of each obstacle, and circles.
  const int wc = static_cast<int>(std::floor((a.position_m.x() - wall_grid_min_m_.x()) / kCellM));
  const int wr = static_cast<int>(std::floor((a.position_m.y() - wall_grid_min_m_.y()) / kCellM));
  if (wc >= 0 && wr >= 0 && wc < wall_grid_cols_ && wr < wall_grid_rows_) {
    const std::size_t cell = static_cast<std::size_t>(wr) * wall_grid_cols_ + wc;
    const std::vector<int>& segs = cell_segments_[cell];
    for (std::size_t s = 0; s < segs.size();) {
      const std::size_t first = s;
      Eigen::Vector2d best_point{0, 0};
      const double best = NearestOfObstacle(a.position_m, segs, &s, &best_point);
      for (std::size_t k = first; k < s; ++k) {
        const WallSegment& w = segments_[segs[k]];
        const double d = (a.position_m - ClosestPointOnSegment(a.position_m, w.a_m, w.b_m)).norm();
        if (d - a.radius_m < skin) near_segments_[i].push_back(segs[k]);
      }
      const double gap = best - a.radius_m;
      if (gap <= o.social_cutoff_m && best > 0.0) {
        f += o.wall_strength_n * std::exp(-gap / o.wall_range_m) * (a.position_m - best_point) /
             best;
      }
    }
    for (int ci : cell_circles_[cell]) {
      const WallCircle& w = circles_[ci];
      const Eigen::Vector2d diff = a.position_m - w.center_m;
      const double d = diff.norm();
      const double gap = d - w.radius_m - a.radius_m;
      if (gap < skin) near_circles_[i].push_back(ci);
      if (gap <= o.social_cutoff_m && d > 0.0) {
        f += o.wall_strength_n * std::exp(-gap / o.wall_range_m) * diff / d;
      }
    }
  }
  return f;
}

Eigen::Vector2d SocialForceModel::RobotForce(int i, double skin, double period) {
  const SocialForceOptions& o = options_;
  const Agent& a = agents_[i];
  Eigen::Vector2d f = Eigen::Vector2d::Zero();
  // Robots, seen all around.
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    const RobotObstacle& robot = robots_[r];
    const double robot_speed = robot_sweep_mps_[r];
    const double near_gap_m = skin + 2.0 * robot_speed * period;
    const double force_gap_m = o.social_cutoff_m + o.robot_range_m * 4;
    // The hull lies within its reach of the centre: a lower bound of the gap
    // beyond both limits skips the exact distance (the same result).
    const double gap_bound_m =
        (a.position_m - robot.center_m).norm() - robot_reach_m_[r] - a.radius_m - kGapBoundSlackM;
    if (gap_bound_m > near_gap_m && gap_bound_m > force_gap_m) continue;
    Eigen::Vector2d normal, closest;
    const double d = SignedDistanceToConvex(robot.hull_m, a.position_m, &normal, &closest);
    const double gap = d - a.radius_m;
    if (gap < near_gap_m) near_robots_.emplace_back(static_cast<int>(r), i);
    if (gap <= force_gap_m && a.approached_robot != static_cast<int>(r)) {
      f += o.robot_strength_n * std::exp(-std::max(gap, 0.0) / o.robot_range_m) * normal;
    }
  }
  return f;
}

double SocialForceModel::NearestOfObstacle(const Eigen::Vector2d& p, const std::vector<int>& segs,
                                           std::size_t* s, Eigen::Vector2d* nearest) const {
  const int group = segments_[segs[*s]].group;
  double best = std::numeric_limits<double>::infinity();
  for (; *s < segs.size() && segments_[segs[*s]].group == group; ++*s) {
    const WallSegment& w = segments_[segs[*s]];
    const Eigen::Vector2d c = ClosestPointOnSegment(p, w.a_m, w.b_m);
    const double d = (p - c).norm();
    if (d < best) {
      best = d;
      *nearest = c;
    }
  }
  return best;
}

Eigen::Vector2d SocialForceModel::Separation(const Eigen::Vector2d& from,
                                             const Eigen::Vector2d& to) const {
  Eigen::Vector2d d = from - to;
  if (periodic_length_m_ > 0.0) {  // the nearest image
    d.x() -= periodic_length_m_ * std::round(d.x() / periodic_length_m_);
  }
  return d;
}

Eigen::Vector2d SocialForceModel::ContactForce(const Agent& a, const Eigen::Vector2d& normal,
                                               double overlap,
                                               const Eigen::Vector2d& surface_velocity,
                                               double dt) const {
  const Eigen::Vector2d tangent = Perp(normal);
  const Eigen::Vector2d relative = surface_velocity - a.velocity_mps;
  // Sliding friction κ g Δv_t, at most what stops the relative sliding in one
  // step (the implicit limit: it never reverses it).
  const double c = std::min(options_.sliding_friction_nspm2 * overlap, a.mass_kg / dt);
  // The body force k g, damped along the normal (contact_restitution) by
  // 2 ζ √(k m) with the same implicit limit; a contact only pushes.
  const double damping =
      std::min(2.0 * contact_damping_ratio_ * std::sqrt(options_.body_stiffness_npm * a.mass_kg),
               a.mass_kg / dt);
  const double push =
      std::max(0.0, options_.body_stiffness_npm * overlap + damping * relative.dot(normal));
  return push * normal + c * relative.dot(tangent) * tangent;
}

void SocialForceModel::Substep(double dt, std::vector<RobotContactForce>* robot_forces,
                               double weight) {
  const SocialForceOptions& o = options_;
  const std::size_t n = agents_.size();
  force_.assign(n, Eigen::Vector2d::Zero());
  held_.assign(n, Eigen::Vector2d::Zero());
  touched_.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Agent& a = agents_[i];
    if (!a.active) continue;
    force_[i] =
        social_force_n_[i] + a.mass_kg * (a.desired_velocity_mps - a.velocity_mps) / o.relaxation_s;
  }
  PeopleContacts(dt);
  WallContacts(dt);
  RobotContacts(dt, weight, robot_forces);
  Integrate(dt);
}

void SocialForceModel::PeopleContacts(double dt) {
  const SocialForceOptions& o = options_;
  // Body force and sliding friction between people (HFV00), equal and opposite.
  for (const auto& [i, j] : near_pairs_) {
    Agent& a = agents_[i];
    Agent& b = agents_[j];
    if (!a.active || !b.active) continue;
    const Eigen::Vector2d diff = Separation(a.position_m, b.position_m);
    const double d = diff.norm();
    const double overlap = a.radius_m + b.radius_m - d;
    if (overlap <= 0.0 || d <= 0.0) continue;
    Overlap(0, overlap);
    const Eigen::Vector2d normal = diff / d;
    const Eigen::Vector2d tangent = Perp(normal);
    const double reduced_mass = a.mass_kg * b.mass_kg / (a.mass_kg + b.mass_kg);
    const double c = std::min(o.sliding_friction_nspm2 * overlap, reduced_mass / dt);
    const Eigen::Vector2d f = o.body_stiffness_npm * overlap * normal +
                              c * (b.velocity_mps - a.velocity_mps).dot(tangent) * tangent;
    force_[i] += f;
    force_[j] -= f;
    held_[i] += f;
    held_[j] -= f;
    touched_[i] = touched_[j] = 1;
  }
}

void SocialForceModel::WallContacts(double dt) {
  const std::size_t n = agents_.size();
  // Walls: per obstacle, the deepest contact.
  for (std::size_t i = 0; i < n; ++i) {
    const Agent& a = agents_[i];
    if (!a.active) continue;
    const std::vector<int>& segs = near_segments_[i];
    for (std::size_t s = 0; s < segs.size();) {
      Eigen::Vector2d best_point{0, 0};
      const double best = NearestOfObstacle(a.position_m, segs, &s, &best_point);
      const double overlap = a.radius_m - best;
      if (overlap > 0.0 && best > 0.0) {
        Overlap(1, overlap);
        touched_[i] = 1;
        const Eigen::Vector2d f =
            ContactForce(a, (a.position_m - best_point) / best, overlap, {0, 0}, dt);
        force_[i] += f;
        held_[i] += f;
      }
    }
    for (int ci : near_circles_[i]) {
      const WallCircle& w = circles_[ci];
      const Eigen::Vector2d diff = a.position_m - w.center_m;
      const double d = diff.norm();
      const double overlap = w.radius_m + a.radius_m - d;
      if (overlap > 0.0 && d > 0.0) {
        Overlap(1, overlap);
        touched_[i] = 1;
        const Eigen::Vector2d f = ContactForce(a, diff / d, overlap, {0, 0}, dt);
        force_[i] += f;
        held_[i] += f;
      }
    }
  }
}

void SocialForceModel::RobotContacts(double dt, double weight,
                                     std::vector<RobotContactForce>* robot_forces) {
  const SocialForceOptions& o = options_;
  // Robots: the person feels the full body force of the machine; the machine
  // feels the person's push, bounded by what a person can exert, plus what
  // holds the person against it: the contact forces of walls, other people
  // and other robots on the person, as far as they push back against this
  // robot's push (Newton's third law through the person). A person pinned
  // hard against a wall passes the whole body force on (a robot cannot
  // squeeze a person flat); one who merely brushes a neighbour passes little
  // more than the push. (Passing the whole force on at any touch threw a
  // Robox that drove into a visitor brushing others against its wheels'
  // grip, expo_rush session 30.) The other robots' contacts count, so that
  // two robots squeezing a person both meet the other's push; judged robot by
  // robot, the first robot felt a bounded push and drove on while the second
  // took the whole spring (expo_tours seed 5: a visitor between two Robox
  // tipped one by 17 deg).
  robot_contacts_.clear();
  std::vector<RobotTouch>& touches = robot_touches_;
  touches.clear();
  for (const auto& [r, i] : near_robots_) {
    if (static_cast<std::size_t>(r) >= robots_.size()) continue;
    const RobotObstacle& robot = robots_[r];
    const Agent& a = agents_[i];
    if (!a.active) continue;
    Eigen::Vector2d normal, closest;
    const double d = SignedDistanceToConvex(robot.hull_m, a.position_m, &normal, &closest);
    const double overlap = a.radius_m - d;
    if (overlap <= 0.0) continue;
    Overlap(2, overlap);
    const Eigen::Vector2d arm = closest - robot.center_m;
    const Eigen::Vector2d surface_velocity = robot.velocity_mps + robot.yaw_rate_radps * Perp(arm);
    touches.push_back({r, i, ContactForce(a, normal, overlap, surface_velocity, dt), closest});
  }
  // What holds a person against robot touch t: the person's other contacts
  // (people touching more than one robot are few: a scan of the few touches).
  const auto holding = [&](const RobotTouch& t) {
    Eigen::Vector2d held = held_[t.person];
    for (const RobotTouch& other : touches) {
      if (other.person == t.person && &other != &t) held += other.force_n;
    }
    const double push = t.force_n.norm();
    return push > 0.0 ? std::max(0.0, -held.dot(t.force_n) / push) : 0.0;
  };
  for (const RobotTouch& t : touches) {
    const double held_n = holding(t);
    force_[t.person] += t.force_n;
    robot_contacts_.emplace_back(t.person, t.robot);
    if (robot_forces) {
      Eigen::Vector2d on_robot = -t.force_n;
      const double magnitude = on_robot.norm();
      const double bound = o.max_push_force_n + held_n;
      if (magnitude > bound) on_robot *= bound / magnitude;
      robot_forces->push_back({t.robot, t.person, weight * on_robot, t.closest_m, held_n > 0.0});
    }
  }
  for (const RobotTouch& t : touches) touched_[t.person] = 1;
}

void SocialForceModel::Integrate(double dt) {
  const SocialForceOptions& o = options_;
  const std::size_t n = agents_.size();
  // Semi-implicit Euler with HM95's speed cap.
  for (std::size_t i = 0; i < n; ++i) {
    Agent& a = agents_[i];
    if (!a.active) continue;
    a.velocity_mps += force_[i] * (dt / a.mass_kg);
    // Walkers stop for what lies ahead but do not back away from it: the
    // anisotropic repulsion is not reciprocal, and in a jam its sum would
    // otherwise push the whole crowd backwards (Lakoba, Kaup & Finkelstein
    // 2005 discuss this defect of the model). Body contact still can.
    const double wish = a.desired_velocity_mps.norm();
    if (wish > 0.0 && !touched_[i]) {
      const Eigen::Vector2d e0 = a.desired_velocity_mps / wish;
      const double along = a.velocity_mps.dot(e0);
      if (along < 0.0) a.velocity_mps -= along * e0;
    }
    const double cap = o.max_speed_factor * a.free_speed_mps;
    const double speed = a.velocity_mps.norm();
    if (speed > cap) a.velocity_mps *= cap / speed;
    a.position_m += a.velocity_mps * dt;
    if (periodic_length_m_ > 0.0) {
      a.position_m.x() =
          periodic_min_x_m_ +
          std::fmod(std::fmod(a.position_m.x() - periodic_min_x_m_, periodic_length_m_) +
                        periodic_length_m_,
                    periodic_length_m_);
    }
  }
}

void SocialForceModel::Step(double dt, std::vector<RobotContactForce>* robot_forces) {
  if (!(dt > 0.0)) return;
  const int substeps = std::max(1, static_cast<int>(std::ceil(dt / options_.max_substep_s - 1e-9)));
  const double h = dt / substeps;
  max_overlap_m_ = {0.0, 0.0, 0.0};
  const std::size_t first_force = robot_forces ? robot_forces->size() : 0;
  for (int s = 0; s < substeps; ++s) {
    if (since_social_s_ >= 1.0 / options_.social_rate_hz - 1e-9) RefreshSocial();
    Substep(h, robot_forces, 1.0 / substeps);
    since_social_s_ += h;
  }
  if (!robot_forces || substeps == 1) return;
  // One entry per robot and agent: the step's mean force.
  std::map<std::pair<int, int>, RobotContactForce> merged;
  for (std::size_t k = first_force; k < robot_forces->size(); ++k) {
    const RobotContactForce& f = (*robot_forces)[k];
    auto [it, fresh] = merged.try_emplace({f.robot, f.agent}, f);
    if (!fresh) {
      it->second.force_n += f.force_n;
      it->second.point_m = f.point_m;
      it->second.pinned = it->second.pinned || f.pinned;
    }
  }
  robot_forces->resize(first_force);
  for (const auto& [key, f] : merged) robot_forces->push_back(f);
}

}  // namespace pavilion::sim::crowd
