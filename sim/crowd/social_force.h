#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace pavilion::sim::crowd {

// Parameters of the social force model of pedestrian motion, with the source
// of each default:
//   HM95  D. Helbing, P. Molnár, "Social force model for pedestrian dynamics",
//         Phys. Rev. E 51 (1995) 4282.
//   HFV00 D. Helbing, I. Farkas, T. Vicsek, "Simulating dynamical features of
//         escape panic", Nature 407 (2000) 487 (the exponential repulsion,
//         body force and sliding friction used here).
//   HMFB01 D. Helbing, P. Molnár, I. Farkas, K. Bolay, "Self-organizing
//         pedestrian movement", Env. Planning B 28 (2001) 361 (anisotropy λ).
//   W93   U. Weidmann, "Transporttechnik der Fussgänger", ETH Zürich (1993):
//         free speed 1.34 m/s.
//
// Each person i obeys m_i dv_i/dt = m_i (v0_i e0_i - v_i)/τ + Σ_j f_ij + Σ_W f_iW
// + Σ_R f_iR, with for any neighbour at centre distance d along the unit
// normal n (pointing to i), radius sum r, overlap g = max(0, r - d) and the
// unit tangent t:
//   f = [A w(φ) exp((r - d)/B) + k g] n + κ g (Δv_t) t          (HFV00)
// where w(φ) = λ + (1 - λ)(1 + cos φ)/2 weighs what lies ahead of the walker
// more than what lies behind (HMFB01; people only: walls and robots are seen
// all around), and Δv_t is the neighbour's tangential velocity relative to i.
//
// Time stepping: the long-range (exponential) forces change over the 0.5 s
// relaxation time and are recomputed at social_rate_hz; the stiff contact
// forces (k, κ) and the driving term are evaluated at every step of the
// caller (the physics rate) with semi-implicit Euler. With k = 1.2e5 kg/s² and
// m = 80 kg the contact oscillator has ω = √(k/m) = 39 rad/s, so a 5 ms step
// gives ω dt = 0.19, far inside the method's stability limit of 2; steps
// longer than max_substep_s are subdivided, and the sliding friction of one
// substep is capped so that it never reverses a relative tangential velocity
// (its implicit limit).
struct SocialForceOptions {
  double relaxation_s =
      0.5;  // τ: how fast a walker regains its desired velocity, s, HM95/HFV00, (0, 10]
  double person_strength_n = 2000.0;  // A between people, N, HFV00, [0, 1e5]
  double person_range_m = 0.08;       // B between people, m, HFV00, (0, 5]
  // λ: the weight of a neighbour straight behind relative to one ahead, HMFB01
  // (0.1-0.3 fits observed walking; chosen with the fundamental-diagram test
  // against W93), [0, 1].
  double anisotropy = 0.2;
  double wall_strength_n = 2000.0;  // A for walls and exhibits, N, HFV00, [0, 1e5]
  double wall_range_m = 0.08;       // B for walls and exhibits, m, HFV00, (0, 5]
  // People keep more room from a moving machine than from each other (chosen:
  // Expo.02 visitors stepped aside for Robox, §6.5), N and m.
  double robot_strength_n = 2000.0;       // [0, 1e5]
  double robot_range_m = 0.2;             // (0, 5]
  double body_stiffness_npm = 1.2e5;      // k: body compression force, kg/s², HFV00, [0, 1e7]
  double sliding_friction_nspm2 = 2.4e5;  // κ: sliding friction, kg/(m s), HFV00, [0, 1e7]
  // The coefficient of restitution of a person's contact with a wall, an
  // exhibit or a robot, [0, 1]: the normal damping of that contact is set so
  // that a person meeting it head-on rebounds with this fraction of the
  // approach speed. 1 is HFV00's undamped spring, which gives back all it
  // stored: a Robox that drove 1 cm into a visitor held by others took the
  // spring's 1.2 kN at its wheels' 560 N grip and was thrown back, turned up
  // to 36° beyond what its encoders saw (expo_rush, session 30). A body gives
  // way and does not bounce (chosen: 0.2). Contacts between people stay
  // HFV00's, the model of the fundamental diagram.
  double contact_restitution = 0.2;
  double max_speed_factor = 1.3;  // a walker's speed stays below this times its v0, HM95, [1, 5]
  double social_rate_hz = 20.0;   // recomputation rate of the long-range forces, Hz, (0, 1000]
  // Neighbours whose surfaces are farther apart than this exert no long-range
  // force (A e^{-cutoff/B} = 0.7 N for people at the defaults), m, (0, 10].
  double social_cutoff_m = 0.6;
  double max_substep_s = 0.005;  // longest integration step, s, (0, 0.05]
  // The largest force a person's contact exerts on a robot: the bounded push of
  // a standing adult (chosen; ergonomic push limits are 200-300 N), N, [0, 1e4].
  double max_push_force_n = 300.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A wall face or exhibit side that people avoid (static); `group` joins the
// segments of one obstacle, of which only the nearest pushes a person.
struct WallSegment {
  Eigen::Vector2d a_m{0, 0};
  Eigen::Vector2d b_m{0, 0};
  int group = 0;
};

struct WallCircle {
  Eigen::Vector2d center_m{0, 0};
  double radius_m = 0.0;
};

// A robot as the crowd meets it: its convex footprint in the world frame
// (counter-clockwise) and its planar motion.
struct RobotObstacle {
  std::vector<Eigen::Vector2d> hull_m;
  Eigen::Vector2d center_m{0, 0};  // reference point of the velocities below
  Eigen::Vector2d velocity_mps{0, 0};
  double yaw_rate_radps = 0.0;
};

// The force a person's contact exerts on a robot over a step (world frame).
struct RobotContactForce {
  int robot = -1;
  int agent = -1;
  Eigen::Vector2d force_n{0, 0};
  Eigen::Vector2d point_m{0, 0};
  // The person was held by a wall, others or another robot: the force is
  // bounded by the push plus what holds the person, not by the push alone.
  bool pinned = false;
};

// One walker of the model: a disc with a mass and a wish.
struct Agent {
  Eigen::Vector2d position_m{0, 0};
  Eigen::Vector2d velocity_mps{0, 0};
  Eigen::Vector2d desired_velocity_mps{0, 0};  // v0 e0, set by whoever steers the agent
  double free_speed_mps = 1.34;                // v0 of the speed cap
  double radius_m = 0.22;
  double mass_kg = 80.0;
  bool active = false;  // inactive agents are parked: they neither move nor push
  // A robot this agent walks up to on purpose (a pusher, to push it): it feels
  // no long-range repulsion from it, only its body. -1: none.
  int approached_robot = -1;
};

// Integrates a set of agents among static walls and moving robots. Each call
// of Step() advances every active agent; contact forces on robots come back
// to the caller, who applies them to the robots' bodies. Deterministic: the
// same calls give the same states bit for bit.
class SocialForceModel {
 public:
  explicit SocialForceModel(SocialForceOptions options);

