#pragma once

#include <vector>

#include "core/features/line_extraction_options.h"
#include "core/features/uncertain_geometry.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// Extracts line segments from a scan (thesis §3.2, appendix C): a line is fitted
// to every window of n_f consecutive valid readings (eqs. 3.4-3.10), windows
// whose model fidelity distance (eqs. 3.12-3.14) is at most d_m (eq. 3.15) form
// segment candidates, and collinear candidates (chi^2 test, eq. 3.16) are fused
// by re-fitting their joined readings under the overlap-adjacency-collinearity
// policy. Invalid readings are skipped. Segments are in the sensor frame, in
// order of their first reading; their lines have r >= 0. Segments shorter than
// min_length_m, or whose longest run of consecutive readings is (legs fused
// across a gap), are rejected. A fused line seen in pieces (occlusions, doors)
// gives one Segment per piece with the same line and line_id (eq. 5.17). Cost:
// O(n) for the segmentation (window fits from prefix moment sums; the thesis'
// direct fits are O(n n_f)), and each of the O(n_s^2) chi^2 distances between
// the n_s candidates computed once, as are the fits of fused clusters (O(runs)).
std::vector<Segment> ExtractLines(const LaserScan& scan, const LineExtractionOptions& options);

}  // namespace pavilion::core
