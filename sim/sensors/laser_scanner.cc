#include "sim/sensors/laser_scanner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace pavilion::sim {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// A field of view within this of 2π is a full turn (spacing fov/beams).
constexpr double kFullTurnToleranceRad = 1e-9;
constexpr int kMaxBeams = 100000;
constexpr double kMaxBeamDivergenceRad = 0.1;
// Bisection steps locating a depth edge inside half the beam footprint: the
// footprint fraction beyond the edge is then known to within 1/2^(n+2).
constexpr int kEdgeBisections = 5;
// Ranges below this count as this in the 1/r² amplitude law (m).
constexpr double kMinAmplitudeRangeM = 1e-3;
// A surface whose plane meets a ray at a cosine below this cannot explain its hit.
constexpr double kMinPlaneCosine = 1e-6;
// A probe's range limit lies this far (m) beyond the last range its surface
// explains, so that rounding cannot cut off an explained hit.
constexpr double kProbeSlackM = 1e-6;
// Half of RandomStream::Uniform()'s 2^-53 step: added to a draw in [0, 1), it
// gives one in (0, 1).
constexpr double kHalfUniformStep = 0x1.0p-54;
// The reflector bit is set when retro-reflective surfaces return more than this
// share of a reading's amplitude.
constexpr double kReflectorAmplitudeShare = 0.5;
// The intensity bias reaches its full size this many decades below the white
// target's relative amplitude (LaserSystematicErrors::intensity_bias_m).
constexpr double kIntensityBiasDecades = 3.0;

// Reflectivities relative to the white target of §2.2.1.3 (Kodak gray scale
// card white): paint and plaster are close to it; retro-reflective sheeting
// returns an order of magnitude more towards the source (what sets the §3.3
// reflector bit); black anodized aluminium and velvet a few percent (§2.2.1.6 "C").
constexpr double kNormalReflectivity = 1.0;
constexpr double kRetroReflectivity = 10.0;
constexpr double kDarkReflectivity = 0.05;
constexpr double kSpecularReflectivity = 1.0;  // near-normal mirror return, else none

// Acuity AccuRange 4000 LIR on Pygmalion (§2.2.1): the mirror turns at
// 2.778 Hz so that 1 kHz sampling gives 1° resolution over 360° (§2.2.1.4).
constexpr double kAcuitySampleRateHz = 1000.0;
constexpr int kAcuityReadingsPerTurn = 360;
// Beyond the thesis' indoor scans (≈ 6 m, Fig. 2.5); white targets fall below
// s_min beyond ≈ 9 m with the amplitude model.
constexpr double kAcuityMaxRangeM = 15.0;
// Stamp bias identified in §2.2.1.5: a constant 5° shift, corrected by 5 ms
// (the thesis gives no sign; taken here as a stamp 5 ms late).
constexpr double kAcuityTimestampBiasS = 0.005;
// §2.2.1.3: short-term σ from Fig. 2.3 (a 4σ interval below 2 mm).
constexpr double kAcuityRangeSigmaM = 0.0005;
// Below s_min the indicated range varies by up to 7.6 cm between weak and
// strong signals (§2.2.1.3); taken as a ±3σ band.
constexpr double kAcuityLowAmplitudeSigmaM = 0.025;
// "The sensor is in general subject to outliers" (§2.2.1.6); a chosen rate.
constexpr double kAcuityOutlierProbability = 0.01;
// 0.5 mrad beam divergence (§2.2.1.3).
constexpr double kAcuityBeamDivergenceRad = 0.0005;

std::string Format(double value) {
  std::ostringstream out;
  out.precision(10);
  out << value;
  return out.str();
}

void Require(bool ok, const char* field, const char* expected, double value) {
  if (!ok) {
    throw std::invalid_argument(std::string("laser scanner option ") + field + " must be " +
                                expected + " (got " + Format(value) + ")");
  }
}

// The robot file's mount composed with the mount error; exactly the file's
// without one (no rounding in a composition with the identity).
core::Pose2 TrueMount(const core::Pose2& robot_from_sensor, const core::Pose2& mount_error) {
  const bool none =
      mount_error.x_m == 0.0 && mount_error.y_m == 0.0 && mount_error.theta_rad == 0.0;
  return none ? robot_from_sensor : robot_from_sensor * mount_error;
}

bool IsFullTurn(double fov_rad) { return fov_rad >= kTwoPi - kFullTurnToleranceRad; }

