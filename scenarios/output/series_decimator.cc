#include "scenarios/output/series_decimator.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::scenarios {

SeriesDecimator::SeriesDecimator(std::size_t max_points)
    : max_points_(max_points < kMinPoints ? kMinPoints : max_points - max_points % 2),
      // The first and the last sample are kept beside the buckets' two each.
      max_buckets_((max_points_ - 2) / 2) {}

void SeriesDecimator::Add(double t_s, double value) {
  if (!std::isfinite(t_s) || !std::isfinite(value)) {
    throw std::invalid_argument("SeriesDecimator: sample (" + std::to_string(t_s) + ", " +
                                std::to_string(value) + ") is not finite");
  }
  if (samples_ > 0 && t_s < last_t_) {
    throw std::invalid_argument("SeriesDecimator: time " + std::to_string(t_s) +
                                " s is before the previous sample's " + std::to_string(last_t_) +
                                " s");
  }
  const Sample s{t_s, value, samples_};
  ++samples_;
  last_t_ = t_s;
  if (buckets_.empty()) {
    if (raw_.size() < max_points_) {
      raw_.push_back(s);
      return;
    }
    StartBuckets(s);
  }
  Take(s);
  last_ = s;
}

std::int64_t SeriesDecimator::BucketOf(double t) const {
  return static_cast<std::int64_t>(std::floor((t - t0_) / width_s_));
}

void SeriesDecimator::StartBuckets(const Sample& next) {
  first_ = raw_.front();
  t0_ = first_.t;
  const double span_s = next.t - t0_;
  // Half the buckets used: room to grow before the first doubling. All
  // samples at one time: any width holds them in bucket 0.
  width_s_ = span_s > 0.0 ? 2.0 * span_s / static_cast<double>(max_buckets_) : 1.0;
  for (const Sample& r : raw_) Take(r);
  raw_.clear();
  raw_.shrink_to_fit();
}

void SeriesDecimator::Take(const Sample& s) {
  std::int64_t k = BucketOf(s.t);
  while (k >= static_cast<std::int64_t>(max_buckets_)) {
    DoubleWidth();
    k = BucketOf(s.t);
  }
  if (!buckets_.empty() && buckets_.back().index == k) {
    Bucket& b = buckets_.back();
    if (s.value < b.min.value) b.min = s;  // ties keep the earlier sample
    if (s.value > b.max.value) b.max = s;
    return;
  }
  buckets_.push_back({k, s, s});
}

void SeriesDecimator::DoubleWidth() {
  // floor(x / 2w) == floor(floor(x / w) / 2): bucket k joins bucket k / 2.
  width_s_ *= 2.0;
  std::vector<Bucket> merged;
  merged.reserve(buckets_.size() / 2 + 1);
  for (const Bucket& b : buckets_) {
    const std::int64_t index = b.index / 2;
    if (!merged.empty() && merged.back().index == index) {
      Bucket& m = merged.back();
      if (b.min.value < m.min.value) m.min = b.min;
      if (b.max.value > m.max.value) m.max = b.max;
    } else {
      merged.push_back({index, b.min, b.max});
    }
  }
  buckets_ = std::move(merged);
}

std::vector<SeriesPoint> SeriesDecimator::points() const {
  std::vector<SeriesPoint> out;
  if (exact()) {
    out.reserve(raw_.size());
    for (const Sample& s : raw_) out.push_back({s.t, s.value});
    return out;
  }
  std::int64_t last_order = -1;
  const auto emit = [&](const Sample& s) {
    if (s.order <= last_order) return;  // already out (a bucket's min and max may be one sample)
    out.push_back({s.t, s.value});
    last_order = s.order;
  };
  out.reserve(2 * buckets_.size() + 2);
  emit(first_);
  for (const Bucket& b : buckets_) {
    const bool min_first = b.min.order <= b.max.order;
    emit(min_first ? b.min : b.max);
    emit(min_first ? b.max : b.min);
  }
  emit(last_);
  return out;
}

}  // namespace pavilion::scenarios
