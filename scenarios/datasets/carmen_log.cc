#include "scenarios/datasets/carmen_log.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "scenarios/config/input_error.h"

namespace pavilion::scenarios {
namespace {

// Field of view of every FLASER scan (README of the data set): 180°.
constexpr double kFovRad = std::numbers::pi;
// First reading at -90°, the robot's right.
constexpr double kFirstBearingRad = -std::numbers::pi / 2.0;
// Upper bound on readings per message, a guard against corrupt counts.
constexpr int kMaxReadings = 100000;
// FLASER: type, n, n ranges, x y theta, odom x y theta, timestamp; then
// optionally host and logger timestamp.
constexpr int kFlaserFixedNumbers = 7;
constexpr int kFlaserOptionalTokens = 2;
// ODOM: type, x y theta tv rv accel timestamp; then optionally host and logger
// timestamp.
constexpr int kOdomNumbers = 7;
constexpr int kOdomOptionalTokens = 2;
// gzip read buffer.
constexpr unsigned kGzBufferBytes = 1u << 18;

double StepRad(int num_readings, CarmenAngleStep step) {
  const int divisions = step == CarmenAngleStep::kFovOverN ? num_readings : num_readings - 1;
  return divisions > 0 ? kFovRad / divisions : 0.0;
}

std::vector<std::string_view> Tokenize(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

std::optional<double> ParseDouble(std::string_view token) {
  double value = 0.0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<int> ParseInt(std::string_view token) {
  int value = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

// Reads lines from a plain or gzip file (gzread passes plain files through).
class LineReader {
 public:
  explicit LineReader(const std::string& path) : file_(gzopen(path.c_str(), "rb")) {
    if (file_ == nullptr) {
      throw InputError(Diagnostic{path, 0, "", "cannot open the CARMEN log for reading"});
    }
    gzbuffer(file_, kGzBufferBytes);
  }
  ~LineReader() { gzclose(file_); }
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // Next line without its newline; false at end of file. Throws on a read error.
  bool Next(const std::string& path, std::string* line) {
    line->clear();
    char chunk[4096];
    while (gzgets(file_, chunk, sizeof(chunk)) != nullptr) {
      line->append(chunk);
      if (!line->empty() && line->back() == '\n') {
        line->pop_back();
        if (!line->empty() && line->back() == '\r') line->pop_back();
        return true;
      }
    }
    int error = Z_OK;
    const char* message = gzerror(file_, &error);
    if (error != Z_OK && error != Z_STREAM_END) {
      throw InputError(Diagnostic{path, 0, "", std::string("read error: ") + message});
    }
    return !line->empty();
  }

 private:
  gzFile file_;
};

struct OdomInterval {
  std::optional<core::Pose2> anchor;  // first ODOM after the previous FLASER
  std::optional<core::Pose2> last;    // last ODOM so far (after the anchor)
};

[[noreturn]] void Malformed(const std::string& path, int line, const std::string& type,
                            const std::string& message) {
  throw InputError(Diagnostic{path, line, type, message});
}

CarmenScan ParseFlaser(const std::vector<std::string_view>& tokens, const std::string& path,
                       int line, const CarmenOptions& options) {
  const std::optional<int> n = tokens.size() > 1 ? ParseInt(tokens[1]) : std::nullopt;
  if (!n || *n < 2 || *n > kMaxReadings) {
    Malformed(path, line, "FLASER",
              "expected the number of readings (an integer in [2, " + std::to_string(kMaxReadings) +
                  "]) as the second field");
  }
  const std::size_t numbers = static_cast<std::size_t>(*n) + kFlaserFixedNumbers;
  const std::size_t min_tokens = 2 + numbers;
  if (tokens.size() < min_tokens || tokens.size() > min_tokens + kFlaserOptionalTokens) {
    Malformed(path, line, "FLASER",
              "expected " + std::to_string(min_tokens) + " to " +
                  std::to_string(min_tokens + kFlaserOptionalTokens) + " fields for n = " +
                  std::to_string(*n) + ", found " + std::to_string(tokens.size()));
  }
  std::vector<double> values(numbers);
  for (std::size_t i = 0; i < numbers; ++i) {
    const std::optional<double> v = ParseDouble(tokens[2 + i]);
    if (!v) {
      Malformed(path, line, "FLASER",
                "expected a finite number as field " + std::to_string(3 + i) + ", found '" +
                    std::string(tokens[2 + i]) + "'");
    }
    values[i] = *v;
  }
  CarmenScan out;
  out.line = line;
  out.scan.sensor_id = "flaser";
  out.scan.max_range_m = options.max_range_m;
  out.scan.readings.resize(static_cast<std::size_t>(*n));
  for (int i = 0; i < *n; ++i) {
    core::LaserReading& reading = out.scan.readings[static_cast<std::size_t>(i)];
    const double range_m = values[static_cast<std::size_t>(i)];
    reading.valid = range_m > 0.0 && range_m < options.max_range_m;
    reading.range_m = reading.valid ? range_m : options.max_range_m;
    reading.bearing_rad = CarmenBearingRad(i, *n, options.angle_step);
  }
  const double* pose = values.data() + *n;
  out.world_from_laser = {pose[0], pose[1], core::NormalizeAngle(pose[2])};
  out.stamp_s = pose[6];
  out.scan.stamp_s = out.stamp_s;
  return out;
}

core::Pose2 ParseOdom(const std::vector<std::string_view>& tokens, const std::string& path,
                      int line) {
  const std::size_t min_tokens = 1 + kOdomNumbers;
  if (tokens.size() < min_tokens || tokens.size() > min_tokens + kOdomOptionalTokens) {
    Malformed(path, line, "ODOM",
              "expected " + std::to_string(min_tokens) + " to " +
                  std::to_string(min_tokens + kOdomOptionalTokens) +
                  " fields (ODOM x y theta tv rv accel timestamp [host logger_timestamp]), found " +
                  std::to_string(tokens.size()));
  }
  double values[kOdomNumbers];
  for (int i = 0; i < kOdomNumbers; ++i) {
    const std::optional<double> v = ParseDouble(tokens[static_cast<std::size_t>(1 + i)]);
    if (!v) {
      Malformed(path, line, "ODOM",
                "expected a finite number as field " + std::to_string(2 + i) + ", found '" +
                    std::string(tokens[static_cast<std::size_t>(1 + i)]) + "'");
    }
    values[i] = *v;
  }
  return {values[0], values[1], core::NormalizeAngle(values[2])};
}

// A straight run of consecutive valid readings of one scan.
struct Run {
  std::size_t scan = 0;
  std::vector<int> indices;
};

Eigen::Vector2d Point(const core::LaserReading& r, double bearing_rad) {
  return {r.range_m * std::cos(bearing_rad), r.range_m * std::sin(bearing_rad)};
}

// Iterative end-point fit on points[first..last] (inclusive), appending the
// pieces that are straight within `split_distance_m`.
void SplitRun(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& indices,
              std::size_t first, std::size_t last, const CarmenStraightnessOptions& options,
              std::vector<std::vector<int>>* runs) {
  if (last < first + 2) return;  // too short to matter
  const Eigen::Vector2d a = points[first];
  const Eigen::Vector2d chord = points[last] - a;
  const double length = chord.norm();
  std::size_t worst = first;
  double worst_distance = 0.0;
  for (std::size_t k = first + 1; k < last; ++k) {
    const Eigen::Vector2d d = points[k] - a;
    const double distance =
        length > 0.0 ? std::abs(chord.x() * d.y() - chord.y() * d.x()) / length : d.norm();
    if (distance > worst_distance) {
      worst_distance = distance;
      worst = k;
    }
  }
  if (worst_distance > options.split_distance_m) {
    SplitRun(points, indices, first, worst, options, runs);
    SplitRun(points, indices, worst, last, options, runs);
    return;
  }
  if (static_cast<int>(last - first + 1) < options.min_points || length < options.min_length_m) {
    return;
  }
  runs->emplace_back(indices.begin() + static_cast<std::ptrdiff_t>(first),
                     indices.begin() + static_cast<std::ptrdiff_t>(last) + 1);
}

// The straight runs of `readings` with reading i at bearing bearings_rad[i].
std::vector<std::vector<int>> StraightRunsOf(const std::vector<core::LaserReading>& readings,
                                             const std::vector<double>& bearings_rad,
                                             const CarmenStraightnessOptions& options) {
  std::vector<std::vector<int>> runs;
  std::vector<Eigen::Vector2d> points;
  std::vector<int> indices;
  const auto flush = [&] {
    if (!points.empty()) SplitRun(points, indices, 0, points.size() - 1, options, &runs);
    points.clear();
    indices.clear();
  };
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const core::LaserReading& r = readings[i];
    if (!r.valid) {
      flush();
      continue;
    }
    const Eigen::Vector2d p = Point(r, bearings_rad[i]);
    if (!points.empty() && (p - points.back()).norm() > options.break_distance_m) flush();
    points.push_back(p);
    indices.push_back(static_cast<int>(i));
  }
  flush();
  return runs;
}

// Sum of squared perpendicular residuals of the total-least-squares line
// through `points` (smallest eigenvalue of the scatter matrix).
double LineFitSquaredResidual(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double sxx = 0.0, syy = 0.0, sxy = 0.0;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d d = p - mean;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  const double half_trace = 0.5 * (sxx + syy);
  const double root = std::hypot(0.5 * (sxx - syy), sxy);
  return std::max(0.0, half_trace - root);
}

}  // namespace

double CarmenBearingRad(int index, int num_readings, CarmenAngleStep step) {
  return kFirstBearingRad + index * StepRad(num_readings, step);
}

void CarmenOptions::Validate() const {
  if (!std::isfinite(max_range_m) || max_range_m <= 0.0) {
    throw std::invalid_argument("CarmenOptions.max_range_m must be finite and > 0");
  }
}

void CarmenStraightnessOptions::Validate() const {
  if (!std::isfinite(break_distance_m) || break_distance_m <= 0.0) {
    throw std::invalid_argument("CarmenStraightnessOptions.break_distance_m must be > 0");
  }
  if (!std::isfinite(split_distance_m) || split_distance_m <= 0.0) {
    throw std::invalid_argument("CarmenStraightnessOptions.split_distance_m must be > 0");
  }
  if (min_points < 3) {
    throw std::invalid_argument("CarmenStraightnessOptions.min_points must be >= 3");
  }
  if (!std::isfinite(min_length_m) || min_length_m <= 0.0) {
    throw std::invalid_argument("CarmenStraightnessOptions.min_length_m must be > 0");
  }
}

std::vector<std::vector<int>> FindStraightRuns(const core::LaserScan& scan,
                                               const CarmenStraightnessOptions& options) {
  options.Validate();
  std::vector<double> bearings_rad;
  bearings_rad.reserve(scan.readings.size());
  for (const core::LaserReading& r : scan.readings) bearings_rad.push_back(r.bearing_rad);
  return StraightRunsOf(scan.readings, bearings_rad, options);
}

int CarmenLog::UnknownOdometryIntervals() const {
  int unknown = 0;
  for (std::size_t i = 1; i < scans.size(); ++i) {
    if (!scans[i].odometry_known) ++unknown;
  }
  return unknown;
}

CarmenLog ReadCarmenLog(const std::string& path, const CarmenOptions& options) {
  options.Validate();
  CarmenLog log;
  log.path = path;
  LineReader reader(path);
  std::string text;
  int line = 0;
  OdomInterval interval;
  bool seen_flaser = false;
  while (reader.Next(path, &text)) {
    ++line;
    const std::vector<std::string_view> tokens = Tokenize(text);
    if (tokens.empty() || tokens[0].front() == '#') continue;
    if (tokens[0] == "FLASER") {
      CarmenScan scan = ParseFlaser(tokens, path, line, options);
      if (seen_flaser && interval.anchor && interval.last) {
        scan.odometry_known = true;
        scan.previous_from_current_odom = interval.anchor->Inverse() * *interval.last;
      }
      log.scans.push_back(std::move(scan));
      interval = {};
      seen_flaser = true;
    } else if (tokens[0] == "ODOM") {
      const core::Pose2 odom = ParseOdom(tokens, path, line);
      if (!interval.anchor) {
        interval.anchor = odom;
      } else {
        interval.last = odom;
      }
    }
    // Any other message type (PARAM, NEFF, RLASER, ...) is not used.
  }
  return log;
}

void SetCarmenAngleStep(CarmenAngleStep step, CarmenLog* log) {
  for (CarmenScan& s : log->scans) {
    const int n = static_cast<int>(s.scan.readings.size());
    for (int i = 0; i < n; ++i) {
      s.scan.readings[static_cast<std::size_t>(i)].bearing_rad = CarmenBearingRad(i, n, step);
    }
  }
}

namespace {

// Bearing of reading i with the step a fraction t of the way from 180°/n to
// 180°/(n-1).
double InterpolatedBearing(int i, int n, double t) {
  const double a = StepRad(n, CarmenAngleStep::kFovOverN);
  const double b = StepRad(n, CarmenAngleStep::kFovOverNMinus1);
  return kFirstBearingRad + i * (a + t * (b - a));
}

// The straight runs of every scan, segmented once with the step halfway
// between the two candidates.
std::vector<Run> StraightRuns(const CarmenLog& log, const CarmenStraightnessOptions& options) {
  std::vector<Run> runs;
  std::vector<double> bearings_rad;
  for (std::size_t s = 0; s < log.scans.size(); ++s) {
    const std::vector<core::LaserReading>& readings = log.scans[s].scan.readings;
    const int n = static_cast<int>(readings.size());
    bearings_rad.resize(readings.size());
    for (int i = 0; i < n; ++i) {
      bearings_rad[static_cast<std::size_t>(i)] = InterpolatedBearing(i, n, 0.5);
    }
    for (std::vector<int>& indices : StraightRunsOf(readings, bearings_rad, options)) {
      runs.push_back({s, std::move(indices)});
    }
  }
  return runs;
}

// Squared line-fit residual of every run with the step at fraction t.
std::vector<double> RunResiduals(const CarmenLog& log, const std::vector<Run>& runs, double t) {
  std::vector<double> out;
  out.reserve(runs.size());
  std::vector<Eigen::Vector2d> points;
  for (const Run& run : runs) {
    const std::vector<core::LaserReading>& readings = log.scans[run.scan].scan.readings;
    const int n = static_cast<int>(readings.size());
    points.clear();
    for (int i : run.indices) {
      points.push_back(Point(readings[static_cast<std::size_t>(i)], InterpolatedBearing(i, n, t)));
    }
    out.push_back(LineFitSquaredResidual(points));
  }
  return out;
}

// The paired z statistic of the per-run residual differences (0 for one run).
double PairedZ(const std::vector<double>& with_n, const std::vector<double>& with_n_minus_1) {
  if (with_n.size() <= 1) return 0.0;
  const double count = static_cast<double>(with_n.size());
  double mean = 0.0;
  for (std::size_t j = 0; j < with_n.size(); ++j) mean += with_n[j] - with_n_minus_1[j];
  mean /= count;
  double variance = 0.0;
  for (std::size_t j = 0; j < with_n.size(); ++j) {
    const double d = with_n[j] - with_n_minus_1[j] - mean;
    variance += d * d;
  }
  variance /= count - 1.0;
  const double standard_error = std::sqrt(variance / count);
  return standard_error > 0.0 ? mean / standard_error : 0.0;
}

// Each run's own best step: its squared residual is close to quadratic in t,
// S(t) = a t² + b t + c, fitted through t = 0, 1/2, 1; the run votes for
// t = -b / 2a with weight a (how sharply its straightness depends on the step).
// The weighted median of the votes is robust to runs that are not truly straight.
double MedianStepFraction(const std::vector<double>& with_n, const std::vector<double>& halfway,
                          const std::vector<double>& with_n_minus_1) {
  std::vector<std::pair<double, double>> votes;  // (t, weight)
  double total_weight = 0.0;
  for (std::size_t j = 0; j < with_n.size(); ++j) {
    const double a = 2.0 * (with_n[j] + with_n_minus_1[j] - 2.0 * halfway[j]);
    const double b = with_n_minus_1[j] - with_n[j] - a;
    if (a <= 0.0) continue;
    votes.emplace_back(-b / (2.0 * a), a);
    total_weight += a;
  }
  std::sort(votes.begin(), votes.end());
  double t = 0.0;
  double cumulative = 0.0;
  for (const auto& [vote, weight] : votes) {
    cumulative += weight;
    t = vote;
    if (cumulative >= 0.5 * total_weight) break;
  }
  return t;
}

}  // namespace

CarmenAngleStepDecision DecideCarmenAngleStep(const CarmenLog& log,
                                              const CarmenStraightnessOptions& options) {
  options.Validate();
  const std::vector<Run> runs = StraightRuns(log, options);
  CarmenAngleStepDecision decision;
  decision.runs = static_cast<int>(runs.size());
  for (const Run& run : runs) decision.points += static_cast<int>(run.indices.size());
  if (runs.empty()) return decision;
  const auto rms = [&](const std::vector<double>& residuals) {
    double sum = 0.0;
    for (double r : residuals) sum += r;
    return std::sqrt(sum / decision.points);
  };
  const std::vector<double> with_n = RunResiduals(log, runs, 0.0);
  const std::vector<double> with_n_minus_1 = RunResiduals(log, runs, 1.0);
  decision.rms_fov_over_n_m = rms(with_n);
  decision.rms_fov_over_n_minus_1_m = rms(with_n_minus_1);
  decision.paired_z = PairedZ(with_n, with_n_minus_1);
  const double t = MedianStepFraction(with_n, RunResiduals(log, runs, 0.5), with_n_minus_1);
  decision.median_step_fraction = t;
  decision.step = t < 0.5 ? CarmenAngleStep::kFovOverN : CarmenAngleStep::kFovOverNMinus1;
  return decision;
}

}  // namespace pavilion::scenarios
