#pragma once

// Fixed-point CSV fields as the run's CSV files write them.

#include <Eigen/Core>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>

namespace pavilion::scenarios {

// `v` with `decimals` places; never "-0.000".
inline std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v == 0.0 ? 0.0 : v);
  return buf;
}

// One CSV row built field by field (GCC 12 warns falsely, -Wrestrict, on long
// chains of string `+`).
class CsvRow {
 public:
  CsvRow& Add(const std::string& field) {
    if (!row_.empty() || fields_ > 0) row_ += ',';
    row_ += field;
    ++fields_;
    return *this;
  }
  CsvRow& Add(double value, int decimals) { return Add(Fixed(value, decimals)); }
  CsvRow& Add(std::int64_t value) { return Add(std::to_string(value)); }
  CsvRow& Empty(int count) {
    for (int k = 0; k < count; ++k) Add(std::string());
    return *this;
  }
  // The six distinct entries of a 3x3 covariance, %.6e.
  CsvRow& Covariance(const Eigen::Matrix3d& c) {
    for (const auto& [i, j] : {std::pair{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.6e", c(i, j));
      Add(std::string(buf));
    }
    return *this;
  }
  const std::string& str() const { return row_; }

 private:
  std::string row_;
  int fields_ = 0;
};

}  // namespace pavilion::scenarios
