#include "sim/crowd/crowd.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <span>
#include <stdexcept>
#include <string>

#include "core/types/pose2.h"
#include "sim/crowd/episode_spot.h"
#include "sim/crowd/floor_field.h"
#include "sim/crowd/robot_avoidance.h"

namespace pavilion::sim::crowd {
namespace {

constexpr double kPi = std::numbers::pi;
// Goal discs: a visitor stops anywhere within this distance of an exhibit's
// station (so a dozen can look at it without standing on the robots' own
// station point), or of a watch spot, m (chosen).
constexpr double kStationDiscM = 1.2;
constexpr double kWatchDiscM = 0.8;
// A visitor slows down over this distance before a target, m (chosen).
constexpr double kArrivalSlowdownM = 0.6;
// Body headings turn towards the walking direction (or what a standing
// person looks at) with this time constant, s; below this speed (m/s) a
// person is standing.
constexpr double kHeadingTimeConstantS = 0.25;
constexpr double kStandingSpeedMps = 0.2;
// A walking visitor slower than this (m/s) for this long (s) within this
// walking distance of the goal (m) stops there: the goal is crowded (chosen).
constexpr double kStuckSpeedMps = 0.15;
constexpr double kStuckS = 2.0;
constexpr double kStuckNearGoalM = 4.0;
// ... and one that slow for this long (s) anywhere gives way: it stands and
// looks from where it is. Walking against a queue of leaving visitors in a
// 2 m corridor, one walker held 35 people for over ten minutes (expo_day seed
// 2, 1,680 s: the social force alone does not resolve a counter-flow jam).
// Chosen: five times kStuckS, longer than a crossing's wait.
constexpr double kStuckFarS = 10.0;
// Visitors who behave towards robots pick, with this chance, the watch spot
// nearest a robot as their next stop: they came to see the robots (§6.5).
constexpr double kSeekRobotChance = 0.5;
// Spawning: tries per visitor to find a free spot, and the gap kept to others (m).
constexpr int kSpawnTries = 40;
constexpr double kSpawnGapM = 0.1;
// Episodes: the half-angle of the crowders' U around a robot's front
// (episode_spot.h has where each behaviour stands).
constexpr double kCrowdHalfAngleRad = 100.0 * kPi / 180.0;
// A pusher pushes once its body is this close to the robot's hull (m).
constexpr double kPushReachM = 0.05;
// Blocked by a robot: wanting to walk (desired speed above the first figure,
// m/s) but slower than the second, within the distance (m) of a robot's hull.
constexpr double kBlockedWishMps = 0.3;
constexpr double kBlockedSpeedMps = 0.1;
constexpr double kBlockedRangeM = 1.0;
// Group cohesion: members farther than base + per-member times the group
// size from their group's centre are drawn back towards it (Moussaïd et al.
// 2010 model this as an attraction; chosen values).
constexpr double kGroupBaseRadiusM = 0.5;
constexpr double kGroupPerMemberM = 0.25;
constexpr double kGroupPull = 1.0;

void Require(bool ok, const std::string& field, const char* what) {
  if (!ok) throw std::invalid_argument(field + " " + what);
}

}  // namespace

// What a visitor is doing and plans to do.
struct Visitor {
  Activity activity = Activity::kParked;
  Behaviour behaviour = Behaviour::kOrdinary;
  int leader = -1;  // the party's leader (itself when alone or leading)
  int party_size = 1;
  std::vector<int> itinerary;  // attractions still to visit, next last
  int goal_field = -1;         // field followed while walking or leaving
  int goal_attraction = -1;    // the attraction walked to or dwelt at
  double until_s = 0.0;        // end of a dwell or watch
  double visit_end_s = 0.0;    // after it, the visitor leaves
  double desired_speed_mps = 1.34;
  // An episode near a robot.
  Activity resume = Activity::kWalking;
  int robot = -1;
  double episode_until_s = 0.0;
  double cooldown_until_s = 0.0;
  double slot_rad = 0.0;                 // crowding: the visitor's place in the U
  Eigen::Vector2d fixed_target_m{0, 0};  // blocking: where it stands
  bool kick = false;
  double push_until_s = -1.0;  // a push pulse lasts until then
  bool pushed = false;
  bool blocked_by_robot = false;
  double moving_since_s = 0.0;  // last time the visitor walked faster than kStuckSpeedMps
};

struct Crowd::Impl {
  const CrowdOptions& o;
  std::vector<PersonState>& people;
  CrowdSite site;
  SocialForceModel model;
  core::RandomStream arrivals_random;
  core::RandomStream visitor_random;
  std::unique_ptr<WalkableGrid> grid;
  // Routing fields: the attractions', the exit's, then the watch spots'.
  std::vector<DistanceField> fields;
  int exit_field = -1;
  int first_watch_field = 0;
  std::vector<Eigen::Vector2d> watch_spots;
  std::vector<double> attraction_cdf;  // cumulative weights
  std::vector<Visitor> visitors;
  std::span<const CrowdRobot> robots;                      // the caller's, during a step
  std::map<int, std::pair<Eigen::Vector2d, int>> parties;  // SumParties
  std::vector<RobotObstacle> obstacles;                    // the robots in the world frame
  std::vector<double> robot_reach_m;  // footprint circumradius about the base origin
  double next_arrival_s = 0.0;
  int waiting_party = 0;  // size of a party that found no room yet
  double since_decision_s = 1e300;
  std::int64_t arrivals = 0;
  std::int64_t departures = 0;
  std::int64_t pushes = 0;
  std::array<std::int64_t, 6> episodes{};  // by Behaviour
  int next_group = 0;

