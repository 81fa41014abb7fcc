// The back end of `slam` (docs/NOTES.md "SLAM bench"): the submap pose graph (submap_graph.h) solved with only
// the loop closures that agree with the solution, and a verdict on it.
//
// Closures that slipped through verification would bend the map; the Cauchy loss alone does not stop a group of
// them. So the graph is solved in rounds: after each solve, every closure whose residual (its measured relative
// pose against the solved frames) exceeds the limit times a factor is set aside, the factor falling 4, 2, 1 (a
// graduated schedule: an early solve bent by wrong closures must not cost the right ones), until no closure
// changes side. Set-aside closures are re-admitted when the solve without them agrees with them.
//
// The verdict judges what the closures did to the front end's chain (consecutive submaps, locally accurate):
//   "closed"     closures were used and the chain bends nowhere beyond the limits;
//   "open"       no closure was accepted: the front end's trajectory as it is (nothing to correct it with);
//   "doubtful"   more than max_rejected_share of the closures disagreed, or the chain had to bend beyond the
//                limits somewhere: the closures' solution may be worse than the front end's, so the front end's
//                chain is kept (front_end_written) and `slam` warns.
//   "front end"  the closures could not be made to agree: the front end's chain is kept untouched (closures
//                unused) and `slam` warns.
#pragma once

#include <string>
#include <vector>

#include "core/slam/loop_closure.h"
#include "core/slam/pose_graph.h"
#include "core/slam/submap_graph.h"

namespace partslam {

struct BackEndConfig {
  SubmapGraphWeights weights;
  PoseGraphConfig graph;
  double max_translation_residual = 0.3;  ///< a used closure's residual at the solution at most [m]
  double max_rotation_residual = 0.05;    ///< [rad]
  int max_rounds = 8;                     ///< solves at most
  double max_rejected_share = 0.4;        ///< more rejected closures than this share make the verdict doubtful
  double max_chain_translation = 0.3;     ///< a consecutive-submap edge bent more makes it doubtful [m]
  double max_chain_rotation = 0.1;        ///< [rad]
};

/// Throws InputError naming the field when a value is out of range.
void validate(const BackEndConfig& config);

struct BackEndResult {
  std::vector<Pose2> frames;  ///< optimised T_world_map per submap
  std::vector<bool> used;     ///< per input closure: in the final graph
  std::size_t used_count = 0;
  std::size_t rejected = 0;   ///< input closures left out
  int rounds = 0;             ///< solves run
  std::size_t chain_bends = 0;  ///< consecutive-submap edges bent beyond the limits in the result
  double max_chain_translation = 0, max_chain_rotation = 0;  ///< the largest bend [m], [rad]
  PoseGraphSummary graph;     ///< of the final solve
  std::string verdict;        ///< "closed", "open", "doubtful" or "front end" (see above)
  std::string reason;         ///< why, in words, for a verdict other than "closed" and "open"
  bool trusted() const { return verdict == "closed" || verdict == "open"; }
  /// frames are the front end's, not the closures' solution (verdict "front end", or "doubtful" from here: the
  /// closures are what is doubted); the used flags, residuals and bends above are of the solution.
  bool front_end_written = false;
};

BackEndResult solve_back_end(const Submaps& maps, const std::vector<LoopClosure>& closures,
                             const BackEndConfig& config = {});

}  // namespace partslam