double AngularSpacing(const LaserScannerOptions& o) {
  return IsFullTurn(o.fov_rad) ? o.fov_rad / o.beams : o.fov_rad / (o.beams - 1);
}

// Linear interpolation of x and y, shortest-angle interpolation of theta.
core::Pose2 Interpolate(const core::Pose2& a, const core::Pose2& b, double s) {
  return {a.x_m + s * (b.x_m - a.x_m), a.y_m + s * (b.y_m - a.y_m),
          core::NormalizeAngle(a.theta_rad + s * core::NormalizeAngle(b.theta_rad - a.theta_rad))};
}

Eigen::Vector3d BeamDirection(const core::Pose2& world_from_sensor, double bearing_rad) {
  const double a = world_from_sensor.theta_rad + bearing_rad;
  return {std::cos(a), std::sin(a), 0.0};
}

}  // namespace

double LaserReflectivity(core::LaserResponse response) {
  switch (response) {
    case core::LaserResponse::kNormal:
      return kNormalReflectivity;
    case core::LaserResponse::kRetroReflective:
      return kRetroReflectivity;
    case core::LaserResponse::kDark:
      return kDarkReflectivity;
    case core::LaserResponse::kSpecular:
      return kSpecularReflectivity;
    case core::LaserResponse::kTransparent:
      return 0.0;
  }
  return 0.0;
}

double RelativeAmplitude(double reflectivity, double range_m, double cos_incidence) {
  const double r = std::max(range_m, kMinAmplitudeRangeM) / kAmplitudeReferenceRangeM;
  return reflectivity * std::max(cos_incidence, 0.0) / (r * r);
}

bool LaserSystematicErrors::Any() const {
  return mount_error.translation().squaredNorm() > 0.0 || mount_error.theta_rad != 0.0 ||
         surface_bias_sigma_m > 0.0 || correlated_sigma_m > 0.0 || intensity_bias_m > 0.0 ||
         intensity_sigma_m > 0.0 || stamp_jitter_s > 0.0;
}

void LaserSystematicErrors::Validate() const {
  constexpr double kMaxMountErrorM = 0.1;
  constexpr double kMaxMountErrorRad = 0.1;
  constexpr double kMaxBiasM = 0.5;
  constexpr double kMaxCorrelationReadings = 1e4;
  constexpr double kMaxJitterS = 0.1;
  Require(
      std::abs(mount_error.x_m) <= kMaxMountErrorM && std::abs(mount_error.y_m) <= kMaxMountErrorM,
      "systematic.mount_error", "within 0.1 m in x and y", mount_error.translation().norm());
  Require(std::abs(mount_error.theta_rad) <= kMaxMountErrorRad, "systematic.mount_error",
          "within 0.1 rad in heading", mount_error.theta_rad);
  Require(surface_bias_sigma_m >= 0.0 && surface_bias_sigma_m <= kMaxBiasM,
          "systematic.surface_bias_sigma_m", "in [0, 0.5] m", surface_bias_sigma_m);
  Require(correlated_sigma_m >= 0.0 && correlated_sigma_m <= kMaxBiasM,
          "systematic.correlated_sigma_m", "in [0, 0.5] m", correlated_sigma_m);
  Require(correlation_readings >= 0.1 && correlation_readings <= kMaxCorrelationReadings,
          "systematic.correlation_readings", "in [0.1, 1e4]", correlation_readings);
  Require(intensity_bias_m >= 0.0 && intensity_bias_m <= kMaxBiasM, "systematic.intensity_bias_m",
          "in [0, 0.5] m", intensity_bias_m);
  Require(intensity_sigma_m >= 0.0 && intensity_sigma_m <= kMaxBiasM,
          "systematic.intensity_sigma_m", "in [0, 0.5] m", intensity_sigma_m);
  Require(stamp_jitter_s >= 0.0 && stamp_jitter_s <= kMaxJitterS, "systematic.stamp_jitter_s",
          "in [0, 0.1] s", stamp_jitter_s);
}