  Impl(const CrowdOptions& options, std::vector<PersonState>& pool, CrowdSite s, std::uint64_t seed)
      : o(options),
        people(pool),
        site(std::move(s)),
        model(options.social),
        arrivals_random(seed, core::RandomStream::StreamId("crowd.arrivals")),
        visitor_random(seed, core::RandomStream::StreamId("crowd.visitors")) {}

  // --- Routing --------------------------------------------------------------

  void BuildRoutes() {
    std::vector<ObstacleSegment> segments;
    std::vector<ObstacleCircle> circles;
    for (const WallSegment& w : site.walls) segments.push_back({w.a_m, w.b_m});
    for (const WallCircle& c : site.pillars) circles.push_back({c.center_m, c.radius_m});
    WalkableGridOptions grid_options;
    grid_options.cell_m = o.route_cell_m;
    grid_options.clearance_m = o.route_clearance_m;
    grid = std::make_unique<WalkableGrid>(site.floor_min_m, site.floor_max_m, segments, circles,
                                          grid_options);
    fields.clear();
    for (const Attraction& a : site.attractions) {
      fields.push_back(DistanceField::ToDisc(*grid, a.pose.translation(), kStationDiscM));
    }
    exit_field = static_cast<int>(fields.size());
    fields.push_back(DistanceField::ToArea(*grid, site.exit));
    first_watch_field = static_cast<int>(fields.size());
    for (const Eigen::Vector2d& p : watch_spots) {
      fields.push_back(DistanceField::ToDisc(*grid, p, kWatchDiscM));
    }
  }

  // A uniformly drawn free spot in `area` (the floor when empty) from which
  // the exit can be reached, at least a gap away from everyone present.
  bool FreeSpot(const core::Polygon2& area, double radius_m, Eigen::Vector2d* spot) {
    Eigen::Vector2d lo = site.floor_min_m, hi = site.floor_max_m;
    if (!area.empty()) {
      lo = hi = area.front();
      for (const Eigen::Vector2d& v : area) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
      }
    }
    for (int t = 0; t < kSpawnTries; ++t) {
      const Eigen::Vector2d p(visitor_random.Uniform(lo.x(), hi.x()),
                              visitor_random.Uniform(lo.y(), hi.y()));
      if (!area.empty() && !core::Contains(area, p)) continue;
      if (!grid->IsFree(p) || !fields[exit_field].Reachable(p)) continue;
      bool clear = true;
      for (const PersonState& q : people) {
        if (q.present && (q.position_m - p).norm() < q.shape.radius_m + radius_m + kSpawnGapM) {
          clear = false;
          break;
        }
      }
      for (const RobotObstacle& r : obstacles) {
        Eigen::Vector2d n, c;
        if (SignedDistanceToConvex(r.hull_m, p, &n, &c) < radius_m + kSpawnGapM) clear = false;
      }
      if (!clear) continue;
      *spot = p;
      return true;
    }
    return false;
  }

  // --- Draws ----------------------------------------------------------------

