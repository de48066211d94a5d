#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/planar_section.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"
#include "sim/raycast/laser_hit_finder.h"
#include "sim/world/world.h"

namespace pavilion::sim {

// SICK LMS 200 at 0.5° (thesis §2.2.2): the mirror turns at 75 Hz (datasheet; the
// thesis quotes 50 Hz) and a 0.5° scan interlaces two turns at 1° each. The last
// reading (179.5°, second turn) comes 1 + 179.5/360 turns after the first.
inline constexpr double kLms200MirrorRateHz = 75.0;
inline constexpr double kLms200SweepS = (1.0 + 179.5 / 360.0) / kLms200MirrorRateHz;  // ≈ 19.98 ms

// How one physical scanner differs from its datasheet and from the robot file
// (issue 20, docs/realism.md): errors that repeat from scan to scan or are
// correlated, unlike the white noise the extraction models. All zero (the
// default, and everything under `realism: ideal`): the ideal scanner.
struct LaserSystematicErrors {
  // The true mount is the robot file's mount composed with this (x, y in the
  // sensor frame, m; heading, rad). The mirror's angular offset (§2.2.1.2: the
  // zero angle calibrated at start-up) is part of the heading: for a planar
  // scanner a turned mirror zero and a turned mount are the same error. Scans
  // report the robot file's mount. |x|, |y| <= 0.1 m, |heading| <= 0.1 rad.
  core::Pose2 mount_error;
  // Range bias per surface (world element), normal with this σ, drawn once
  // per element from `seed`: the same wall reads long by the same millimetres
  // in every scan (its paint, its angle to the floor). m, [0, 0.5].
  double surface_bias_sigma_m = 0.0;
  // Range noise correlated between neighbouring readings: a stationary AR(1)
  // process along the reading index with this σ and correlation length (the
  // correlation of readings k apart is exp(-k / length)). m, [0, 0.5]; readings, [0.1, 1e4].
  double correlated_sigma_m = 0.0;
  double correlation_readings = 1.0;
  // Intensity-dependent bias (§2.2.1.3: "indicated range can vary as much as
  // 7.6 cm between very weak and very strong signals"): the range reads long
  // by intensity_bias_m · clamp(-log10(a) / 3, 0, 1) for a relative amplitude
  // a (RelativeAmplitude below): nothing for the white target at 2 m, the
  // whole bias at a thousandth of its signal. m, [0, 0.5].
  double intensity_bias_m = 0.0;
  // Intensity-dependent noise: a weaker return's time of flight is timed less
  // sharply, so the white range noise grows as the amplitude falls. Its σ is
  // the datasheet σ and intensity_sigma_m · clamp(-log10(a) / 3, 0, 1) added
  // in quadrature (the same amplitude law as the bias): nothing for the white
  // target at 2 m, 40 % of it for a white wall at 8 m. m, [0, 0.5].
  double intensity_sigma_m = 0.0;
  // White error of each scan's stamp (scheduling and bus jitter, §2.2.1.5,
  // §4.4.3), σ; a constant latency is LaserScannerOptions::timestamp_bias_s. s, [0, 0.1].
  double stamp_jitter_s = 0.0;
  // Seeds the surface biases (shared by the scanners that should see the
  // same surfaces alike), and this scanner's correlated noise and jitter streams.
  std::uint64_t surface_seed = 0;
  std::uint64_t seed = 0;

  bool Any() const;       // any error set
  void Validate() const;  // throws std::invalid_argument naming the field
};

// Parameters of a simulated 2D laser scanner. Defaults are the SICK LMS 200 as
// the thesis configured it (§2.2.2: 180°, 0.5°, 8 m, σ_ρ = 1 cm, 1 mm resolution).
struct LaserScannerOptions {
  std::string profile = "sick_lms200";             // sick_lms200 | acuity_accurange | custom
  double fov_rad = 3.14159265358979323846;         // angular range covered, rad, (0, 2π]
  int beams = 361;                                 // readings per scan, [2, 100000]
  double first_bearing_rad = -1.5707963267948966;  // bearing of the first reading, rad, [-2π, 2π]
  double max_range_m = 8.0;                        // readings beyond are "no return", m, (0, 1000]
  double scan_rate_hz = 10.0;                      // scans delivered per second, Hz, (0, 1e4]
  double sweep_s = kLms200SweepS;  // first to last reading in time, s, [0, 1/scan_rate_hz]
  int interlaced_turns = 2;        // mirror turns a sweep spreads its readings over, [1, beams-1]
  double timestamp_bias_s = 0.0;   // constant error added to the stamp (§2.2.1.5), s, [-1, 1]
  double range_sigma_m = 0.01;     // range noise σ on normal surfaces, m, [0, 10]
  double range_resolution_m = 0.001;  // quantization of reported ranges, m, [0, 1] (0: none)