void LaserScannerOptions::Validate() const {
  // Bounds that catch unit mistakes (millimetres, degrees, milliseconds).
  constexpr double kMaxRangeM = 1000.0;
  constexpr double kMaxScanRateHz = 1e4;
  constexpr double kMaxTimestampBiasS = 1.0;
  constexpr double kMaxSigmaM = 10.0;
  constexpr double kMaxResolutionM = 1.0;
  constexpr double kMaxDarkSigmaFactor = 1000.0;
  constexpr double kMaxMixedPixelGapM = 100.0;
  Require(profile == "sick_lms200" || profile == "acuity_accurange" || profile == "custom",
          "profile", "sick_lms200, acuity_accurange or custom", 0.0);
  Require(fov_rad > 0.0 && fov_rad <= kTwoPi + kFullTurnToleranceRad, "fov_rad", "in (0, 2π]",
          fov_rad);
  Require(beams >= 2 && beams <= kMaxBeams, "beams", "in [2, 100000]", beams);
  Require(first_bearing_rad >= -kTwoPi && first_bearing_rad <= kTwoPi, "first_bearing_rad",
          "in [-2π, 2π]", first_bearing_rad);
  Require(max_range_m > 0.0 && max_range_m <= kMaxRangeM, "max_range_m", "in (0, 1000] m",
          max_range_m);
  Require(scan_rate_hz > 0.0 && scan_rate_hz <= kMaxScanRateHz, "scan_rate_hz", "in (0, 1e4] Hz",
          scan_rate_hz);
  Require(sweep_s >= 0.0 && sweep_s <= 1.0 / scan_rate_hz, "sweep_s",
          "in [0, 1/scan_rate_hz] (a sweep ends before the next begins)", sweep_s);
  Require(interlaced_turns >= 1 && interlaced_turns <= beams - 1, "interlaced_turns",
          "in [1, beams - 1]", interlaced_turns);
  Require(timestamp_bias_s >= -kMaxTimestampBiasS && timestamp_bias_s <= kMaxTimestampBiasS,
          "timestamp_bias_s", "in [-1, 1] s", timestamp_bias_s);
  Require(range_sigma_m >= 0.0 && range_sigma_m <= kMaxSigmaM, "range_sigma_m", "in [0, 10] m",
          range_sigma_m);
  Require(range_resolution_m >= 0.0 && range_resolution_m <= kMaxResolutionM, "range_resolution_m",
          "in [0, 1] m", range_resolution_m);
  Require(min_amplitude >= 0.0 && min_amplitude <= 1.0, "min_amplitude", "in [0, 1]",
          min_amplitude);
  Require(low_amplitude_sigma_m >= 0.0 && low_amplitude_sigma_m <= kMaxSigmaM,
          "low_amplitude_sigma_m", "in [0, 10] m", low_amplitude_sigma_m);
  Require(outlier_probability >= 0.0 && outlier_probability <= 1.0, "outlier_probability",
          "in [0, 1]", outlier_probability);
  Require(dark_dropout_probability >= 0.0 && dark_dropout_probability <= 1.0,
          "dark_dropout_probability", "in [0, 1]", dark_dropout_probability);
  Require(dark_sigma_factor >= 1.0 && dark_sigma_factor <= kMaxDarkSigmaFactor, "dark_sigma_factor",
          "in [1, 1000]", dark_sigma_factor);
  Require(specular_max_incidence_rad >= 0.0 && specular_max_incidence_rad <= std::numbers::pi / 2,
          "specular_max_incidence_rad", "in [0, π/2]", specular_max_incidence_rad);
  Require(beam_divergence_rad >= 0.0 && beam_divergence_rad <= kMaxBeamDivergenceRad,
          "beam_divergence_rad", "in [0, 0.1]", beam_divergence_rad);
  Require(mixed_pixel_min_gap_m > 0.0 && mixed_pixel_min_gap_m <= kMaxMixedPixelGapM,
          "mixed_pixel_min_gap_m", "in (0, 100] m", mixed_pixel_min_gap_m);
  systematic.Validate();
}

LaserScannerOptions LaserScannerOptions::Profile(const std::string& name) {
  LaserScannerOptions o;  // the defaults are the SICK LMS 200
  if (name == "sick_lms200" || name == "custom") {
    o.profile = name;
    return o;
  }
  if (name == "acuity_accurange") {
    o.profile = name;
    o.fov_rad = kTwoPi;
    o.beams = kAcuityReadingsPerTurn;
    o.first_bearing_rad = -std::numbers::pi;
    o.max_range_m = kAcuityMaxRangeM;
    o.scan_rate_hz = kAcuitySampleRateHz / kAcuityReadingsPerTurn;  // 2.778 Hz, one scan a turn
    o.sweep_s = (kAcuityReadingsPerTurn - 1) / kAcuitySampleRateHz;
    o.interlaced_turns = 1;
    o.timestamp_bias_s = kAcuityTimestampBiasS;
    o.range_sigma_m = kAcuityRangeSigmaM;
    o.range_resolution_m = 0.0;  // analogue output, limited only by the ADC (§2.2.1.6)
    o.amplitude_model = true;
    o.low_amplitude_sigma_m = kAcuityLowAmplitudeSigmaM;
    o.outlier_probability = kAcuityOutlierProbability;
    o.beam_divergence_rad = kAcuityBeamDivergenceRad;
    return o;
  }
  throw std::invalid_argument("unknown laser scanner profile '" + name +
                              "' (expected sick_lms200, acuity_accurange or custom)");
}

