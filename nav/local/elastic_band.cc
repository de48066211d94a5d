#include "nav/local/elastic_band.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace pavilion::nav {

namespace {

// A step whose target lowers the clearance below the band's minimum is
// halved this many times before the bubble stays where it is.
constexpr int kStepHalvings = 2;
// Directions from vectors shorter than this are undefined (m).
constexpr double kTinyLength_m = 1e-9;

}  // namespace

void ElasticBandOptions::Validate() const {
  auto fail = [](const std::string& message) { throw std::invalid_argument(message); };
  auto in = [](double v, double lo, double hi) { return v > lo && v <= hi; };
  if (!in(robot_radius_m, 0.0, 2.0)) fail("robot_radius_m must be in (0, 2] m");
  if (!(clearance_margin_m >= 0.0 && clearance_margin_m <= 1.0)) {
    fail("clearance_margin_m must be in [0, 1] m");
  }
  if (!in(repulsion_range_m, 0.0, 2.0)) fail("repulsion_range_m must be in (0, 2] m");
  if (!in(contraction_gain, 0.0, 10.0)) fail("contraction_gain must be in (0, 10]");
  if (!in(repulsion_gain_per_m, 0.0, 1000.0)) fail("repulsion_gain_per_m must be in (0, 1000] 1/m");
  if (!in(step_gain, 0.0, 1.0)) fail("step_gain must be in (0, 1]");
  if (!(step_gain * repulsion_gain_per_m * (clearance_margin_m + repulsion_range_m) < 1.0)) {
    fail(
        "repulsion_gain_per_m must keep step_gain * repulsion_gain_per_m * (clearance_margin_m + "
        "repulsion_range_m) below 1");
  }
  if (!(iterations >= 1 && iterations <= 100)) fail("iterations must be in [1, 100]");
  if (!in(max_bubble_radius_m, 0.0, 5.0)) fail("max_bubble_radius_m must be in (0, 5] m");
  if (!in(min_bubble_radius_m, 0.0, 0.5)) fail("min_bubble_radius_m must be in (0, 0.5] m");
  if (!(overlap_fraction > 0.0 && overlap_fraction < 1.0)) {
    fail("overlap_fraction must be in (0, 1)");
  }
  if (!(redundant_fraction > 0.0 && redundant_fraction < overlap_fraction)) {
    fail("redundant_fraction must be in (0, overlap_fraction)");
  }
  if (!(max_bubbles >= 3 && max_bubbles <= 100000)) fail("max_bubbles must be in [3, 100000]");
}

ElasticBand::ElasticBand(const ElasticBandOptions& options) : options_(options) {
  options_.Validate();
}

void ElasticBand::Reset(std::vector<Eigen::Vector2d> initial_path) {
  bubbles_.clear();
  initial_path_ = std::move(initial_path);
  if (initial_path_.size() < 2) initial_path_.clear();
}

Bubble ElasticBand::MakeBubble(const Eigen::Vector2d& center, const DistanceField& field) const {
  Bubble bubble;
  bubble.center = center;
  bubble.clearance_m = field.Distance(center);
  bubble.radius_m =
      std::min(bubble.clearance_m - options_.robot_radius_m, options_.max_bubble_radius_m);
  return bubble;
}

double ElasticBand::SpacingRadius(const Bubble& bubble) const {
  return std::max(bubble.radius_m, options_.min_bubble_radius_m);
}

bool ElasticBand::Connected(const Bubble& a, const Bubble& b, double fraction) const {
  return (a.center - b.center).norm() <= fraction * (SpacingRadius(a) + SpacingRadius(b));
}

void ElasticBand::PlaceAlongPath(const DistanceField& field) {
  bubbles_.clear();
  bubbles_.push_back(MakeBubble(initial_path_.front(), field));
  const std::size_t limit = static_cast<std::size_t>(options_.max_bubbles) + 1;
  for (std::size_t k = 1; k < initial_path_.size() && bubbles_.size() <= limit; ++k) {
    const Eigen::Vector2d& to = initial_path_[k];
    // Each step connects to any next bubble (its radius is at least the floor).
    while (bubbles_.size() <= limit) {
      const Bubble& last = bubbles_.back();
      const Eigen::Vector2d along = to - last.center;
      const double remaining_m = along.norm();
      const double step_m =
          options_.overlap_fraction * (SpacingRadius(last) + options_.min_bubble_radius_m);
      if (remaining_m <= step_m) break;
      bubbles_.push_back(MakeBubble(last.center + along * (step_m / remaining_m), field));
    }
    bubbles_.push_back(MakeBubble(to, field));
  }
}

void ElasticBand::DropPassed() {
  // Bubble 1 is passed once the robot is beyond the line through it normal
  // to the band; the goal is never dropped.
  std::size_t passed = 0;
  const Eigen::Vector2d& robot = bubbles_.front().center;
  while (passed + 2 < bubbles_.size()) {
    const Eigen::Vector2d& c1 = bubbles_[passed + 1].center;
    const Eigen::Vector2d& c2 = bubbles_[passed + 2].center;
    if ((robot - c1).dot(c2 - c1) <= 0.0) break;
    ++passed;
  }
  bubbles_.erase(bubbles_.begin() + 1, bubbles_.begin() + 1 + static_cast<std::ptrdiff_t>(passed));
}

