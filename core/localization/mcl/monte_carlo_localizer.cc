#include "core/localization/mcl/monte_carlo_localizer.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <utility>

namespace pavilion::core {
namespace {

using Vec2 = Eigen::Vector2d;

constexpr int kMinParticles = 10;
constexpr int kMaxParticles = 100000;
constexpr int kMaxBeams = 1000;
constexpr double kMaxSigmaHitM = 10.0;
constexpr double kMaxWheelKM = 1.0;

// A square root S of a symmetric positive semi-definite matrix, S S^T = m.
template <int N>
Eigen::Matrix<double, N, N> SquareRoot(const Eigen::Matrix<double, N, N>& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(m);
  return eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
}

void Require(bool ok, const char* message) {
  if (!ok) throw std::invalid_argument(message);
}

}  // namespace

void MonteCarloOptions::Validate() const {
  Require(particles >= kMinParticles && particles <= kMaxParticles,
          "MonteCarloOptions.particles must be in [10, 100000]");
  Require(beams >= 1 && beams <= kMaxBeams, "MonteCarloOptions.beams must be in [1, 1000]");
  Require(sigma_hit_m > 0.0 && sigma_hit_m <= kMaxSigmaHitM,
          "MonteCarloOptions.sigma_hit_m must be in (0, 10] m");
  Require(z_hit >= 0.0 && z_hit <= 1.0, "MonteCarloOptions.z_hit must be in [0, 1]");
  Require(z_rand >= 0.0 && z_rand <= 1.0, "MonteCarloOptions.z_rand must be in [0, 1]");
  Require(z_hit + z_rand > 0.0, "MonteCarloOptions.z_hit + z_rand must be > 0");
  Require(alpha_slow > 0.0 && alpha_slow < 1.0, "MonteCarloOptions.alpha_slow must be in (0, 1)");
  Require(alpha_fast > alpha_slow && alpha_fast < 1.0,
          "MonteCarloOptions.alpha_fast must be in (alpha_slow, 1)");
  Require(update_min_d_m >= 0.0 && std::isfinite(update_min_d_m),
          "MonteCarloOptions.update_min_d_m must be >= 0 m");
  Require(update_min_a_rad >= 0.0 && std::isfinite(update_min_a_rad),
          "MonteCarloOptions.update_min_a_rad must be >= 0 rad");
  Require(resample_interval >= 1, "MonteCarloOptions.resample_interval must be >= 1");
  Require(wheel_k_floor_m >= 0.0 && wheel_k_floor_m <= kMaxWheelKM,
          "MonteCarloOptions.wheel_k_floor_m must be in [0, 1] m");
  Require(converged_spread_m > 0.0, "MonteCarloOptions.converged_spread_m must be > 0 m");
  Require(converged_heading_sigma_rad > 0.0,
          "MonteCarloOptions.converged_heading_sigma_rad must be > 0 rad");
  field.Validate();
  free_space.Validate();
}

MonteCarloLocalizer::MonteCarloLocalizer(RobotMap map, const EncoderOdometryOptions& odometry,
                                         const MonteCarloOptions& options)
    : odometry_((odometry.Validate(), odometry)),
      options_((options.Validate(), options)),
      field_(map, options.field),
      free_space_(map, options.free_space),
      random_(options.seed, options.stream_id) {
  const WheelNoise calibrated = odometry_.noise();
  particle_noise_ = {std::max(calibrated.k_left_m, options_.wheel_k_floor_m),
                     std::max(calibrated.k_right_m, options_.wheel_k_floor_m), calibrated.k_turn_m};
  // Pose2{} start with a point cloud there until an Initialize*.
  Initialize(PoseWithCovariance{});
}

void MonteCarloLocalizer::ResetFilter() {
  update_pending_ = true;
  posterior_count_ = particles_.size();
  w_slow_ = 0.0;
  w_fast_ = 0.0;
  UpdateEstimate();
}

Particle MonteCarloLocalizer::RandomParticle() {
  const Vec2 p = free_space_.Sample(random_);
  const double heading = random_.Uniform(-std::numbers::pi, std::numbers::pi);
  return {{p.x(), p.y(), NormalizeAngle(heading)}, 0.0};
}

void MonteCarloLocalizer::InitializeGlobal() {
  particles_.clear();
  const double weight = 1.0 / options_.particles;
  for (int i = 0; i < options_.particles; ++i) {
    particles_.push_back(RandomParticle());
    particles_.back().weight = weight;
  }
  ResetFilter();
}

void MonteCarloLocalizer::Initialize(const PoseWithCovariance& start) {
  const Eigen::Matrix3d root = SquareRoot<3>(start.covariance);
  particles_.clear();
  const double weight = 1.0 / options_.particles;
  for (int i = 0; i < options_.particles; ++i) {
    Eigen::Vector3d n;
    for (int k = 0; k < 3; ++k) n[k] = random_.Normal();
    const Eigen::Vector3d d = root * n;
    particles_.push_back({{start.pose.x_m + d[0], start.pose.y_m + d[1],
                           NormalizeAngle(start.pose.theta_rad + d[2])},
                          weight});
  }
  ResetFilter();
}

void MonteCarloLocalizer::AddEncoders(const EncoderReading& reading) {
  if (!last_encoders_) {
    last_encoders_ = reading;
    return;
  }
  const WheelTravel travel = WheelTravelFromEncoders(*last_encoders_, reading, odometry_);
  last_encoders_ = reading;
  if (travel.left_m == 0.0 && travel.right_m == 0.0) return;
  const double b = odometry_.wheelbase_m;
  odometry_pose_ = DiffDriveStep(odometry_pose_, travel, b);
  // One factor for every particle: U depends on the travel only (eq. 2.9).
  const Eigen::Matrix2d root = SquareRoot<2>(WheelTravelCovariance(travel, particle_noise_));
  for (Particle& p : particles_) {
    const double n0 = random_.Normal();
    const double n1 = random_.Normal();
    const Eigen::Vector2d du = root * Eigen::Vector2d(n0, n1);  // [s_r, s_l]
    p.pose = DiffDriveStep(p.pose,
                           {travel.left_m + du[kLeftWheel], travel.right_m + du[kRightWheel]}, b);
  }
  UpdateEstimate();
}

std::vector<Vec2> MonteCarloLocalizer::BeamEndsInRobot(const LaserScan& scan) const {
  std::vector<int> usable;
  for (int i = 0; i < static_cast<int>(scan.readings.size()); ++i) {
    const LaserReading& r = scan.readings[static_cast<std::size_t>(i)];
    if (r.valid && std::isfinite(r.range_m) && r.range_m > 0.0 && r.range_m < scan.max_range_m) {
      usable.push_back(i);
    }
  }
  const int n = static_cast<int>(usable.size());
  const int count = std::min(n, options_.beams);
  std::vector<Vec2> ends;
  ends.reserve(static_cast<std::size_t>(count));
  for (int j = 0; j < count; ++j) {
    // The j-th of `count` equal slices of the usable readings, at its middle.
    const long pick = (2L * j + 1) * n / (2L * count);
    const LaserReading& r = scan.readings[static_cast<std::size_t>(usable[std::size_t(pick)])];
    ends.push_back(scan.robot_from_sensor *
                   Vec2(r.range_m * std::cos(r.bearing_rad), r.range_m * std::sin(r.bearing_rad)));
  }
  return ends;
}

bool MonteCarloLocalizer::AddScan(const LaserScan& scan) {
  if (!update_pending_) {
    const double moved_m = (odometry_pose_.translation() - last_update_pose_.translation()).norm();
    const double turned_rad =
        std::abs(NormalizeAngle(odometry_pose_.theta_rad - last_update_pose_.theta_rad));
    if (moved_m <= options_.update_min_d_m && turned_rad <= options_.update_min_a_rad) {
      return false;
    }
  }
  const std::vector<Vec2> ends = BeamEndsInRobot(scan);
  if (ends.empty()) return false;
  Weigh(ends, scan.max_range_m);
  last_beams_ = static_cast<int>(ends.size());
  last_update_pose_ = odometry_pose_;
  update_pending_ = false;
  ++updates_;
  posterior_count_ = particles_.size();
  if (updates_ % options_.resample_interval == 0) Resample();
  UpdateEstimate();
  return true;
}

void MonteCarloLocalizer::BuildLogLikelihoodTable(double max_range_m) {
  // Table 6.3: p = z_hit prob(dist, sigma_hit) + z_rand / z_max, with prob the
  // Gaussian density (nav2 drops its normalizer; we keep Thrun's).
  const double sigma = options_.sigma_hit_m;
  const double density = 1.0 / (std::sqrt(2.0 * std::numbers::pi) * sigma);
  const double uniform = options_.z_rand / max_range_m;
  const auto log_p = [&](double d) {
    return std::log(options_.z_hit * density * std::exp(-0.5 * d * d / (sigma * sigma)) + uniform);
  };
  log_p_cell_.resize(static_cast<std::size_t>(field_.cell_count()));
  for (long i = 0; i < field_.cell_count(); ++i) {
    log_p_cell_[static_cast<std::size_t>(i)] = static_cast<float>(log_p(field_.CellDistanceM(i)));
  }
  log_p_off_grid_ = log_p(field_.max_distance_m());
  table_max_range_m_ = max_range_m;
}

void MonteCarloLocalizer::Weigh(const std::vector<Vec2>& ends_in_robot, double max_range_m) {
  if (max_range_m != table_max_range_m_) BuildLogLikelihoodTable(max_range_m);
  const std::size_t m = particles_.size();
  log_likelihood_.resize(m);
  double max_log = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < m; ++i) {
    const Pose2& pose = particles_[i].pose;
    const double c = std::cos(pose.theta_rad);
    const double s = std::sin(pose.theta_rad);
    double sum = 0.0;
    for (const Vec2& e : ends_in_robot) {
      const Vec2 end_in_map(pose.x_m + c * e.x() - s * e.y(), pose.y_m + s * e.x() + c * e.y());
      const long cell = field_.CellIndex(end_in_map);
      sum += cell < 0 ? log_p_off_grid_ : log_p_cell_[static_cast<std::size_t>(cell)];
    }
    log_likelihood_[i] = sum;
    max_log = std::max(max_log, sum);
  }
  // Weights w_i p_i, scaled by exp(-max_log) for range; w_avg = sum_i w_i p_i
  // is table 8.3's average likelihood (uniform w_i after each resampling).
  double scaled_sum = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    particles_[i].weight *= std::exp(log_likelihood_[i] - max_log);
    scaled_sum += particles_[i].weight;
  }
  if (!(scaled_sum > 0.0)) {  // every prior weight underflowed: start afresh
    for (Particle& p : particles_) p.weight = 1.0 / static_cast<double>(m);
    scaled_sum = 1.0 / static_cast<double>(m);
  } else {
    for (Particle& p : particles_) p.weight /= scaled_sum;
  }
  const double w_avg = std::exp(max_log) * scaled_sum;
  // Table 8.3's averages, started at the first average instead of 0 (as nav2
  // AMCL's pf.c does): a cold w_slow of 0 would keep recovery asleep for
  // ~1/alpha_slow updates (250 m of travel at update_min_d). nav2 also
  // restarts both after an injection, which leaves one small burst per loss;
  // table 8.3 keeps injecting while w_fast < w_slow, which recovers far more
  // often, and is kept here.
  if (w_slow_ == 0.0) {
    w_slow_ = w_avg;
    w_fast_ = w_avg;
  } else {
    w_slow_ += options_.alpha_slow * (w_avg - w_slow_);
    w_fast_ += options_.alpha_fast * (w_avg - w_fast_);
  }
}

