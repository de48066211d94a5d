#pragma once

// A picture of a robot's localization over a run: the 2-sigma bounds of the
// estimate in the robot's frontal and lateral direction against time (thesis
// Fig. 4.4), for report.html and the snapshots folder.

#include <vector>

#include "core/types/image.h"
#include "scenarios/metrics/localization_tracker.h"

namespace pavilion::scenarios {

struct TwoSigmaPlotOptions {
  int width_px = 640;   // whole picture, [200, 4000]
  int height_px = 300;  // whole picture, [120, 4000]

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Frontal (blue) and lateral (red) 2-sigma in cm over the cycles' time, on
// axes from 0 with labelled ticks and a legend. No cycles: empty axes.
core::RgbImage PlotTwoSigmaOverTime(const std::vector<LocalizationCycle>& cycles,
                                    const TwoSigmaPlotOptions& options = {});

}  // namespace pavilion::scenarios