  const SocialForceOptions& options() const { return options_; }
  // Replaces the static obstacles (a door moved).
  void SetWalls(std::vector<WallSegment> segments, std::vector<WallCircle> circles);
  // The robots for the coming steps.
  void SetRobots(std::vector<RobotObstacle> robots);

  std::vector<Agent>& agents() { return agents_; }
  const std::vector<Agent>& agents() const { return agents_; }

  // Advances by dt seconds (subdivided by max_substep_s). Appends the contact
  // forces on robots, averaged over dt, to `robot_forces` when not null.
  void Step(double dt, std::vector<RobotContactForce>* robot_forces);

  // Forgets the cached long-range forces: they are recomputed at the next
  // step (call after teleporting or activating agents).
  void Invalidate() { since_social_s_ = kNever; }

  // A periodic domain along x (a corridor whose ends meet, for calibration):
  // agents leaving [min_x_m, min_x_m + length_m) re-enter at the other end and
  // feel each other across it. length_m <= 0 turns it off.
  void SetPeriodicX(double min_x_m, double length_m);

  // (agent, robot) pairs in contact during the last substep.
  const std::vector<std::pair<int, int>>& robot_contacts() const { return robot_contacts_; }
  // Largest overlap of an agent with another agent, a wall or a robot during
  // the last step (m): the interpenetration figure, and by what was overlapped.
  double max_overlap_m() const {
    return std::max({max_overlap_m_[0], max_overlap_m_[1], max_overlap_m_[2]});
  }
  double max_overlap_people_m() const { return max_overlap_m_[0]; }
  double max_overlap_walls_m() const { return max_overlap_m_[1]; }
  double max_overlap_robots_m() const { return max_overlap_m_[2]; }

