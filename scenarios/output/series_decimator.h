#pragma once

// A time series thinned to a bounded number of points as it is recorded, for
// the report's charts (issue 17): a 12-hour run's millions of samples become
// at most `max_points`, with every spike still visible.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pavilion::scenarios {

struct SeriesPoint {
  double t = 0.0;      // time, s
  double value = 0.0;  // in the series' unit
};

// Keeps every sample while there are at most `max_points`; past that, the
// time axis from the first sample is cut into equal buckets (at most
// max_points / 2 - 1) and each bucket keeps its smallest and its largest
// sample; the first and the last sample are kept too.
// When a sample falls beyond the last bucket, the bucket width doubles and
// neighbouring buckets merge. Memory stays O(max_points) however many samples
// arrive; the result depends only on the samples (deterministic), and the
// series' minimum and maximum always survive.
class SeriesDecimator {
 public:
  // `max_points`: at least kMinPoints; an odd number counts as one less.
  explicit SeriesDecimator(std::size_t max_points = kDefaultMaxPoints);

  static constexpr std::size_t kDefaultMaxPoints = 5000;  // the report's budget per series
  static constexpr std::size_t kMinPoints = 4;

  // Adds a sample. Throws std::invalid_argument when `t_s` or `value` is not
  // finite or `t_s` is earlier than the previous sample's time.
  void Add(double t_s, double value);

  // The kept points in time order (ties: the order they were added).
  std::vector<SeriesPoint> points() const;
  std::int64_t samples() const { return samples_; }  // every Add() so far
  bool empty() const { return samples_ == 0; }
  bool exact() const { return buckets_.empty(); }  // still every sample
  double last_t() const { return last_t_; }        // the latest sample's time (0 when empty)
  std::size_t max_points() const { return max_points_; }

 private:
  struct Sample {
    double t = 0.0;
    double value = 0.0;
    std::int64_t order = 0;  // 0-based index of the Add()
  };
  struct Bucket {
    std::int64_t index = 0;  // floor((t - t0) / width)
    Sample min;
    Sample max;
  };

  void Take(const Sample& s);
  void StartBuckets(const Sample& next);
  void DoubleWidth();
  std::int64_t BucketOf(double t) const;

  std::size_t max_points_;
  std::size_t max_buckets_;
  std::vector<Sample> raw_;      // while exact
  std::vector<Bucket> buckets_;  // by increasing index, once past max_points_
  Sample first_;                 // kept beside the buckets, once past max_points_
  Sample last_;
  double t0_ = 0.0;
  double width_s_ = 0.0;
  double last_t_ = 0.0;
  std::int64_t samples_ = 0;
};

}  // namespace pavilion::scenarios
