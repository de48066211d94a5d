#include "core/math/rounding.h"

#include <cstdio>
#include <cstdlib>

namespace pavilion::core {

double RoundDecimals(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  const double r = std::strtod(buf, nullptr);
  return r == 0.0 ? 0.0 : r;
}

double RoundSignificant(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  const double r = std::strtod(buf, nullptr);
  return r == 0.0 ? 0.0 : r;
}

}  // namespace pavilion::core
