// The submap pose graph: consecutive submaps joined by their stored relative pose (the front end's, locally
// consistent) and loop closures (loop_closure.h) between earlier and later submaps, optimised over the submap
// frames with the first held fixed. The back end (back_end.h) and the loop closures' consistency check solve it.
#pragma once

#include <vector>

#include "core/maps/submap.h"
#include "core/slam/pose_graph.h"

namespace partslam {

/// A loop closure: an edge of the graph between an earlier and a later submap, as core/slam/loop_closure.h finds
/// them.
struct LoopClosure {
  std::size_t query = 0;  ///< index of the later submap
  std::size_t match = 0;  ///< index of the earlier submap
  Pose2 T_match_query;    ///< the query's frame in the match's frame (dMM)
  double score = 0.0;     ///< dMM inlier fraction
  double context_score = 0.0;  ///< mean likelihood of the match's context on the query's (0 without context)
  double confidence = 0.0;  ///< context score (dMM score without context) minus the best one at another place
  /// Same-place probability of the two submaps at dMM's verified pose (before the context stage refines it);
  /// -1 when dMM was not verified (LoopClosureConfig::verify_dmm false).
  double probability = -1.0;
  /// The consistency checks of loop_closure.h (each failed one took 1 of confidence): in the largest group of
  /// hypotheses that agree pairwise through the front end's chain (true when not tested: confidence <= 0, or the
  /// check off), and in agreement with the robust pose graph of that group (true when the graph check is off).
  bool in_group = true;
  bool graph_agrees = true;
};

/// Information of a submap pose graph's edges: consecutive submaps joined by their stored relative pose (the
/// front end's; sigma 5 cm, 0.02 rad) and loop closures (sigma 0.2 m, 0.1 rad, under a Cauchy loss).
struct SubmapGraphWeights {
  double chain_translation = 400;  ///< [1/m^2]
  double chain_rotation = 2500;    ///< [1/rad^2]
  double loop_translation = 25;    ///< [1/m^2]
  double loop_rotation = 100;      ///< [1/rad^2]
};

/// Throws InputError naming the offending field (every weight must be finite and > 0).
void validate(const SubmapGraphWeights& weights);

/// The submap frames (T_world_map) optimised over that graph, the first held fixed.
std::vector<Pose2> optimize_submap_graph(const Submaps& maps, const std::vector<LoopClosure>& closures,
                                         const SubmapGraphWeights& weights = {}, const PoseGraphConfig& graph = {},
                                         PoseGraphSummary* summary = nullptr);

}  // namespace partslam
