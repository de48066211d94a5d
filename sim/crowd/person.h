#pragma once

#include <Eigen/Core>
#include <array>

#include "core/random/random_stream.h"

namespace pavilion::sim::crowd {

// The body of a simulated person: a disc for the crowd model, two legs that a
// laser at beam height sees, a torso above them. Dimensions are drawn per
// person from the ranges; defaults are adult averages (chosen).
struct PersonBodyOptions {
  double min_shoulder_radius_m = 0.20;  // body disc radius range, m, (0, 0.4]
  double max_shoulder_radius_m = 0.25;
  double min_leg_diameter_m = 0.10;  // leg diameter at beam height, m, (0, 0.3]
  double max_leg_diameter_m = 0.15;
  double hip_height_m = 0.85;      // top of the legs, m, (0.2, 1.5]
  double height_m = 1.70;          // top of the head, m, > hip_height_m, <= 2.5
  double hip_half_width_m = 0.09;  // leg axes' distance from the body axis, m, [0, 0.2]
  double mass_kg = 80.0;           // HFV00's pedestrian mass, kg, (0, 300]
  // Step length at the free walking speed of 1.34 m/s, m: with a cadence of
  // about 1.85 steps/s (chosen, adult averages); shorter steps at lower
  // speeds as L ∝ √v (Grieve 1968). (0, 1.5]
  double step_length_m = 0.72;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// What a person's body is made of, drawn once per person.
struct PersonShape {
  double radius_m = 0.22;      // body disc
  double leg_radius_m = 0.06;  // each leg
  double hip_height_m = 0.85;
  double height_m = 1.70;
  double hip_half_width_m = 0.09;
  double mass_kg = 80.0;

  static PersonShape Draw(const PersonBodyOptions& options, core::RandomStream* random);
};

// The gait: legs swing with a phase that advances one half turn per step, by
// an amplitude that follows the walking speed (zero when standing).
struct Gait {
  double phase_rad = 0.0;
  double swing_m = 0.0;  // current fore-aft foot offset amplitude (half a step)

  // Advances by dt at walking speed `speed_mps`.
  void Advance(double speed_mps, double dt, const PersonBodyOptions& options);
};

// Where a person is and what the laser can see of them.
struct PersonState {
  Eigen::Vector2d position_m{0, 0};
  Eigen::Vector2d velocity_mps{0, 0};
  double heading_rad = 0.0;  // where the body faces
  PersonShape shape;
  Gait gait;
  bool present = false;  // on the floor (else parked in the pool)
  int group = -1;        // visitors arriving together share a group id (>= 0)

  // Centres of the two legs' cuts by the plane z (left, right), world frame:
  // each leg pivots at the hip, so its offset is the foot's scaled by
  // (hip - z) / hip. Only meaningful for z below the hip.
  std::array<Eigen::Vector2d, 2> LegCentres(double z_m) const;
};

}  // namespace pavilion::sim::crowd
