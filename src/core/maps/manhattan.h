// Manhattan alignment (docs/DESIGN.md, "Canonical frame"; the paper's ref. [18]): the rotation in [0, pi/2) that
// minimises the summed Shannon entropy of the x and y point histograms. Walls of a Manhattan building then
// run along the axes, so two maps of one place differ by a multiple of 90 degrees plus a small residual.
#pragma once

#include "core/types.h"

namespace partslam {

struct ManhattanConfig {
  double bin_size = kMapResolution;                            ///< histogram bin [m]
  double coarse_step = 1.0 * std::numbers::pi / 180;   ///< first sweep over [0, pi/2) [rad]
  double fine_step = 0.05 * std::numbers::pi / 180;    ///< refinement step around the best coarse angle [rad]
};

/// Summed entropy of the x and y histograms of the points rotated by angle [nats].
double axis_entropy(const Points2& points, double angle, double bin_size);

/// The angle in [0, pi/2) by which to rotate the points (about the origin) into the canonical frame.
double manhattan_angle(const Points2& points, const ManhattanConfig& config = {});

}  // namespace partslam
