// Closures refined on the scans (docs/NOTES.md, "SLAM on real raw logs"). A closure's relative pose comes from
// the two submaps' 10 cm cells and the context around them (loop_closure.h); two visits of the same place then
// still disagree by several centimetres (fr079: relations between scans of two visits 7.3 cm off against 2.7 cm
// within one visit). Here each closure is matched once more, on the beam endpoints of the scans around both
// submaps (2.5 cm cells, a likelihood field of sigma 5 cm), in a small window around its pose.
#pragma once

#include <vector>

#include "core/maps/submap.h"
#include "core/slam/submap_graph.h"

namespace partslam {

struct ClosureRefinementConfig {
  bool enabled = true;
  double context = 2.0;          ///< scans this much travel before and after a submap's window join it [m]
  double resolution = 0.025;     ///< cells of the points and of the likelihood field [m]
  double sigma = 0.05;           ///< likelihood field width [m]
  double max_range = 8.0;        ///< beam endpoints farther from the laser are not used [m]
  double linear_window = 0.05;   ///< correlative search around the closure's pose [m]
  double angular_window = 0.02;  ///< [rad]
  int max_points = 1000;         ///< the query side's points are thinned to at most this many
  int num_threads = 1;           ///< results do not depend on it
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const ClosureRefinementConfig& config);

/// The closures with their T_match_query refined. `scans` are those the submaps were built from (the submaps'
/// frames and the scans' poses are in the same world frame); `window_length` is the submaps' L. A refinement that
/// moves a pose by more than twice the window (the least-squares step left the basin) keeps the closure's pose.
std::vector<LoopClosure> refine_closures(const Scans& scans, const Submaps& maps, double window_length,
                                         std::vector<LoopClosure> closures,
                                         const ClosureRefinementConfig& config = {});

}  // namespace partslam
