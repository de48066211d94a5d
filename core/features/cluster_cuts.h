#pragma once

// Where the line extraction cuts clusters of readings (thesis §3.2.3 and its
// fit consistency extension): the best split of one cluster into two lines,
// and the split of readings two lines share at a corner. Readings are indices
// into the scan's prepared fit points, ascending.

#include <vector>

#include "core/features/line_fit.h"
#include "core/features/uncertain_geometry.h"

namespace pavilion::core {

// Whether two sorted index lists have an element in common.
bool SharePoints(const std::vector<int>& a, const std::vector<int>& b);

// The cut k in [1, n) minimizing the residual sums of the two best lines
// through members[0, k) and members[k, n); each residual is the smaller
// eigenvalue of the weighted scatter matrix about the weighted mean (the
// minimum of eqs. 3.4-3.5's objective), from running moment sums in O(n).
// members.size() >= 2.
int BestTwoLineCut(const std::vector<FitPoint>& prepared, const std::vector<int>& members);

// The readings `shared` by line a (before them) and line b (after them): the
// cut in [0, shared.size()] such that shared[0, cut) stay with a and the rest
// go to b, minimizing the squared perpendicular residuals to the two lines.
int CornerCut(const std::vector<FitPoint>& prepared, const std::vector<int>& shared, const Line& a,
              const Line& b);

}  // namespace pavilion::core