  std::vector<int> DrawItinerary(int count) {
    std::vector<int> picks;
    std::vector<double> cdf = attraction_cdf;
    for (int k = 0; k < count && !cdf.empty() && cdf.back() > 0.0; ++k) {
      const double u = visitor_random.Uniform(0.0, cdf.back());
      const auto pick = static_cast<int>(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin());
      if (pick >= static_cast<int>(cdf.size())) break;
      picks.push_back(pick);
      const double w = pick == 0 ? cdf[0] : cdf[pick] - cdf[pick - 1];  // without replacement
      for (std::size_t q = pick; q < cdf.size(); ++q) cdf[q] -= w;
    }
    return picks;
  }

  Behaviour DrawBehaviour() {
    const BehaviourOptions& b = o.behaviours;
    const double u = visitor_random.Uniform();
    double acc = 0.0;
    for (auto [fraction, kind] :
         {std::pair{b.curious, Behaviour::kCurious}, std::pair{b.crowding, Behaviour::kCrowding},
          std::pair{b.blocking, Behaviour::kBlocking},
          std::pair{b.following, Behaviour::kFollowing},
          std::pair{b.pushing, Behaviour::kPushing}}) {
      acc += fraction;
      if (u < acc) return kind;
    }
    return Behaviour::kOrdinary;
  }

  double DrawDwell() {
    return std::max(5.0, visitor_random.Normal(o.visit.dwell_mean_s, o.visit.dwell_std_s));
  }

  // --- The pool -------------------------------------------------------------

  int FreeBody() const {
    for (std::size_t i = 0; i < people.size(); ++i) {
      if (!people[i].present) return static_cast<int>(i);
    }
    return -1;
  }
  int Present() const {
    int n = 0;
    for (const PersonState& p : people) n += p.present ? 1 : 0;
    return n;
  }

  void Activate(int i, const Eigen::Vector2d& p, double heading_rad) {
    PersonState& s = people[i];
    s.present = true;
    s.position_m = p;
    s.velocity_mps.setZero();
    s.heading_rad = heading_rad;
    s.gait = Gait{};
    Agent& a = model.agents()[i];
    a.active = true;
    a.position_m = p;
    a.velocity_mps.setZero();
    a.desired_velocity_mps.setZero();
    a.free_speed_mps = visitors[i].desired_speed_mps;
    model.Invalidate();
  }

  void Park(int i) {
    PersonState& s = people[i];
    s.present = false;
    s.group = -1;
    s.velocity_mps.setZero();
    s.position_m = site.floor_min_m - Eigen::Vector2d(10.0 + i, 10.0);
    Agent& a = model.agents()[i];
    a.active = false;
    a.position_m = s.position_m;
    a.velocity_mps.setZero();
    visitors[i] = Visitor{};
    ++departures;
    model.Invalidate();
  }

  // Brings a party of `size` into `area` (or around `at`), at the start of its
  // visit or, when `mid_visit`, somewhere in it. Returns how many came in.
  int Arrive(double now, int size, const core::Polygon2& area, bool mid_visit) {
    const VisitOptions& v = o.visit;
    // The party shares a speed (the slowest member's, as groups walk) and an itinerary.
    double speed = std::numeric_limits<double>::infinity();
    for (int k = 0; k < size; ++k) {
      speed = std::min(speed, std::clamp(visitor_random.Normal(v.desired_speed_mean_mps,
                                                               v.desired_speed_std_mps),
                                         0.3, 2.5));
    }
    const double visit_s = std::max(60.0, visitor_random.Normal(v.visit_mean_s, v.visit_std_s));
    const int exhibits =
        static_cast<int>(visitor_random.UniformInt(v.min_exhibits, v.max_exhibits));
    std::vector<int> itinerary = DrawItinerary(
        mid_visit ? static_cast<int>(visitor_random.UniformInt(0, exhibits)) : exhibits);
    const double visit_end = now + (mid_visit ? visitor_random.Uniform(0.0, visit_s) : visit_s);
    const int group = size > 1 ? next_group++ : -1;
    int leader = -1, came = 0;
    for (int k = 0; k < size; ++k) {
      const int i = FreeBody();
      if (i < 0) break;
      Eigen::Vector2d p;
      if (!FreeSpot(area, people[i].shape.radius_m, &p)) break;
      Visitor& vis = visitors[i];
      vis = Visitor{};
      vis.leader = leader < 0 ? i : leader;
      if (leader < 0) leader = i;
      vis.party_size = size;
      vis.behaviour = DrawBehaviour();
      vis.desired_speed_mps = speed;
      vis.itinerary = itinerary;
      vis.visit_end_s = visit_end;
      // Everyone starts by choosing a goal at the next decision.
      vis.activity = Activity::kDwelling;
      vis.until_s = mid_visit ? now + visitor_random.Uniform(0.0, 20.0) : now;
      Activate(i, p, visitor_random.Uniform(-kPi, kPi));
      people[i].group = group;
      ++came;
      ++arrivals;
    }
    return came;
  }