LaserScanner::LaserScanner(std::string id, LaserScannerOptions options,
                           core::Pose2 robot_from_sensor, double mount_height_m,
                           core::RandomStream stream)
    : id_(std::move(id)),
      options_(std::move(options)),
      reported_robot_from_sensor_(robot_from_sensor),
      robot_from_sensor_(TrueMount(robot_from_sensor, options_.systematic.mount_error)),
      mount_height_m_(mount_height_m),
      stream_(stream),
      correlated_stream_(options_.systematic.seed, core::RandomStream::StreamId("correlated")),
      jitter_stream_(options_.systematic.seed, core::RandomStream::StreamId("stamp_jitter")) {
  options_.Validate();
  if (!std::isfinite(mount_height_m_)) {
    throw std::invalid_argument("laser scanner mount_height_m must be finite");
  }
  const int n = options_.beams;
  const int k = options_.interlaced_turns;
  const double spacing = AngularSpacing(options_);
  bearings_rad_.resize(n);
  offsets_s_.resize(n);
  // Phase of reading i in mirror turns after the first reading: turn i mod k,
  // plus the mirror angle of its bearing.
  std::vector<double> phase(n);
  for (int i = 0; i < n; ++i) {
    bearings_rad_[i] = options_.first_bearing_rad + i * spacing;
    phase[i] = (i % k) + i * spacing / kTwoPi;
  }
  const double last_phase = *std::max_element(phase.begin(), phase.end());
  for (int i = 0; i < n; ++i) {
    offsets_s_[i] =
        k == 1 ? i * options_.sweep_s / (n - 1) : options_.sweep_s * phase[i] / last_phase;
  }
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](int a, int b) { return offsets_s_[a] < offsets_s_[b]; });
  check_edges_ = options_.effects && options_.beam_divergence_rad > 0.0;
  // The comparison of consecutive readings of a turn finds every edge inside a
  // footprint only if half the footprint fits between them.
  check_every_edge_ = 0.5 * options_.beam_divergence_rad > k * spacing;
}

void LaserScanner::BeginSweep(double start_s) {
  // The sweep's buffers are reused: a scanner starts 10-75 sweeps a second,
  // and a fresh 361-reading sweep is large enough (~100 kB) that allocating
  // it each time cost 5 % of a hall benchmark run in page faults.
  ResetSweep(start_s, &sweep_);
  in_sweep_ = true;
}

bool LaserScanner::SweepComplete() const { return in_sweep_ && sweep_.next == options_.beams; }

void LaserScanner::Cast(const World& world, double t0_s, const core::Pose2& world_from_robot_t0,
                        double t1_s, const core::Pose2& world_from_robot_t1, int ignore_group) {
  Cast(WorldHitFinder(world), t0_s, world_from_robot_t0, t1_s, world_from_robot_t1, ignore_group);
}

void LaserScanner::Cast(const LaserHitFinder& finder, double t0_s,
                        const core::Pose2& world_from_robot_t0, double t1_s,
                        const core::Pose2& world_from_robot_t1, int ignore_group) {
  if (!in_sweep_ || SweepComplete()) return;
  const double duration_s = t1_s - t0_s;
  while (sweep_.next < options_.beams) {
    const int i = order_[sweep_.next];
    const double t = sweep_.start_s + offsets_s_[i];
    if (!(t < t1_s)) break;
    const double s = duration_s > 0.0 ? std::clamp((t - t0_s) / duration_s, 0.0, 1.0) : 0.0;
    CastReading(finder, i, Interpolate(world_from_robot_t0, world_from_robot_t1, s), ignore_group,
                &sweep_);
    ++sweep_.next;
  }
  if (SweepComplete()) {
    scan_ = Finalize(sweep_);
    ApplyFault(&scan_);
    truth_ = std::move(sweep_.truth);
  }
}

