#include "scenarios/run/body_spawner.h"

#include <algorithm>
#include <numbers>
#include <string>
#include <utility>

#include "core/geometry/segment2.h"
#include "core/random/random_stream.h"
#include "scenarios/config/input_error.h"

namespace pavilion::scenarios {
namespace {

// Free space kept between a spawned body and anything else (m).
constexpr double kSpawnClearanceM = 0.05;
constexpr int kSpawnAttempts = 2000;
// Heights at which spawn clearance is checked, besides the body's mid-height (m).
constexpr double kSpawnCheckLowM = 0.05;
// The stream of spawn poses (not a body's).
constexpr std::uint64_t kSpawnStream = 0x5350415749ULL;  // "SPAWN"

double FootprintRadius(const sim::BodyShape& s) {
  if (s.type == sim::BodyShapeType::kBox) return 0.5 * s.box_size_m.head<2>().norm();
  return s.radius_m;
}

bool Clear(const core::PlanarSection& section, const Eigen::Vector2d& p, double r) {
  for (const auto& s : section.segments) {
    if (core::PointSegmentDistance(p, s.a_m, s.b_m) < r) return false;
  }
  for (const auto& c : section.circles) {
    if ((c.center_m - p).norm() < r + c.radius_m) return false;
  }
  return true;
}

// Draws a pose inside the body's spawn area that is clear of the world and of
// the bodies placed before it.
core::Pose2 DrawSpawnPose(const sim::World& world, const BodyEntry& entry,
                          const std::string& scenario_file, core::RandomStream* stream) {
  const core::Polygon2& area = *entry.spawn_polygon;
  Eigen::Vector2d lo = area.front(), hi = area.front();
  for (const auto& p : area) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double r = FootprintRadius(entry.spec.shape) + kSpawnClearanceM;
  const double h = 2.0 * entry.spec.shape.HalfHeight();
  const core::PlanarSection low = world.SectionAt(std::min(kSpawnCheckLowM, 0.5 * h));
  const core::PlanarSection mid = world.SectionAt(0.5 * h);
  std::vector<std::pair<Eigen::Vector2d, double>> others;
  for (int b = 0; b < world.body_count(); ++b) {
    others.emplace_back(world.body_state(b).pose.translation(),
                        FootprintRadius(world.body_spec(b).shape));
  }
  for (int attempt = 0; attempt < kSpawnAttempts; ++attempt) {
    const Eigen::Vector2d p(stream->Uniform(lo.x(), hi.x()), stream->Uniform(lo.y(), hi.y()));
    const double yaw = stream->Uniform(-std::numbers::pi, std::numbers::pi);
    if (!core::Contains(area, p) || !Clear(low, p, r) || !Clear(mid, p, r)) continue;
    bool free = true;
    for (const auto& [q, rq] : others) {
      if ((q - p).norm() < r + rq) {
        free = false;
        break;
      }
    }
    if (free) return {p.x(), p.y(), yaw};
  }
  throw InputError(Diagnostic{scenario_file, 0, "bodies",
                              "cannot place body '" + entry.spec.id + "' in area '" +
                                  entry.spawn_area + "' after " + std::to_string(kSpawnAttempts) +
                                  " tries: the area is too small or too crowded"});
}

std::unique_ptr<sim::BodyMotion> MakeMotion(const BodyEntry& entry, std::uint64_t seed) {
  switch (entry.motion.type) {
    case MotionSpec::Type::kScripted:
      return std::make_unique<sim::ScriptedMotion>(entry.motion.scripted);
    case MotionSpec::Type::kRandomWalk: {
      sim::RandomWalkOptions options = entry.motion.random_walk;
      options.roam_area = entry.spawn_polygon;  // walkers stay where they were spawned
      return std::make_unique<sim::RandomWalkMotion>(
          options, core::RandomStream(seed, core::RandomStream::StreamId(entry.spec.id.c_str())));
    }
    case MotionSpec::Type::kNone:
      break;
  }
  return nullptr;
}

}  // namespace

std::vector<std::unique_ptr<sim::BodyMotion>> SpawnBodies(const Scenario& scenario,
                                                          sim::World* world) {
  core::RandomStream spawn_stream(scenario.seed, kSpawnStream);
  std::vector<std::unique_ptr<sim::BodyMotion>> motions;
  for (const BodyEntry& entry : scenario.bodies) {
    sim::BodySpec spec = entry.spec;
    if (entry.spawn_polygon)
      spec.pose = DrawSpawnPose(*world, entry, scenario.source_file, &spawn_stream);
    world->AddBody(spec);
    motions.push_back(MakeMotion(entry, scenario.seed));
  }
  return motions;
}

}  // namespace pavilion::scenarios