  // --- Decisions ------------------------------------------------------------

  // After a dwell or a watch: the next attraction, a watch spot while the
  // visit lasts, or the exit. Party members follow their leader's choice.
  void NextGoal(int i, double now) {
    Visitor& v = visitors[i];
    v.moving_since_s = now;
    const int leader = v.leader;
    if (leader != i && people[leader].present && visitors[leader].activity != Activity::kParked) {
      const Visitor& l = visitors[leader];
      if (l.activity == Activity::kWalking || l.activity == Activity::kLeaving) {
        v.activity = l.activity;
        v.goal_field = l.goal_field;
        v.goal_attraction = l.goal_attraction;
      } else {
        v.until_s = l.until_s;  // wait with the leader
      }
      return;
    }
    if (!v.itinerary.empty() && now < v.visit_end_s) {  // a visit's time is its budget
      const int a = v.itinerary.back();
      v.itinerary.pop_back();
      if (!fields[a].Reachable(people[i].position_m)) return NextGoal(i, now);
      v.activity = Activity::kWalking;
      v.goal_field = a;
      v.goal_attraction = a;
      return;
    }
    const int spots = static_cast<int>(watch_spots.size());
    if (now < v.visit_end_s && spots > 0 && v.behaviour != Behaviour::kOrdinary &&
        !robots.empty() && now >= v.cooldown_until_s &&
        visitor_random.Uniform() < kSeekRobotChance) {
      const int w = WatchSpotNearestARobot(i);
      if (w >= 0) {
        v.activity = Activity::kWalking;
        v.goal_field = first_watch_field + w;
        v.goal_attraction = -1;
        return;
      }
    }
    if (now < v.visit_end_s && spots > 0) {
      const int w = static_cast<int>(visitor_random.UniformInt(0, spots - 1));
      if (fields[first_watch_field + w].Reachable(people[i].position_m)) {
        v.activity = Activity::kWalking;
        v.goal_field = first_watch_field + w;
        v.goal_attraction = -1;
        return;
      }
    }
    v.activity = Activity::kLeaving;
    v.goal_field = exit_field;
    v.goal_attraction = -1;
  }