core::LaserScan LaserScanner::ScanFrom(const World& world, const core::Pose2& world_from_robot,
                                       double start_s, int ignore_group,
                                       core::LaserScanTruth* truth) {
  return ScanFrom(WorldHitFinder(world), world_from_robot, start_s, ignore_group, truth);
}

core::LaserScan LaserScanner::ScanFrom(const LaserHitFinder& finder,
                                       const core::Pose2& world_from_robot, double start_s,
                                       int ignore_group, core::LaserScanTruth* truth) {
  Sweep sweep = NewSweep(start_s);
  for (const int i : order_) CastReading(finder, i, world_from_robot, ignore_group, &sweep);
  core::LaserScan scan = Finalize(sweep);
  if (truth != nullptr) *truth = std::move(sweep.truth);
  return scan;
}

void LaserScanner::SetFault(const LaserFault& fault) {
  fault_ = fault;
  fault_random_.reset();
  if (fault.mode == LaserFault::Mode::kNoise) fault_random_.emplace(fault.seed, 0);
}

void LaserScanner::ApplyFault(core::LaserScan* scan) {
  const bool active = fault_.mode != LaserFault::Mode::kNone && scan->stamp_s >= fault_.from_s &&
                      scan->stamp_s < fault_.until_s;
  if (!active) {
    last_good_ = *scan;
    return;
  }
  switch (fault_.mode) {
    case LaserFault::Mode::kBlackout:
      for (core::LaserReading& r : scan->readings) {
        r.range_m = scan->max_range_m;
        r.valid = false;
        r.reflector = false;
      }
      break;
    case LaserFault::Mode::kNoise:
      for (core::LaserReading& r : scan->readings) {
        if (!r.valid) continue;
        r.range_m = std::clamp(r.range_m + fault_random_->Normal(0.0, fault_.extra_sigma_m), 0.0,
                               scan->max_range_m);
      }
      break;
    case LaserFault::Mode::kStuck:
      if (last_good_.readings.size() == scan->readings.size()) {
        for (std::size_t i = 0; i < scan->readings.size(); ++i) {
          core::LaserReading& r = scan->readings[i];
          r.range_m = last_good_.readings[i].range_m;
          r.valid = last_good_.readings[i].valid;
          r.reflector = last_good_.readings[i].reflector;
        }
      }
      break;
    case LaserFault::Mode::kNone:
      break;
  }
}

LaserScanner::Sweep LaserScanner::NewSweep(double start_s) const {
  Sweep sweep;
  ResetSweep(start_s, &sweep);
  return sweep;
}

void LaserScanner::ResetSweep(double start_s, Sweep* sweep) const {
  sweep->start_s = start_s;
  sweep->next = 0;
  const std::size_t n = options_.beams;
  if (sweep->geometry.size() == n) {
    // Every reading's central ray is cast anew in the sweep, and an edge's
    // surface is read only where its fraction is positive: the fractions
    // alone must start at zero. (Rewriting the whole geometry, ~110 kB a
    // sweep, cost 2 % of an expo_day run.)
    for (ReadingGeometry& g : sweep->geometry) g.edge_fraction = {0.0, 0.0};
  } else {
    sweep->geometry.assign(n, ReadingGeometry{});
  }
  sweep->truth.world_from_sensor.assign(n, core::Pose2{});
  sweep->truth.true_range_m.assign(n, options_.max_range_m);
  sweep->truth.element.assign(n, -1);
}

Eigen::Vector3d LaserScanner::RayOrigin(const core::Pose2& world_from_sensor) const {
  return {world_from_sensor.x_m, world_from_sensor.y_m, mount_height_m_};
}

LaserScanner::RaySample LaserScanner::CastBeam(const LaserHitFinder& finder,
                                               const core::Pose2& world_from_sensor,
                                               double bearing_rad, int ignore_group,
                                               double max_range_m) const {
  return CastAlong(finder, world_from_sensor, BeamDirection(world_from_sensor, bearing_rad),
                   ignore_group, max_range_m);
}