  // Acuity AccuRange amplitude model (§2.2.1.3): amplitude ∝ reflectivity·cos(incidence)/r²
  // (RelativeAmplitude below), σ = range_sigma_m above min_amplitude, low_amplitude_sigma_m below.
  bool amplitude_model = false;
  double min_amplitude = 0.05;         // relative amplitude threshold s_min, [0, 1]
  double low_amplitude_sigma_m = 0.1;  // σ of readings below s_min, m, [0, 10]
  double outlier_probability = 0.0;    // chance of a uniform random range, [0, 1]

  // Surface effects (thesis §2.2.1.6).
  double dark_dropout_probability = 0.3;  // `dark` surfaces: chance of no return, [0, 1]
  double dark_sigma_factor = 5.0;         // ... and range σ multiplied by this, [1, 1000]
  // `specular`: no return beyond this incidence, rad, [0, π/2].
  double specular_max_incidence_rad = 1.0;
  double beam_divergence_rad = 0.0087;  // full footprint width for mixed pixels, rad, [0, 0.1]
  double mixed_pixel_min_gap_m = 0.05;  // depth jump that can produce a mixed pixel, m, (0, 100]

  // noise=false: no range noise, outliers or dark dropouts. effects=false: every
  // surface answers as `normal` (no dark/specular behaviour, no mixed pixels);
  // the reflector flag is still reported. Both off: the geometric range, quantized.
  bool noise = true;
  bool effects = true;
  // The physical scanner's systematic and correlated errors (off by default).
  // The correlated noise follows `noise`; the rest applies whatever it is.
  LaserSystematicErrors systematic;

  // Throws std::invalid_argument naming the field.
  void Validate() const;
  // Named profiles: "sick_lms200", "acuity_accurange", and "custom" (the
  // defaults, to be edited). Throws std::invalid_argument for other names.
  static LaserScannerOptions Profile(const std::string& name);
};

// Amplitude model (§2.2.1.3). The relative amplitude of a return is
// reflectivity·cos(incidence)/(r/kAmplitudeReferenceRangeM)²: 1 for the white
// reference target met head-on at the reference range.
inline constexpr double kAmplitudeReferenceRangeM = 2.0;
// Reflectivity of a laser response relative to the white reference: normal 1,
// retro-reflective 10, dark 0.05, specular 1 (within its incidence limit),
// transparent 0.
double LaserReflectivity(core::LaserResponse response);
double RelativeAmplitude(double reflectivity, double range_m, double cos_incidence);

// A laser scanner mounted on a robot, casting rays in its horizontal beam plane
// through a LaserHitFinder (Bullet or the planar caster) and applying its error
// models to the hits.
// A sweep spans several physics ticks: the runner calls Cast() every tick
// with the robot pose at the start and end of the tick, and each reading is
// cast in the tick its time falls in, from the pose interpolated to its time
// (so a moving robot gets the distorted scans of §2.2.1.4).
//
// Reading i has bearing first_bearing_rad + i·Δ (Δ = fov/(beams-1), or
// fov/beams for a full turn). With k interlaced turns of period T, reading i is
// taken in turn i mod k when the mirror passes its bearing: at
// T·((i mod k) + i·Δ/2π) after the first, T chosen so that the last is sweep_s
// after the first. For k = 1 that is i·sweep_s/(beams-1).
//
// Mixed pixels (§2.2.1.6 "A"): the beam has an angular footprint of width
// beam_divergence_rad with uniform intensity. Where a depth edge lies inside it,
// the reading is the amplitude-weighted mean of the ranges of the surfaces it
// covers (phase/frequency-to-range sensors average the returned signals). Edges
// are looked for only where needed: the readings taken one after the other in
// a mirror turn are compared, and only across a depth discontinuity are edge
// rays cast (at ±divergence/2) and the edge located by bisection. Readings at
// the ends of a turn always check their outer side; when the footprint is wider
// than the spacing of a turn, every reading checks both sides. (A gap narrower
// than that spacing, with one surface on both sides, can go unnoticed.)
// A fault of a laser for a while (a scenario's sensor_fault event): a
// blackout (every reading a dropout), extra range noise, or readings stuck at
// the last scan before the fault.
struct LaserFault {
  enum class Mode { kNone, kBlackout, kNoise, kStuck };
  Mode mode = Mode::kNone;
  double from_s = 0.0;         // scans stamped from then ...
  double until_s = 0.0;        // ... until before then are faulty
  double extra_sigma_m = 0.0;  // kNoise: standard deviation added to valid ranges, m
  std::uint64_t seed = 0;      // kNoise: seeds the fault's own stream (the sensor's draws stay)
};

class LaserScanner {
 public:
  // `stream` draws every random number of this sensor but those of
  // options.systematic (streams of their own, so that turning one error on
  // leaves every other draw as it was). `robot_from_sensor` is the robot
  // file's mount; the rays leave from it composed with the mount error.
  // Throws std::invalid_argument for invalid options.
  LaserScanner(std::string id, LaserScannerOptions options, core::Pose2 robot_from_sensor,
               double mount_height_m, core::RandomStream stream);