  // The reachable watch spot closest to any robot, or -1.
  int WatchSpotNearestARobot(int i) const {
    int best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t w = 0; w < watch_spots.size(); ++w) {
      if (!fields[first_watch_field + w].Reachable(people[i].position_m)) continue;
      for (const CrowdRobot& r : robots) {
        const double d = (r.pose.translation() - watch_spots[w]).norm();
        if (d < best_d) {
          best_d = d;
          best = static_cast<int>(w);
        }
      }
    }
    return best;
  }

  // Each present party's member positions summed and counted, by group id:
  // once per decision, for PartyPull.
  void SumParties() {
    parties.clear();
    for (const PersonState& p : people) {
      if (!p.present || p.group < 0) continue;
      // (An Eigen vector is not zeroed by default construction.)
      auto [it, fresh] = parties.try_emplace(p.group, Eigen::Vector2d::Zero(), 0);
      it->second.first += p.position_m;
      ++it->second.second;
    }
  }

  // Drawn back towards the party's centre when farther than its size allows.
  Eigen::Vector2d PartyPull(int i) const {
    const auto it = parties.find(people[i].group);
    if (it == parties.end() || it->second.second < 2) return Eigen::Vector2d::Zero();
    const auto& [sum, n] = it->second;
    const Eigen::Vector2d to_centre = sum / n - people[i].position_m;
    const double slack = to_centre.norm() - (kGroupBaseRadiusM + kGroupPerMemberM * n);
    return slack > 0.0 ? Eigen::Vector2d(kGroupPull * slack * to_centre.normalized())
                       : Eigen::Vector2d::Zero();
  }

  Eigen::Vector2d AvoidRobots(int i, const Eigen::Vector2d& e, double goal_distance_m,
                              int ignore) const {
    return SteerAroundRobots(people[i].position_m, people[i].shape.radius_m,
                             visitors[i].desired_speed_mps, e, goal_distance_m, robots,
                             robot_reach_m, ignore);
  }

  // An episode's place near its robot (episode_spot.h); a pusher's is the
  // robot's nearest point.
  Eigen::Vector2d EpisodeTarget(int i, const Visitor& v) const {
    const Eigen::Vector2d& p = people[i].position_m;
    if (v.behaviour == Behaviour::kPushing) {
      Eigen::Vector2d n, closest;
      SignedDistanceToConvex(obstacles[v.robot].hull_m, p, &n, &closest);
      return closest;
    }
    return EpisodePlace(Floor(), v.behaviour, robots[v.robot].pose, robot_reach_m[v.robot],
                        v.slot_rad, v.fixed_target_m, p, people[i].shape.radius_m);
  }

  StandingFloor Floor() const { return {grid.get(), &fields[exit_field], obstacles}; }

  void MaybeStartEpisode(int i, double now) {
    Visitor& v = visitors[i];
    if (v.behaviour == Behaviour::kOrdinary || now < v.cooldown_until_s) return;
    if (v.activity == Activity::kLeaving || v.activity == Activity::kEpisode) return;
    int nearest = -1;
    double best = o.behaviours.notice_range_m;
    for (std::size_t r = 0; r < robots.size(); ++r) {
      const double d = (robots[r].pose.translation() - people[i].position_m).norm();
      if (d < best) {
        best = d;
        nearest = static_cast<int>(r);
      }
    }
    if (nearest < 0) return;
    v.resume = v.activity;
    v.activity = Activity::kEpisode;
    ++episodes[static_cast<std::size_t>(v.behaviour)];
    v.robot = nearest;
    const double mean = o.behaviours.episode_mean_s;
    v.episode_until_s = now + std::max(5.0, visitor_random.Normal(mean, mean / 3.0));
    v.slot_rad = visitor_random.Uniform(-kCrowdHalfAngleRad, kCrowdHalfAngleRad);
    const CrowdRobot& robot = robots[nearest];
    Eigen::Vector2d ahead(std::cos(robot.pose.theta_rad), std::sin(robot.pose.theta_rad));
    if (robot.velocity_mps.norm() > 0.05) ahead = robot.velocity_mps.normalized();
    v.fixed_target_m = BlockingPlace(Floor(), robot.pose.translation(), robot_reach_m[nearest],
                                     ahead, people[i].position_m, people[i].shape.radius_m);
    v.kick = visitor_random.Uniform() < 1.0 / 3.0;
    v.pushed = false;
  }

  void EndEpisode(int i, double now) {
    Visitor& v = visitors[i];
    v.activity = v.resume == Activity::kEpisode ? Activity::kWalking : v.resume;
    if (v.activity == Activity::kWalking && v.goal_field < 0) v.activity = Activity::kDwelling;
    v.robot = -1;
    v.cooldown_until_s = now + o.behaviours.cooldown_s;
  }

  // A walking speed towards a target at `distance`, slowing down before it.
  double Approach(const Visitor& v, double distance) const {
    return v.desired_speed_mps * std::clamp(distance / kArrivalSlowdownM, 0.0, 1.0);
  }

  // The velocity of an episode near a robot: towards the behaviour's place,
  // or a pusher's push once in reach.
  Eigen::Vector2d EpisodeVelocity(int i, double now) {
    Visitor& v = visitors[i];
    const Eigen::Vector2d to = EpisodeTarget(i, v) - people[i].position_m;
    const double d = to.norm();
    if (v.behaviour == Behaviour::kPushing) {
      Eigen::Vector2d n, c;
      const double gap =
          SignedDistanceToConvex(obstacles[v.robot].hull_m, people[i].position_m, &n, &c) -
          people[i].shape.radius_m;
      if (!v.pushed && gap <= kPushReachM) {
        v.pushed = true;
        ++pushes;
        v.push_until_s =
            now + (v.kick ? o.behaviours.kick_duration_s : o.behaviours.push_duration_s);
      }
      return v.pushed ? Eigen::Vector2d::Zero()
                      : Eigen::Vector2d(v.desired_speed_mps * to / std::max(d, 1e-9));
    } else if (d > 0.15) {
      // The episode's robot is avoided like any other: the place keeps a gap to it.
      const Eigen::Vector2d e = AvoidRobots(i, to / d, d, -1);
      return NotIntoRobots(people[i].position_m, people[i].shape.radius_m, Approach(v, d) * e,
                           obstacles);
    }
    return Eigen::Vector2d::Zero();
  }

  // Decides every present visitor's desired velocity for the coming period.
  void Decide(double now) {
    SumParties();
    for (std::size_t k = 0; k < people.size(); ++k) {
      const int i = static_cast<int>(k);
      if (!people[i].present) continue;
      Visitor& v = visitors[i];
      Agent& agent = model.agents()[i];
      MaybeStartEpisode(i, now);
      if (v.activity == Activity::kEpisode &&
          (now >= v.episode_until_s || v.robot >= static_cast<int>(robots.size()) ||
           (v.behaviour == Behaviour::kPushing && v.pushed && now >= v.push_until_s))) {
        EndEpisode(i, now);
      }
      if ((v.activity == Activity::kDwelling || v.activity == Activity::kWatching) &&
          now >= v.until_s) {
        NextGoal(i, now);
      }
      Eigen::Vector2d desired = Eigen::Vector2d::Zero();
      switch (v.activity) {
        case Activity::kWalking:
        case Activity::kLeaving: {
          const DistanceField& field = fields[v.goal_field];
          const double distance = field.Distance(people[i].position_m);
          if (v.activity == Activity::kLeaving && core::Contains(site.exit, people[i].position_m)) {
            Park(i);
            continue;
          }
          Eigen::Vector2d e = field.Direction(people[i].position_m);
          // Near a goal that others crowd (the visitor has made no way for a
          // while), a visitor looks from where they are instead of pressing on.
          const bool slow = people[i].velocity_mps.norm() < kStuckSpeedMps;
          if (!slow) v.moving_since_s = now;
          const bool stuck_near =
              v.activity == Activity::kWalking &&
              ((distance < kStuckNearGoalM && now - v.moving_since_s > kStuckS) ||
               now - v.moving_since_s > kStuckFarS);
          if ((e.squaredNorm() == 0.0 || stuck_near) && v.activity == Activity::kWalking) {
            // Arrived (inside the goal), as close as the crowd lets them, or
            // cut off: stand there for a while.
            const bool attraction = v.goal_attraction >= 0;
            v.activity = attraction ? Activity::kDwelling : Activity::kWatching;
            v.until_s = now + DrawDwell();
            break;
          }
          if (e.squaredNorm() == 0.0) {  // leaving, but the exit is out of reach: go
            Park(i);
            continue;
          }
          e = (e + PartyPull(i)).normalized();
          e = AvoidRobots(i, e, distance, -1);
          desired = NotIntoRobots(people[i].position_m, people[i].shape.radius_m,
                                  v.desired_speed_mps * e, obstacles);
          break;
        }
        case Activity::kEpisode:
          desired = EpisodeVelocity(i, now);
          break;
        case Activity::kDwelling:
        case Activity::kWatching:
        case Activity::kParked:
          break;
      }
      agent.desired_velocity_mps = desired;
      agent.free_speed_mps = v.desired_speed_mps;
      // Only a pusher walks up to its robot without keeping away from it.
      agent.approached_robot =
          v.activity == Activity::kEpisode && v.behaviour == Behaviour::kPushing ? v.robot : -1;
    }
  }

  // Where a standing visitor looks: the exhibit, or the robot of an episode.
  std::optional<Eigen::Vector2d> Gaze(int i) const {
    const Visitor& v = visitors[i];
    if (v.activity == Activity::kEpisode && v.robot >= 0 &&
        v.robot < static_cast<int>(robots.size())) {
      return robots[v.robot].pose.translation();
    }
    if (v.activity == Activity::kDwelling && v.goal_attraction >= 0) {
      const core::Pose2& station = site.attractions[v.goal_attraction].pose;
      // The exhibit lies ahead of its station, the way the station faces.
      return station.translation() +
             Eigen::Vector2d(std::cos(station.theta_rad), std::sin(station.theta_rad));
    }
    return std::nullopt;
  }

  // After the motion: body headings (the walking direction, or what a
  // standing person looks at), gaits, and who is blocked by a robot.
  void UpdateBodies(double dt) {
    const std::vector<Agent>& agents = model.agents();
    for (std::size_t k = 0; k < people.size(); ++k) {
      const int i = static_cast<int>(k);
      PersonState& s = people[i];
      if (!s.present) continue;
      s.position_m = agents[i].position_m;
      s.velocity_mps = agents[i].velocity_mps;
      const double speed = s.velocity_mps.norm();
      std::optional<Eigen::Vector2d> look;
      if (speed > kStandingSpeedMps) {
        look = s.position_m + s.velocity_mps;
      } else {
        look = Gaze(i);
      }
      if (look && (*look - s.position_m).squaredNorm() > 1e-12) {
        const Eigen::Vector2d d = *look - s.position_m;
        const double target = std::atan2(d.y(), d.x());
        s.heading_rad =
            core::NormalizeAngle(s.heading_rad + core::NormalizeAngle(target - s.heading_rad) *
                                                     (1.0 - std::exp(-dt / kHeadingTimeConstantS)));
      }
      s.gait.Advance(speed, dt, o.body);
      // Blocked by a robot; not by the robot of an episode, which a visitor
      // stands at on purpose (held off its place by the robot's repulsion).
      Visitor& v = visitors[i];
      v.blocked_by_robot = false;
      if (agents[i].desired_velocity_mps.norm() > kBlockedWishMps && speed < kBlockedSpeedMps) {
        for (std::size_t r = 0; r < obstacles.size(); ++r) {
          if (v.activity == Activity::kEpisode && static_cast<int>(r) == v.robot) continue;
          Eigen::Vector2d n, c;
          if (SignedDistanceToConvex(obstacles[r].hull_m, s.position_m, &n, &c) - s.shape.radius_m <
              kBlockedRangeM) {
            v.blocked_by_robot = true;
          }
        }
      }
    }
  }

  void Arrivals(double now) {
    if (o.arrivals_per_hour <= 0.0) return;
    while (now >= next_arrival_s) {
      if (waiting_party == 0) {
        waiting_party = visitor_random.Uniform() < o.visit.group_fraction
                            ? static_cast<int>(visitor_random.UniformInt(o.visit.min_group_size,
                                                                         o.visit.max_group_size))
                            : 1;
      }
      // Wait while the hall is full or the entrance crowded.
      if (Present() + waiting_party > o.max_present) return;
      if (Arrive(now, waiting_party, site.entrance, false) == 0) return;
      waiting_party = 0;
      next_arrival_s += -std::log(1.0 - arrivals_random.Uniform()) * 3600.0 / PartiesPerHour();
    }
  }

  double PartiesPerHour() const {
    const VisitOptions& v = o.visit;
    const double mean_party =
        (1.0 - v.group_fraction) + v.group_fraction * 0.5 * (v.min_group_size + v.max_group_size);
    return o.arrivals_per_hour / mean_party;
  }
};