LaserScanner::RaySample LaserScanner::CastAlong(const LaserHitFinder& finder,
                                                const core::Pose2& world_from_sensor,
                                                const Eigen::Vector3d& dir, int ignore_group,
                                                double max_range_m) const {
  const Eigen::Vector3d from = RayOrigin(world_from_sensor);
  // Transparent elements are skipped by the finder itself.
  ++rays_cast_;
  const RayHit hit = finder.Cast(
      from, dir.head<2>(), max_range_m < 0.0 ? options_.max_range_m : max_range_m, ignore_group);
  RaySample s;
  s.direction = dir;
  if (!hit.hit) return s;
  s.hit = true;
  s.range_m = hit.distance_m;
  s.point_m = hit.point_m;
  s.normal = hit.normal;
  // Incidence: the angle between the reversed ray and the surface normal.
  s.cos_incidence = std::clamp(-dir.dot(hit.normal), 0.0, 1.0);
  s.element = hit.element;
  const auto& elements = finder.elements();
  if (hit.element >= 0 && hit.element < static_cast<int>(elements.size())) {
    s.response = elements[hit.element].laser;
  }
  return s;
}

// True when `sample`, cast from `world_from_sensor` (along sample.direction), met
// the plane of `surface` within the mixed-pixel gap (or both met nothing): no
// depth edge between them.
bool LaserScanner::Explains(const RaySample& surface, const core::Pose2& world_from_sensor,
                            const RaySample& sample) const {
  if (!surface.hit) return !sample.hit;
  if (!sample.hit) return false;
  const Eigen::Vector3d& dir = sample.direction;
  const double cos_plane = surface.normal.dot(dir);
  if (cos_plane > -kMinPlaneCosine) return false;
  const double predicted_m =
      surface.normal.dot(surface.point_m - RayOrigin(world_from_sensor)) / cos_plane;
  return std::abs(sample.range_m - predicted_m) <= options_.mixed_pixel_min_gap_m;
}

// A probe explained by `surface` hits within the mixed-pixel gap of where the
// ray meets the surface's plane: nothing farther matters, so the ray stops
// there (a bisection's probes that pass an edge into the background no longer
// walk the whole range). The decision is Explains()'s: a hit it explains lies
// short of the limit, and one beyond it is not explained, cast or not. Only
// with a finder whose short rays agree with its long ones (the planar
// caster); Bullet's probes keep the full range.
bool LaserScanner::ExplainsBeam(const LaserHitFinder& finder, const RaySample& surface,
                                const core::Pose2& world_from_sensor, double bearing_rad,
                                int ignore_group) const {
  if (surface.hit && finder.ShortRaysAgree()) {
    const Eigen::Vector3d dir = BeamDirection(world_from_sensor, bearing_rad);
    const double cos_plane = surface.normal.dot(dir);
    if (cos_plane > -kMinPlaneCosine) return false;
    const double predicted_m =
        surface.normal.dot(surface.point_m - RayOrigin(world_from_sensor)) / cos_plane;
    const double reach_m = predicted_m + options_.mixed_pixel_min_gap_m + kProbeSlackM;
    if (!(reach_m > 0.0)) return false;
    if (reach_m < options_.max_range_m) {
      return Explains(surface, world_from_sensor,
                      CastAlong(finder, world_from_sensor, dir, ignore_group, reach_m));
    }
  }
  return Explains(surface, world_from_sensor,
                  CastBeam(finder, world_from_sensor, bearing_rad, ignore_group));
}

void LaserScanner::CastReading(const LaserHitFinder& finder, int i,
                               const core::Pose2& world_from_robot, int ignore_group,
                               Sweep* sweep) const {
  const core::Pose2 world_from_sensor = world_from_robot * robot_from_sensor_;
  ReadingGeometry& g = sweep->geometry[i];
  g.centre = CastBeam(finder, world_from_sensor, bearings_rad_[i], ignore_group);
  sweep->truth.world_from_sensor[i] = world_from_sensor;
  if (g.centre.hit) {
    sweep->truth.true_range_m[i] = g.centre.range_m;
    sweep->truth.element[i] = g.centre.element;
  }
  if (!check_edges_) return;
  if (check_every_edge_) {
    CheckEdge(finder, i, 0, ignore_group, sweep);
    CheckEdge(finder, i, 1, ignore_group, sweep);
    return;
  }
  // The previous reading of this turn was taken just before this one; a depth
  // edge inside either footprint shows as a discontinuity between the two.
  const int k = options_.interlaced_turns;
  const int previous = i - k;
  if (previous < 0) {
    CheckEdge(finder, i, 0, ignore_group, sweep);
  } else {
    const ReadingGeometry& p = sweep->geometry[previous];
    const core::Pose2& world_from_previous = sweep->truth.world_from_sensor[previous];
    if (!Explains(p.centre, world_from_sensor, g.centre) ||
        !Explains(g.centre, world_from_previous, p.centre)) {
      CheckEdge(finder, previous, 1, ignore_group, sweep);
      CheckEdge(finder, i, 0, ignore_group, sweep);
    }
  }
  if (i + k >= options_.beams) CheckEdge(finder, i, 1, ignore_group, sweep);
}

