#pragma once

// Monte Carlo localization (Probabilistic Robotics §8.3, Augmented_MCL of
// table 8.3) with the likelihood field sensor model (§6.4, table 6.3): the
// baseline from outside the thesis that runs in shadow beside the feature-based
// localization. Parameters follow nav2 AMCL's defaults where it has one.

#include <cstdint>
#include <optional>
#include <vector>

#include "core/localization/encoder_odometry.h"
#include "core/localization/mcl/free_space_grid.h"
#include "core/localization/mcl/likelihood_field.h"
#include "core/map/robot_map.h"
#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

struct MonteCarloOptions {
  // Particle count, fixed (no KLD sampling); [10, 100000]. nav2 keeps 500-2000
  // (min_particles, max_particles); chosen: the middle.
  int particles = 1000;
  int beams = 60;            // beams per scan scored; [1, 1000]; nav2 max_beams 60
  double sigma_hit_m = 0.2;  // sigma of the hit Gaussian, m; (0, 10]; nav2 sigma_hit
  double z_hit = 0.5;        // weight of the hit term; [0, 1]; nav2 z_hit
  double z_rand = 0.5;       // weight of the uniform term (z_rand / max range); [0, 1]; nav2 z_rand
  double alpha_slow = 0.001;  // long-term likelihood average rate; (0, 1); nav2 recovery_alpha_slow
  double alpha_fast = 0.1;    // short-term rate; (alpha_slow, 1); nav2 recovery_alpha_fast
  double update_min_d_m = 0.25;   // travel before a sensor update, m; >= 0; nav2 update_min_d
  double update_min_a_rad = 0.2;  // rotation before a sensor update, rad; >= 0; nav2 update_min_a
  int resample_interval = 1;      // sensor updates per resampling; >= 1; nav2 resample_interval
  // Floor on the per-wheel noise k of eq. 2.9 used to move particles, m; [0, 1].
  // Chosen: the thesis' k = 5e-6 m gives 1.6 mm over update_min_d, too little
  // spread for a particle set to track unmodelled slip; 1e-3 m gives 1.6 cm
  // per wheel and about 2.6 deg of heading over 0.25 m (Robox's b = 0.5 m).
  double wheel_k_floor_m = 1e-3;
  // "Declared localized": position spread (sqrt of the largest eigenvalue of
  // the xy covariance) at most this, m; > 0. Chosen (ours, not nav2's).
  double converged_spread_m = 0.25;
  // ... and heading sigma at most this, rad; > 0. Chosen: 10 deg.
  double converged_heading_sigma_rad = 0.17453292519943295;
  LikelihoodFieldOptions field;        // nav2 laser_likelihood_max_dist 2.0 m
  MapFreeSpaceOptions free_space;      // where random particles are drawn
  std::uint64_t seed = 1;              // RandomStream seed
  std::uint64_t stream_id = 0x6d636c;  // RandomStream stream id ("mcl")

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct Particle {
  Pose2 pose;           // world_from_robot hypothesis
  double weight = 0.0;  // normalized importance weight; the set sums to 1
};

// A particle filter over the robot pose in the map frame. Every draw comes from
// one RandomStream(seed, stream_id); the particle order is stable (resampled
// particles in the order the low-variance resampler picks them, then the
// injected random ones), so the same inputs and seed give the same bytes.
class MonteCarloLocalizer {
 public:
  // Throws std::invalid_argument when an option is out of range.
  MonteCarloLocalizer(RobotMap map, const EncoderOdometryOptions& odometry,
                      const MonteCarloOptions& options);

  // Global localization: particles uniform over the map's free space with
  // uniform headings; w_slow = w_fast = 0; the next scan updates.
  void InitializeGlobal();
  // Pose tracking: particles drawn from N(pose, covariance); the next scan updates.
  void Initialize(const PoseWithCovariance& start);

  // Prediction: the wheel travels since the previous reading (the first one only
  // sets the reference), each particle moved by DiffDriveStep with each wheel's
  // travel drawn with variance max(k, wheel_k_floor_m)|s| (eq. 2.9; the k_turn
  // term of WheelTravelCovariance included).
  void AddEncoders(const EncoderReading& reading);
  // Correction, when the odometry moved more than update_min_d_m or turned more
  // than update_min_a_rad since the last one (or on the first scan after an
  // initialization): scores `beams` readings chosen evenly among the valid ones
  // below max range, updates w_slow and w_fast (table 8.3) and resamples every
  // resample_interval updates, injecting random free-space particles with
  // probability max(0, 1 - w_fast / w_slow). As in table 8.3, w_slow and
  // w_fast start at 0 at each initialization and are never reset (nav2 resets
  // both after an injection), so the recovery wakes only once w_slow has
  // warmed up, some 1 / alpha_slow updates. Returns whether it updated.
  bool AddScan(const LaserScan& scan);

  // Weighted mean (circular mean for the heading) and weighted covariance of
  // the particles that carry the posterior: all of them after a sensor
  // update; after a resampling, the resampled ones (injected random particles
  // join at the next sensor update, whose weights judge them). No clustering:
  // while the set is multi-modal the mean may lie between the modes, and the
  // spread says so.
  const PoseWithCovariance& estimate() const { return estimate_; }
  double position_spread_m() const;
  bool converged() const;
  const std::vector<Particle>& particles() const { return particles_; }
  long updates() const { return updates_; }
  int last_beams() const { return last_beams_; }  // beams scored by the last update
  double w_slow() const { return w_slow_; }
  double w_fast() const { return w_fast_; }
  const LikelihoodField& field() const { return field_; }
  const MapFreeSpace& free_space() const { return free_space_; }

 private:
  std::vector<Eigen::Vector2d> BeamEndsInRobot(const LaserScan& scan) const;
  void Weigh(const std::vector<Eigen::Vector2d>& ends_in_robot, double max_range_m);
  void Resample();
  Particle RandomParticle();
  void UpdateEstimate();
  void ResetFilter();
  void BuildLogLikelihoodTable(double max_range_m);

  EncoderOdometryOptions odometry_;
  WheelNoise particle_noise_;
  MonteCarloOptions options_;
  LikelihoodField field_;
  MapFreeSpace free_space_;
  RandomStream random_;
  std::vector<Particle> particles_;
  std::vector<double> log_likelihood_;  // scratch, per particle
  std::vector<float> log_p_cell_;       // log p(beam end in cell), per field_ cell
  double log_p_off_grid_ = 0.0;         // log p of a beam end off the grid
  double table_max_range_m_ = -1.0;     // the max range log_p_cell_ was built for
  std::optional<EncoderReading> last_encoders_;
  Pose2 odometry_pose_;     // noise-free dead reckoning, for the update trigger
  Pose2 last_update_pose_;  // odometry_pose_ at the last sensor update
  bool update_pending_ = true;
  PoseWithCovariance estimate_;
  std::size_t posterior_count_ = 0;  // leading particles the estimate is over
  long updates_ = 0;
  int last_beams_ = 0;
  double w_slow_ = 0.0;
  double w_fast_ = 0.0;
};

}  // namespace pavilion::core