Crowd::Crowd(CrowdSite site, CrowdOptions options, std::uint64_t seed)
    : options_(std::move(options)) {
  options_.Validate();
  people_.resize(options_.pool_size);
  impl_ = std::make_unique<Impl>(options_, people_, std::move(site), seed);
  Impl& im = *impl_;
  double total = 0.0;
  for (const Attraction& a : im.site.attractions) {
    Require(std::isfinite(a.weight) && a.weight >= 0.0, "attraction " + a.name, "must be >= 0");
    total += a.weight;
    im.attraction_cdf.push_back(total);
  }
  im.visitors.resize(options_.pool_size);
  im.model.agents().resize(options_.pool_size);
  core::RandomStream bodies(seed, core::RandomStream::StreamId("crowd.bodies"));
  for (int i = 0; i < options_.pool_size; ++i) {
    people_[i].shape = PersonShape::Draw(options_.body, &bodies);
    Agent& a = im.model.agents()[i];
    a.radius_m = people_[i].shape.radius_m;
    a.mass_kg = people_[i].shape.mass_kg;
    im.Park(i);
  }
  im.departures = 0;
  im.model.SetWalls(im.site.walls, im.site.pillars);
  im.BuildRoutes();
  // Watch spots: free places of the roam area from which the exit can be reached.
  for (int k = 0; k < options_.watch_spots; ++k) {
    Eigen::Vector2d p;
    if (!im.FreeSpot(im.site.roam_area, kWatchDiscM, &p)) break;
    im.watch_spots.push_back(p);
    im.fields.push_back(DistanceField::ToDisc(*im.grid, p, kWatchDiscM));
  }
  // Visitors already in the hall at the start, somewhere in their visit, off the robots.
  for (const std::vector<Eigen::Vector2d>& hull : im.site.keep_clear) {
    im.obstacles.push_back(RobotObstacle{hull, {0, 0}, {0, 0}, 0.0});
  }
  while (im.Present() < options_.initial_present) {
    if (im.Arrive(0.0, 1, im.site.roam_area, true) == 0) break;  // the floor is full
  }
  im.arrivals = 0;
  im.obstacles.clear();
  if (options_.arrivals_per_hour > 0.0) {
    im.next_arrival_s =
        -std::log(1.0 - im.arrivals_random.Uniform()) * 3600.0 / im.PartiesPerHour();
  }
}

