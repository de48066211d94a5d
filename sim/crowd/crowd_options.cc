#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/crowd/crowd.h"

namespace pavilion::sim::crowd {
namespace {

void Require(bool ok, const std::string& field, const char* what) {
  if (!ok) throw std::invalid_argument(field + " " + what);
}
bool InRange(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

}  // namespace

const char* ToString(Behaviour behaviour) {
  switch (behaviour) {
    case Behaviour::kOrdinary:
      return "ordinary";
    case Behaviour::kCurious:
      return "curious";
    case Behaviour::kCrowding:
      return "crowding";
    case Behaviour::kBlocking:
      return "blocking";
    case Behaviour::kFollowing:
      return "following";
    case Behaviour::kPushing:
      return "pushing";
  }
  return "?";
}

const char* ToString(Activity activity) {
  switch (activity) {
    case Activity::kParked:
      return "parked";
    case Activity::kWalking:
      return "walking";
    case Activity::kDwelling:
      return "dwelling";
    case Activity::kWatching:
      return "watching";
    case Activity::kEpisode:
      return "episode";
    case Activity::kLeaving:
      return "leaving";
  }
  return "?";
}

void BehaviourOptions::Validate() const {
  const char* fractions[] = {"curious", "crowding", "blocking", "following", "pushing"};
  const double values[] = {curious, crowding, blocking, following, pushing};
  double sum = 0.0;
  for (int k = 0; k < 5; ++k) {
    Require(InRange(values[k], 0, 1), std::string("behaviours.") + fractions[k],
            "must be in [0, 1]");
    sum += values[k];
  }
  Require(sum <= 1.0 + 1e-9, "behaviours.pushing", "the behaviour fractions sum to more than 1");
  Require(InRange(notice_range_m, 1e-3, 50), "behaviours.notice_range_m", "must be in (0, 50]");
  Require(InRange(episode_mean_s, 1e-3, 3600), "behaviours.episode_mean_s", "must be in (0, 3600]");
  Require(InRange(cooldown_s, 0, 1e5), "behaviours.cooldown_s", "must be in [0, 1e5]");
  Require(InRange(push_force_n, 1e-3, 1e4), "behaviours.push_force_n", "must be in (0, 1e4]");
  Require(InRange(push_duration_s, 1e-3, 10), "behaviours.push_duration_s", "must be in (0, 10]");
  Require(InRange(kick_duration_s, 1e-3, 10), "behaviours.kick_duration_s", "must be in (0, 10]");
}

void VisitOptions::Validate() const {
  Require(min_exhibits >= 0 && min_exhibits <= 50, "visit.min_exhibits", "must be in [0, 50]");
  Require(max_exhibits >= min_exhibits && max_exhibits <= 50, "visit.max_exhibits",
          "must be in [min_exhibits, 50]");
  Require(InRange(dwell_mean_s, 0, 3600), "visit.dwell_mean_s", "must be in [0, 3600]");
  Require(InRange(dwell_std_s, 0, 3600), "visit.dwell_std_s", "must be in [0, 3600]");
  Require(InRange(visit_mean_s, 0, 86400), "visit.visit_mean_s", "must be in [0, 86400]");
  Require(InRange(visit_std_s, 0, 86400), "visit.visit_std_s", "must be in [0, 86400]");
  Require(InRange(desired_speed_mean_mps, 1e-3, 3), "visit.desired_speed_mean_mps",
          "must be in (0, 3]");
  Require(InRange(desired_speed_std_mps, 0, 1), "visit.desired_speed_std_mps", "must be in [0, 1]");
  Require(InRange(group_fraction, 0, 1), "visit.group_fraction", "must be in [0, 1]");
  Require(min_group_size >= 2 && min_group_size <= max_group_size, "visit.min_group_size",
          "must be in [2, max_group_size]");
  Require(max_group_size <= 20, "visit.max_group_size", "must be in [min_group_size, 20]");
}

void CrowdOptions::Validate() const {
  Require(pool_size >= 1 && pool_size <= 10000, "pool", "must be in [1, 10000]");
  Require(initial_present >= 0 && initial_present <= pool_size, "present", "must be in [0, pool]");
  Require(InRange(arrivals_per_hour, 0, 1e5), "arrivals_per_hour", "must be in [0, 1e5]");
  Require(max_present >= 0 && max_present <= pool_size, "max_present", "must be in [0, pool]");
  Require(visit.group_fraction == 0.0 || visit.max_group_size <= pool_size, "visit.max_group_size",
          "is larger than the pool");
  Require(InRange(route_cell_m, 1e-3, 1), "route_cell_m", "must be in (0, 1]");
  Require(InRange(route_clearance_m, 0, 1), "route_clearance_m", "must be in [0, 1]");
  Require(watch_spots >= 0 && watch_spots <= 200, "watch_spots", "must be in [0, 200]");
  visit.Validate();
  behaviours.Validate();
  try {
    body.Validate();
    social.Validate();
  } catch (const std::invalid_argument& e) {
    // "person.x ..." -> "body.x ...", "social_force.x" stays.
    const std::string what = e.what();
    if (what.rfind("person.", 0) == 0) throw std::invalid_argument("body." + what.substr(7));
    throw;
  }
}

}  // namespace pavilion::sim::crowd