void ElasticBand::MoveBubble(std::size_t i, const DistanceField& field) {
  Bubble& bubble = bubbles_[i];
  const Eigen::Vector2d c = bubble.center;
  const DistanceField::Query here = field.Nearest(c);
  bubble.clearance_m = here.distance_m;
  bubble.radius_m =
      std::min(here.distance_m - options_.robot_radius_m, options_.max_bubble_radius_m);

  // Q&K's internal force: the tension of the two neighbours (unit vectors).
  Eigen::Vector2d force = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& neighbour : {bubbles_[i - 1].center, bubbles_[i + 1].center}) {
    const Eigen::Vector2d to = neighbour - c;
    const double norm = to.norm();
    if (norm > kTinyLength_m) force += options_.contraction_gain * to / norm;
  }
  // Q&K's external force: -grad of a potential growing inside the range.
  const double influence_m = options_.min_clearance_m() + options_.repulsion_range_m;
  if (here.distance_m < influence_m) {
    force += options_.repulsion_gain_per_m * (influence_m - here.distance_m) * here.gradient;
  }
  // Only the component normal to the band moves the bubble (Q&K §4).
  const Eigen::Vector2d chord = bubbles_[i + 1].center - bubbles_[i - 1].center;
  const double chord_norm = chord.norm();
  if (chord_norm > kTinyLength_m) {
    const Eigen::Vector2d tangent = chord / chord_norm;
    force -= force.dot(tangent) * tangent;
  }
  // Displacement in proportion to the bubble's radius, never leaving it.
  const double scale_m = SpacingRadius(bubble);
  Eigen::Vector2d step = options_.step_gain * scale_m * force;
  const double step_norm = step.norm();
  if (step_norm > scale_m) step *= scale_m / step_norm;
  for (int attempt = 0; attempt <= kStepHalvings; ++attempt) {
    const Bubble moved = MakeBubble(c + step, field);
    if (moved.clearance_m >= options_.min_clearance_m() || moved.clearance_m >= here.distance_m) {
      bubble = moved;
      return;
    }
    step *= 0.5;
  }
}

void ElasticBand::Relax(const DistanceField& field) {
  // Gauss-Seidel sweeps: each bubble sees its neighbours' new positions.
  for (int sweep = 0; sweep < options_.iterations; ++sweep) {
    for (std::size_t i = 1; i + 1 < bubbles_.size(); ++i) MoveBubble(i, field);
  }
}

bool ElasticBand::Maintain(const DistanceField& field) {
  const std::size_t max_bubbles = static_cast<std::size_t>(options_.max_bubbles);
  if (bubbles_.size() > max_bubbles) return false;
  // Bridge every gap by bisection; a bridging bubble below the robot radius
  // cannot be inserted: the band snaps.
  scratch_.clear();
  scratch_.push_back(bubbles_.front());
  for (std::size_t i = 1; i < bubbles_.size(); ++i) {
    // pending_ is a stack of targets, the nearest to scratch_.back() on top.
    pending_.clear();
    pending_.push_back(bubbles_[i]);
    while (!pending_.empty()) {
      if (Connected(scratch_.back(), pending_.back(), options_.overlap_fraction)) {
        scratch_.push_back(pending_.back());
        pending_.pop_back();
        continue;
      }
      const Bubble mid = MakeBubble(0.5 * (scratch_.back().center + pending_.back().center), field);
      if (mid.clearance_m < options_.robot_radius_m) return false;
      if (scratch_.size() + pending_.size() + (bubbles_.size() - i) > max_bubbles) return false;
      pending_.push_back(mid);
    }
  }
  // Delete bubbles whose neighbours (after deletion) connect without them.
  bubbles_.clear();
  bubbles_.push_back(scratch_.front());
  for (std::size_t i = 1; i + 1 < scratch_.size(); ++i) {
    if (!Connected(bubbles_.back(), scratch_[i + 1], options_.redundant_fraction)) {
      bubbles_.push_back(scratch_[i]);
    }
  }
  bubbles_.push_back(scratch_.back());
  return true;
}

bool ElasticBand::Update(const Eigen::Vector2d& robot_position, const DistanceField& field) {
  if (!initial_path_.empty()) {
    PlaceAlongPath(field);
    initial_path_.clear();
  }
  if (bubbles_.size() < 2) return false;
  bubbles_.front() = MakeBubble(robot_position, field);
  bubbles_.back() = MakeBubble(bubbles_.back().center, field);
  DropPassed();
  Relax(field);
  for (std::size_t i = 1; i + 1 < bubbles_.size(); ++i) {
    if (bubbles_[i].clearance_m < options_.robot_radius_m) return false;
  }
  return Maintain(field);
}

std::vector<Eigen::Vector2d> ElasticBand::path() const {
  std::vector<Eigen::Vector2d> centers;
  centers.reserve(bubbles_.size());
  for (const Bubble& bubble : bubbles_) centers.push_back(bubble.center);
  return centers;
}

double ElasticBand::length_m() const {
  double length = 0.0;
  for (std::size_t i = 1; i < bubbles_.size(); ++i) {
    length += (bubbles_[i].center - bubbles_[i - 1].center).norm();
  }
  return length;
}

Eigen::Vector2d ElasticBand::TargetAhead(double distance_m) const {
  if (bubbles_.empty()) return Eigen::Vector2d::Zero();
  double remaining_m = std::max(distance_m, 0.0);
  for (std::size_t i = 1; i < bubbles_.size(); ++i) {
    const Eigen::Vector2d segment = bubbles_[i].center - bubbles_[i - 1].center;
    const double length = segment.norm();
    if (remaining_m <= length) {
      return length > 0.0
                 ? Eigen::Vector2d(bubbles_[i - 1].center + segment * (remaining_m / length))
                 : bubbles_[i].center;
    }
    remaining_m -= length;
  }
  return bubbles_.back().center;
}

}  // namespace pavilion::nav