Crowd::~Crowd() = default;

void Crowd::SetObstacles(std::vector<WallSegment> walls, std::vector<WallCircle> pillars) {
  Impl& im = *impl_;
  im.site.walls = std::move(walls);
  im.site.pillars = std::move(pillars);
  im.model.SetWalls(im.site.walls, im.site.pillars);
  im.BuildRoutes();
}

void Crowd::Step(double dt, const std::vector<CrowdRobot>& robots, CrowdStepResult* result) {
  Impl& im = *impl_;
  const double now = time_s_;
  // The robots in the world frame.
  im.robots = robots;
  im.obstacles.resize(robots.size());
  im.robot_reach_m.resize(robots.size());
  for (std::size_t r = 0; r < robots.size(); ++r) {
    const CrowdRobot& robot = robots[r];
    RobotObstacle& ob = im.obstacles[r];
    ob.hull_m.clear();
    double reach = 0.0;
    for (const Eigen::Vector2d& v : robot.footprint_in_robot_m) {
      ob.hull_m.push_back(robot.pose * v);
      reach = std::max(reach, v.norm());
    }
    ob.center_m = robot.pose.translation();
    ob.velocity_mps = robot.velocity_mps;
    ob.yaw_rate_radps = robot.yaw_rate_radps;
    im.robot_reach_m[r] = reach;
  }
  im.model.SetRobots(im.obstacles);
  // Decisions at the social force rate.
  if (im.since_decision_s >= 1.0 / options_.social.social_rate_hz - 1e-9) {
    im.Arrivals(now);
    im.Decide(now);
    im.since_decision_s = 0.0;
  }
  im.since_decision_s += dt;
  CrowdStepResult scratch;
  CrowdStepResult* out = result ? result : &scratch;
  im.model.Step(dt, &out->contacts);
  // Pushes and kicks in progress.
  for (std::size_t k = 0; k < people_.size(); ++k) {
    const int i = static_cast<int>(k);
    Visitor& v = im.visitors[i];
    if (!people_[i].present || v.activity != Activity::kEpisode || !v.pushed ||
        now >= v.push_until_s || v.robot < 0 || v.robot >= static_cast<int>(robots.size())) {
      continue;
    }
    Eigen::Vector2d n, closest;
    SignedDistanceToConvex(im.obstacles[v.robot].hull_m, people_[i].position_m, &n, &closest);
    const double force =
        v.kick ? options_.social.max_push_force_n
               : std::min(options_.behaviours.push_force_n, options_.social.max_push_force_n);
    out->pushes.push_back({v.robot, i, -force * n, closest, v.kick});
  }
  im.UpdateBodies(dt);
  time_s_ = now + dt;
}