 private:
  static constexpr double kNever = 1e300;

  // The long-range forces and the contact candidates, at the social rate.
  void RefreshSocial();
  void BinAgents();
  Eigen::Vector2d PeopleForce(int i, double skin);
  Eigen::Vector2d WallForce(int i, double skin);
  Eigen::Vector2d RobotForce(int i, double skin, double period);
  // One integration step: contact forces, then semi-implicit Euler.
  void Substep(double dt, std::vector<RobotContactForce>* robot_forces, double weight);
  void PeopleContacts(double dt);
  void WallContacts(double dt);
  void RobotContacts(double dt, double weight, std::vector<RobotContactForce>* robot_forces);
  void Integrate(double dt);
  // Contact force on agent i from a surface point at `normal` (pointing to i)
  // with overlap g and the surface's velocity there.
  Eigen::Vector2d ContactForce(const Agent& a, const Eigen::Vector2d& normal, double overlap,
                               const Eigen::Vector2d& surface_velocity, double dt) const;
  void BuildWallGrid();
  // The nearest point to p of the obstacle whose segments start at segs[*s]
  // (segments of one group are consecutive); advances *s past them and
  // returns the distance.
  double NearestOfObstacle(const Eigen::Vector2d& p, const std::vector<int>& segs, std::size_t* s,
                           Eigen::Vector2d* nearest) const;
  // from - to, across the periodic seam when that is shorter.
  Eigen::Vector2d Separation(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;

  SocialForceOptions options_;
  double contact_damping_ratio_ = 0.0;  // ζ of the contact_restitution
  std::vector<Agent> agents_;
  std::vector<WallSegment> segments_;
  std::vector<WallCircle> circles_;
  std::vector<RobotObstacle> robots_;
  std::vector<double> robot_sweep_mps_;  // by robot: the fastest a point of its hull moves
  std::vector<double> robot_reach_m_;    // by robot: its hull's farthest point from center_m
  // Walls binned into square cells, each listing the walls within reach of a
  // person standing in it (sorted: segments by group, then circles).
  Eigen::Vector2d wall_grid_min_m_{0, 0};
  int wall_grid_cols_ = 0, wall_grid_rows_ = 0;
  std::vector<std::vector<int>> cell_segments_;
  std::vector<std::vector<int>> cell_circles_;
  // Cached at the social rate.
  double since_social_s_ = kNever;
  std::vector<Eigen::Vector2d> social_force_n_;
  std::vector<std::pair<int, int>> near_pairs_;   // agents that may touch before the refresh
  std::vector<std::vector<int>> near_segments_;   // by agent
  std::vector<std::vector<int>> near_circles_;    // by agent
  std::vector<std::pair<int, int>> near_robots_;  // (robot, agent) that may touch
  double periodic_min_x_m_ = 0.0;
  double periodic_length_m_ = 0.0;
  // Agent grid scratch.
  std::vector<int> cell_start_, cell_agents_, agent_cell_;
  int bin_cols_ = 0, bin_rows_ = 0;
  // Substep scratch: forces, who is in body contact, the deepest overlap.
  std::vector<Eigen::Vector2d> force_;
  std::vector<Eigen::Vector2d> held_;  // the contact forces of walls and people, per substep
  std::vector<char> touched_;
  std::vector<std::pair<int, int>> robot_contacts_;
  // A person's contact with a robot in the current substep (RobotContacts).
  struct RobotTouch {
    int robot, person;
    Eigen::Vector2d force_n, closest_m;
  };
  std::vector<RobotTouch> robot_touches_;               // reused across substeps
  std::array<double, 3> max_overlap_m_{0.0, 0.0, 0.0};  // people, walls, robots
  void Overlap(int kind, double overlap_m) {
    max_overlap_m_[kind] = std::max(max_overlap_m_[kind], overlap_m);
  }
};

// Closest point of the segment [a, b] to p.
Eigen::Vector2d ClosestPointOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                      const Eigen::Vector2d& b);
// Signed distance from p to a convex counter-clockwise polygon (negative
// inside) and the unit normal pointing from the polygon to p.
double SignedDistanceToConvex(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p,
                              Eigen::Vector2d* normal, Eigen::Vector2d* closest);

}  // namespace pavilion::sim::crowd