void MonteCarloLocalizer::Resample() {
  const int m = static_cast<int>(particles_.size());
  const double p_random = (w_slow_ > 0.0 && free_space_.free_cells() > 0)
                              ? std::max(0.0, 1.0 - w_fast_ / w_slow_)
                              : 0.0;
  int random_count = 0;
  if (p_random > 0.0) {
    for (int i = 0; i < m; ++i) random_count += random_.Uniform() < p_random ? 1 : 0;
  }
  const int kept = m - random_count;
  std::vector<Particle> next;
  next.reserve(static_cast<std::size_t>(m));
  if (kept > 0) {  // Low_variance_sampler, table 4.4
    const double step = 1.0 / kept;
    const double r = random_.Uniform(0.0, step);
    double cumulative = particles_[0].weight;
    int i = 0;
    for (int k = 0; k < kept; ++k) {
      const double u = r + k * step;
      while (u > cumulative && i + 1 < m)
        cumulative += particles_[static_cast<std::size_t>(++i)].weight;
      next.push_back(particles_[static_cast<std::size_t>(i)]);
    }
  }
  for (int k = 0; k < random_count; ++k) next.push_back(RandomParticle());
  const double weight = 1.0 / m;
  for (Particle& p : next) p.weight = weight;
  particles_ = std::move(next);
  posterior_count_ = static_cast<std::size_t>(kept > 0 ? kept : m);
}