int Crowd::size() const { return static_cast<int>(people_.size()); }
int Crowd::present() const { return impl_->Present(); }
const PersonState& Crowd::person(int i) const { return people_.at(i); }
Activity Crowd::activity(int i) const { return impl_->visitors.at(i).activity; }
Behaviour Crowd::behaviour(int i) const { return impl_->visitors.at(i).behaviour; }
bool Crowd::blocked_by_robot(int i) const { return impl_->visitors.at(i).blocked_by_robot; }
std::int64_t Crowd::arrivals() const { return impl_->arrivals; }
std::int64_t Crowd::departures() const { return impl_->departures; }
std::int64_t Crowd::pushes() const { return impl_->pushes; }
double Crowd::max_overlap_m() const { return impl_->model.max_overlap_m(); }
std::array<double, 3> Crowd::max_overlaps_m() const {
  const SocialForceModel& m = impl_->model;
  return {m.max_overlap_people_m(), m.max_overlap_walls_m(), m.max_overlap_robots_m()};
}
const std::array<std::int64_t, 6>& Crowd::episodes() const { return impl_->episodes; }

int Crowd::SpawnGroup(const Eigen::Vector2d& position_m, int count) {
  Impl& im = *impl_;
  // A disc around the spot, large enough for the party.
  core::Polygon2 area;
  const double radius = 0.6 + 0.35 * std::sqrt(static_cast<double>(count));
  for (int k = 0; k < 12; ++k) {
    const double a = 2.0 * kPi * k / 12;
    area.push_back(position_m + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return im.Arrive(time_s_, count, area, false);
}

}  // namespace pavilion::sim::crowd