  const std::string& id() const { return id_; }
  // Rays this scanner has cast (central and edge rays), by either hit finder.
  std::int64_t rays_cast() const { return rays_cast_; }
  const LaserScannerOptions& options() const { return options_; }
  // Bearing and time after the sweep start of reading i.
  double bearing_rad(int i) const { return bearings_rad_[i]; }
  double time_offset_s(int i) const { return offsets_s_[i]; }

  // Starts a new sweep whose first reading is taken at `start_s`; the scan's
  // stamp is start_s + timestamp_bias_s.
  void BeginSweep(double start_s);
  // Casts the readings whose times lie in [t0_s, t1_s), the robot moving
  // linearly from world_from_robot_t0 to world_from_robot_t1 (readings due
  // before t0_s are cast from world_from_robot_t0). Rays ignore the elements of
  // `ignore_group` (the robot's own body). Does nothing without a sweep.
  // `finder` gives the geometric hits (Bullet or the planar caster); the
  // World overload casts with Bullet.
  void Cast(const LaserHitFinder& finder, double t0_s, const core::Pose2& world_from_robot_t0,
            double t1_s, const core::Pose2& world_from_robot_t1, int ignore_group);
  void Cast(const World& world, double t0_s, const core::Pose2& world_from_robot_t0, double t1_s,
            const core::Pose2& world_from_robot_t1, int ignore_group);
  // True when every reading of the current sweep has been cast.
  bool SweepComplete() const;
  // The finished scan and its ground truth; valid after SweepComplete().
  const core::LaserScan& scan() const { return scan_; }
  const core::LaserScanTruth& truth() const { return truth_; }

  // Casts a whole scan at once from a fixed robot pose (the `pavilion scan`
  // command); `start_s` is the time of the first reading, as for BeginSweep.
  // Leaves a sweep in progress untouched (though it draws from the same stream);
  // `truth` may be null.
  core::LaserScan ScanFrom(const LaserHitFinder& finder, const core::Pose2& world_from_robot,
                           double start_s, int ignore_group, core::LaserScanTruth* truth);
  core::LaserScan ScanFrom(const World& world, const core::Pose2& world_from_robot, double start_s,
                           int ignore_group, core::LaserScanTruth* truth);

  double mount_height_m() const { return mount_height_m_; }
  // Faults the scans that finish from now until fault.until_s.
  void SetFault(const LaserFault& fault);
  // The true mount (the rays'), and the mount the scans report (the robot file's).
  const core::Pose2& robot_from_sensor() const { return robot_from_sensor_; }
  const core::Pose2& reported_robot_from_sensor() const { return reported_robot_from_sensor_; }

