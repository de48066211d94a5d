#pragma once

// Decimal rounding of derived numbers, so that files written from them are
// stable and readable (map derivation, roadmaps). -0 becomes 0.

namespace pavilion::core {

// v rounded to `decimals` places after the point (as printf's "%.*f").
double RoundDecimals(double v, int decimals);

// v rounded to `digits` significant digits (as printf's "%.*g").
double RoundSignificant(double v, int digits);

}  // namespace pavilion::core
