// The last stage of slam (docs/NOTES.md, "Scans refined on their neighbours"): after loop closing, every scan is
// matched once more against the scans around it in time, on both sides. The front end matched each scan against
// the scans before it only (it runs as the log is read); the finished trajectory has the scans after it too, and
// a scan held between both sides jitters less: on the four raw logs with relations (mit-csail, fr079, intel, aces)
// the relation error fell by 1.3-4.8 mm, on every one of them and for every setting tried near the default.
//
// The log is cut into blocks of `block` consecutive scans; a block's scans are refined (Gauss-Newton on a
// likelihood field, no search: core/matching/scan_matcher.h) against a field of the points of the `window` scans
// on each side of it, its own left out (a scan's own points would hold it where it is). Every block of a round
// reads the poses the round began with, so blocks run in parallel and the answer does not depend on the threads.
#pragma once

#include <cstddef>

#include "core/maps/scan.h"
#include "core/slam/front_end_config.h"

namespace partslam {

struct NeighbourRefinementConfig {
  int rounds = 2;          ///< passes over the log; 0 turns the stage off
  int window = 30;         ///< scans on each side of a block whose points make its field
  int block = 5;           ///< consecutive scans refined against one field, their own points left out of it
  double sigma = 0.02;     ///< the field's width [m] (its cells and the points': the front end's)
  double max_move = 0.1;   ///< a refinement that moves a scan further than this in a round is not taken [m]
  int num_threads = 1;     ///< results do not depend on it
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const NeighbourRefinementConfig& config);

struct NeighbourRefinementStats {
  std::size_t refined = 0;   ///< scan refinements taken, over all rounds
  std::size_t too_far = 0;   ///< refinements not taken: they moved the scan beyond max_move
  double mean_move = 0;      ///< mean distance a taken refinement moved its scan [m]
};

/// The scans with their poses refined as above. The points and the field's cells are those of the front end
/// (its point_resolution, max_range and matcher.resolution).
Scans refine_on_neighbours(const Scans& scans, const NeighbourRefinementConfig& config,
                           const FrontEndConfig& front_end, NeighbourRefinementStats* stats = nullptr);

}  // namespace partslam