void MonteCarloLocalizer::UpdateEstimate() {
  const std::span<const Particle> posterior(particles_.data(),
                                            std::min(posterior_count_, particles_.size()));
  double x = 0.0, y = 0.0, sin_sum = 0.0, cos_sum = 0.0, total = 0.0;
  for (const Particle& p : posterior) {
    x += p.weight * p.pose.x_m;
    y += p.weight * p.pose.y_m;
    sin_sum += p.weight * std::sin(p.pose.theta_rad);
    cos_sum += p.weight * std::cos(p.pose.theta_rad);
    total += p.weight;
  }
  if (!(total > 0.0)) return;
  const Pose2 mean{x / total, y / total, std::atan2(sin_sum, cos_sum)};
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Particle& p : posterior) {
    const Eigen::Vector3d d(p.pose.x_m - mean.x_m, p.pose.y_m - mean.y_m,
                            NormalizeAngle(p.pose.theta_rad - mean.theta_rad));
    covariance += p.weight * d * d.transpose();
  }
  estimate_ = {mean, covariance / total};
}

double MonteCarloLocalizer::position_spread_m() const {
  const Eigen::Matrix3d& c = estimate_.covariance;
  const double half_trace = 0.5 * (c(0, 0) + c(1, 1));
  const double half_diff = 0.5 * (c(0, 0) - c(1, 1));
  const double largest = half_trace + std::sqrt(half_diff * half_diff + c(0, 1) * c(0, 1));
  return std::sqrt(std::max(0.0, largest));
}

bool MonteCarloLocalizer::converged() const {
  return position_spread_m() <= options_.converged_spread_m &&
         std::sqrt(std::max(0.0, estimate_.covariance(2, 2))) <=
             options_.converged_heading_sigma_rad;
}

}  // namespace pavilion::core