// Casts the edge ray of reading i on one side (0: clockwise, 1: counter-
// clockwise) from the pose the reading was taken at; where it meets another
// surface than the central ray, locates the edge by bisection and records the
// fraction of the footprint beyond it.
void LaserScanner::CheckEdge(const LaserHitFinder& finder, int i, int side, int ignore_group,
                             Sweep* sweep) const {
  ReadingGeometry& g = sweep->geometry[i];
  const core::Pose2& world_from_sensor = sweep->truth.world_from_sensor[i];
  const double half_rad = 0.5 * options_.beam_divergence_rad;
  const double sign = side == 0 ? -1.0 : 1.0;
  const double bearing = bearings_rad_[i];
  const RaySample edge =
      CastBeam(finder, world_from_sensor, bearing + sign * half_rad, ignore_group);
  if (Explains(g.centre, world_from_sensor, edge)) return;
  double explained_rad = 0.0;
  double unexplained_rad = half_rad;
  for (int step = 0; step < kEdgeBisections; ++step) {
    const double mid_rad = 0.5 * (explained_rad + unexplained_rad);
    const double b = bearing + sign * mid_rad;
    if (ExplainsBeam(finder, g.centre, world_from_sensor, b, ignore_group)) {
      explained_rad = mid_rad;
    } else {
      unexplained_rad = mid_rad;
    }
  }
  const double edge_rad = 0.5 * (explained_rad + unexplained_rad);
  g.edge_fraction[side] = (half_rad - edge_rad) / options_.beam_divergence_rad;
  g.edge[side] = edge;
}

// Amplitude of the light a surface returns (§2.2.1.3); 0 for no return. A
// specular surface returns nothing beyond its incidence limit. Without
// effects every surface answers as a normal one.
double LaserScanner::Amplitude(const RaySample& sample) const {
  if (!sample.hit) return 0.0;
  if (!options_.effects) {
    return RelativeAmplitude(kNormalReflectivity, sample.range_m, sample.cos_incidence);
  }
  if (sample.response == core::LaserResponse::kSpecular &&
      sample.cos_incidence < std::cos(options_.specular_max_incidence_rad)) {
    return 0.0;
  }
  return RelativeAmplitude(LaserReflectivity(sample.response), sample.range_m,
                           sample.cos_incidence);
}