 private:
  // What one ray met.
  struct RaySample {
    bool hit = false;
    double range_m = 0.0;
    Eigen::Vector3d point_m{0, 0, 0};
    Eigen::Vector3d normal{0, 0, 0};  // unit, facing the ray
    double cos_incidence = 1.0;
    int element = -1;
    core::LaserResponse response = core::LaserResponse::kNormal;
    // The ray's unit direction (world, z = 0), kept for Explains: its sine
    // and cosine are a good part of a ray's cost.
    Eigen::Vector3d direction{0, 0, 0};
  };
  // The rays of one reading: the central ray, and per side (0: clockwise,
  // 1: counter-clockwise) the fraction of the footprint beyond a depth edge
  // and the surface seen there.
  struct ReadingGeometry {
    RaySample centre;
    std::array<double, 2> edge_fraction{0.0, 0.0};
    std::array<RaySample, 2> edge;
  };
  struct Sweep {
    double start_s = 0.0;
    int next = 0;  // position in order_ of the next reading to cast
    std::vector<ReadingGeometry> geometry;
    core::LaserScanTruth truth;
  };

  Sweep NewSweep(double start_s) const;
  // Sets `sweep` up for a new sweep starting at start_s, keeping its buffers.
  void ResetSweep(double start_s, Sweep* sweep) const;
  // A ray of at most max_range_m (the scanner's range when negative).
  RaySample CastBeam(const LaserHitFinder& finder, const core::Pose2& world_from_sensor,
                     double bearing_rad, int ignore_group, double max_range_m = -1.0) const;
  // CastBeam along a direction already computed (BeamDirection).
  RaySample CastAlong(const LaserHitFinder& finder, const core::Pose2& world_from_sensor,
                      const Eigen::Vector3d& direction, int ignore_group,
                      double max_range_m = -1.0) const;
  Eigen::Vector3d RayOrigin(const core::Pose2& world_from_sensor) const;
  bool Explains(const RaySample& surface, const core::Pose2& world_from_sensor,
                const RaySample& sample) const;
  // Explains(surface, world_from_sensor, CastBeam(...bearing_rad...)), casting
  // the ray only as far as a hit it explains could lie.
  bool ExplainsBeam(const LaserHitFinder& finder, const RaySample& surface,
                    const core::Pose2& world_from_sensor, double bearing_rad,
                    int ignore_group) const;
  void CastReading(const LaserHitFinder& finder, int i, const core::Pose2& world_from_robot,
                   int ignore_group, Sweep* sweep) const;
  void CheckEdge(const LaserHitFinder& finder, int i, int side, int ignore_group,
                 Sweep* sweep) const;
  double Amplitude(const RaySample& sample) const;
  core::LaserScan Finalize(const Sweep& sweep);
  // The fault, if one is active at the scan's time (after Finalize).
  void ApplyFault(core::LaserScan* scan);

  std::string id_;
  LaserScannerOptions options_;
  // The amplitude-weighted range of a reading's footprint; adds its amplitude
  // and the retro-reflective part of it.
  double FootprintReturn(const ReadingGeometry& g, double* amplitude, double* retro_amplitude);
  // The range bias of world element `element` (LaserSystematicErrors).
  double SurfaceBias(int element);

  core::Pose2 reported_robot_from_sensor_;
  core::Pose2 robot_from_sensor_;
  double mount_height_m_;
  core::RandomStream stream_;
  core::RandomStream correlated_stream_;
  core::RandomStream jitter_stream_;
  double correlated_state_m_ = 0.0;     // the AR(1) process at the last reading
  bool correlated_started_ = false;     // drawn from its stationary law at first
  std::vector<double> surface_bias_m_;  // by element, NaN until drawn
  std::vector<double> bearings_rad_;
  std::vector<double> offsets_s_;
  std::vector<int> order_;  // reading indices in the order they are taken
  bool check_edges_ = false;
  bool check_every_edge_ = false;
  bool in_sweep_ = false;
  Sweep sweep_;
  core::LaserScan scan_;
  core::LaserScanTruth truth_;
  LaserFault fault_;
  std::optional<core::RandomStream> fault_random_;
  core::LaserScan last_good_;           // the last scan before a kStuck fault
  mutable std::int64_t rays_cast_ = 0;  // counted in CastBeam (const: a geometric query)
};

}  // namespace pavilion::sim
