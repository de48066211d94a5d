#pragma once

#include <cstdint>

namespace pavilion::core {

// A reproducible pseudo-random stream: xoshiro256** seeded by splitmix64 from
// (scenario seed, stream id). The distributions are implemented here rather than
// taken from <random> so that draws are identical across standard libraries.
// Every random draw in Pavilion comes from a stream owned by one robot, sensor or
// body (architecture.md, "Time and determinism").
class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint64_t stream_id);

  // Derives a stable stream id from a name (FNV-1a, 64 bit), e.g. a body id.
  static std::uint64_t StreamId(const char* name);

  std::uint64_t NextU64();
  // Uniform in [0, 1).
  double Uniform();
  // Uniform in [lo, hi).
  double Uniform(double lo, double hi);
  // Uniform integer in [lo, hi] (inclusive), lo <= hi.
  std::int64_t UniformInt(std::int64_t lo, std::int64_t hi);
  // Normal with the given mean and standard deviation (Marsaglia polar method).
  double Normal(double mean = 0.0, double stddev = 1.0);

 private:
  std::uint64_t state_[4];
  bool has_spare_normal_ = false;
  double spare_normal_ = 0.0;
};

}  // namespace pavilion::core