// Applies the error models to the geometry of a sweep, reading by reading in
// index order (every random draw in that order, from this sensor's stream).
core::LaserScan LaserScanner::Finalize(const Sweep& sweep) {
  const LaserScannerOptions& o = options_;
  core::LaserScan scan;
  scan.sensor_id = id_;
  const LaserSystematicErrors& sys = o.systematic;
  scan.stamp_s = sweep.start_s + o.timestamp_bias_s;  // constant bias, §2.2.1.5
  if (sys.stamp_jitter_s > 0.0) scan.stamp_s += jitter_stream_.Normal(0.0, sys.stamp_jitter_s);
  scan.max_range_m = o.max_range_m;
  scan.robot_from_sensor = reported_robot_from_sensor_;
  // Correlated range noise, one AR(1) step per reading in index order whatever
  // it returns, so that its law does not depend on the scene.
  const bool correlated = o.noise && sys.correlated_sigma_m > 0.0;
  const double rho = correlated ? std::exp(-1.0 / sys.correlation_readings) : 0.0;
  const double innovation_sigma_m = sys.correlated_sigma_m * std::sqrt(1.0 - rho * rho);
  scan.readings.resize(o.beams);
  auto quantize = [&](double r) {
    return o.range_resolution_m > 0.0 ? std::round(r / o.range_resolution_m) * o.range_resolution_m
                                      : r;
  };
  for (int i = 0; i < o.beams; ++i) {
    core::LaserReading& reading = scan.readings[i];
    reading.bearing_rad = bearings_rad_[i];
    reading.time_offset_s = offsets_s_[i];
    reading.range_m = o.max_range_m;
    const ReadingGeometry& g = sweep.geometry[i];
    if (correlated) {
      correlated_state_m_ =
          correlated_started_
              ? rho * correlated_state_m_ + correlated_stream_.Normal(0.0, innovation_sigma_m)
              : correlated_stream_.Normal(0.0, sys.correlated_sigma_m);
      correlated_started_ = true;
    }

    // Outlier (§2.2.1.6): a uniform range in (0, max range), whatever was hit.
    if (o.noise && o.outlier_probability > 0.0 && stream_.Uniform() < o.outlier_probability) {
      const double r = quantize((stream_.Uniform() + kHalfUniformStep) * o.max_range_m);
      reading.valid = r < o.max_range_m;
      if (reading.valid) reading.range_m = r;
      continue;
    }

    double amplitude = 0.0;
    double retro_amplitude = 0.0;
    double range_m = FootprintReturn(g, &amplitude, &retro_amplitude);
    if (!(amplitude > 0.0)) continue;  // no return
    // How far the return is below the white target's, on the intensity errors'
    // scale (only when an intensity error is on: a log per reading).
    const double weakness =
        sys.intensity_bias_m > 0.0 || sys.intensity_sigma_m > 0.0
            ? std::clamp(-std::log10(amplitude) / kIntensityBiasDecades, 0.0, 1.0)
            : 0.0;
    range_m += sys.intensity_bias_m * weakness;

    const bool dark = o.effects && g.centre.hit && g.centre.response == core::LaserResponse::kDark;
    if (dark && o.noise && o.dark_dropout_probability > 0.0 &&
        stream_.Uniform() < o.dark_dropout_probability) {
      continue;  // dropout
    }
    if (o.noise) {
      // Amplitude-dependent σ (§2.2.1.3, Fig. 2.3): constant above s_min.
      double sigma_m = o.amplitude_model && amplitude < o.min_amplitude ? o.low_amplitude_sigma_m
                                                                        : o.range_sigma_m;
      if (dark) sigma_m *= o.dark_sigma_factor;
      if (sys.intensity_sigma_m > 0.0)
        sigma_m = std::hypot(sigma_m, sys.intensity_sigma_m * weakness);
      if (sigma_m > 0.0) range_m += stream_.Normal(0.0, sigma_m);
    }
    if (correlated) range_m += correlated_state_m_;
    range_m = quantize(std::max(range_m, 0.0));
    if (range_m >= o.max_range_m) continue;  // beyond the measuring range
    reading.range_m = range_m;
    reading.valid = true;
    // The reflector bit (§3.3): the return is mostly from retro-reflective sheeting.
    reading.reflector = retro_amplitude > kReflectorAmplitudeShare * amplitude;
  }
  return scan;
}

// The footprint's parts: centre, and the parts beyond an edge on either side.
// The return is their amplitude-weighted mean range (mixed pixel), each part's
// range with its surface's bias.
double LaserScanner::FootprintReturn(const ReadingGeometry& g, double* amplitude,
                                     double* retro_amplitude) {
  const RaySample* parts[3] = {&g.centre, &g.edge[0], &g.edge[1]};
  const double weights[3] = {1.0 - g.edge_fraction[0] - g.edge_fraction[1], g.edge_fraction[0],
                             g.edge_fraction[1]};
  const bool biased = options_.systematic.surface_bias_sigma_m > 0.0;
  double weighted_range_m = 0.0;
  for (int p = 0; p < 3; ++p) {
    if (weights[p] <= 0.0) continue;
    const double a = weights[p] * Amplitude(*parts[p]);
    *amplitude += a;
    const double bias_m = biased && a > 0.0 ? SurfaceBias(parts[p]->element) : 0.0;
    weighted_range_m += a * (parts[p]->range_m + bias_m);
    if (parts[p]->response == core::LaserResponse::kRetroReflective) *retro_amplitude += a;
  }
  return *amplitude > 0.0 ? weighted_range_m / *amplitude : 0.0;
}

double LaserScanner::SurfaceBias(int element) {
  if (element < 0) return 0.0;
  if (static_cast<std::size_t>(element) >= surface_bias_m_.size()) {
    surface_bias_m_.resize(element + 1, std::numeric_limits<double>::quiet_NaN());
  }
  double& bias = surface_bias_m_[element];
  if (std::isnan(bias)) {
    // One stream per element: the bias depends on the seed and the element
    // alone, not on which scanner meets it first.
    core::RandomStream draw(options_.systematic.surface_seed, static_cast<std::uint64_t>(element));
    bias = draw.Normal(0.0, options_.systematic.surface_bias_sigma_m);
  }
  return bias;
}

}  // namespace pavilion::sim
