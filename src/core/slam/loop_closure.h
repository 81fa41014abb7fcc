// Loop closures (issue "raw logs", item 3): for every submap, the earlier submaps (beyond a travel gap) of the
// same place, found by a ranking method that verifies its shortlist by dMM (core/ranking/ranking.h:
// rerank:R[:SPEC], the succinct shortlist reordered by dMM, or dmm itself). Every verified candidate is a
// hypothesis (unless the drift gate rules it out) with the dMM relative pose, its score (inlier fraction), a
// context score (the submaps a few metres
// of travel around the query and around the match, joined, matched around that pose: a corridor that looks the
// same over one 2 m submap rarely does over 10 m; the pose is refined by it) and a confidence: the context
// score minus the best one among the query's hypotheses at another place (stored frames more than other_place
// apart), so a place that looks like several others gets a low confidence even when its score is high.
// evaluate_loop_closures measures them against true map frames: precision-recall over the confidence, where a
// hypothesis is correct when its pose is (0.5 m, 0.2 rad) and recall is the share of the relevant pairs (true
// frames within R, beyond the travel gap) found by a correct hypothesis. Every verified shortlist candidate is
// a hypothesis, so recall is bounded by how many of a query's relevant pairs its shortlist of R holds.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/work_split.h"
#include "core/maps/submap.h"
#include "core/parallel.h"
#include "core/slam/pose_graph.h"

namespace partslam {

struct LoopClosureConfig {
  std::string method = "rerank:20";  ///< a method spec whose candidates carry a dMM pose (rerank:R..., dmm)
  double min_travel_gap = 20.0;      ///< G: candidates were anchored at least this much travel earlier [m]
  double other_place = 4.0;          ///< stored frames farther apart are another place (confidence) [m]
  double min_score = 0.0;            ///< hypotheses with a lower dMM inlier fraction are not kept
  /// Verification in context: the submaps within this much travel of the query (and of the match) are joined
  /// in its frame (stored frames: locally consistent) and the match's context is matched against the query's
  /// around the dMM pose (scan_matcher.h); 0 = off [m].
  double context = 4.0;
  /// Drift gate: the stored frames (the front end's, locally consistent, drifting with travel) bound where a
  /// true match can be: a hypothesis whose pose disagrees with the stored relative pose of the two maps by more
  /// than drift_offset + drift_rate * gap [m] or drift_turn + drift_turn_rate * gap [rad] (gap: their travel
  /// difference) is dropped, as Cartographer searches loop closures in a window around the pose estimate.
  /// drift_rate = 0 and drift_offset = 0 turn it off.
  double drift_offset = 2.0;
  double drift_rate = 0.05;
  double drift_turn = 0.3;
  double drift_turn_rate = 0.01;
  /// Consistency among hypotheses: those that disagree with a robust pose graph of all of them lose 1 of
  /// confidence (see loop_closure.cc).
  bool graph_check = true;
  int num_threads = 1;               ///< results do not depend on it
};

/// Throws InputError naming the offending field.
void validate(const LoopClosureConfig& config);

struct LoopClosure {
  std::size_t query = 0;  ///< index of the later submap
  std::size_t match = 0;  ///< index of the earlier submap
  Pose2 T_match_query;    ///< the query's frame in the match's frame (dMM)
  double score = 0.0;     ///< dMM inlier fraction
  double context_score = 0.0;  ///< mean likelihood of the match's context on the query's (0 without context)
  double confidence = 0.0;  ///< context score (dMM score without context) minus the best one at another place
};

/// Information of a submap pose graph's edges: consecutive submaps joined by their stored relative pose (the
/// front end's; sigma 5 cm, 0.02 rad) and loop closures (sigma 0.2 m, 0.1 rad, under a Cauchy loss).
struct SubmapGraphWeights {
  double chain_translation = 400;  ///< [1/m^2]
  double chain_rotation = 2500;    ///< [1/rad^2]
  double loop_translation = 25;    ///< [1/m^2]
  double loop_rotation = 100;      ///< [1/rad^2]
};

/// The submap frames (T_world_map) optimised over that graph, the first held fixed.
std::vector<Pose2> optimize_submap_graph(const Submaps& maps, const std::vector<LoopClosure>& closures,
                                         const SubmapGraphWeights& weights = {}, const PoseGraphConfig& graph = {},
                                         PoseGraphSummary* summary = nullptr);

/// Hypotheses of every query, in query order, each query's by decreasing score. Over a split of several
/// processes (MPI ranks), each takes every size-th query (later queries have more candidates) and the hypotheses
/// are gathered before the graph check, so every process returns the one-process result.
std::vector<LoopClosure> find_loop_closures(const Submaps& maps, const LoopClosureConfig& config = {},
                                            const Progress& progress = {}, const WorkSplit& split = local_work());

struct LoopTruthConfig {
  double radius = 2.0;               ///< R: true frames at most this far apart are the same place [m]
  double min_travel_gap = 20.0;      ///< G: as LoopClosureConfig::min_travel_gap [m]
  double max_translation_error = 0.5;  ///< a correct hypothesis's pose error [m]
  double max_rotation_error = 0.2;     ///< [rad]
};

struct PrecisionRecall {
  double confidence = 0.0;  ///< threshold: hypotheses with at least this confidence are accepted
  double precision = 0.0;
  double recall = 0.0;
};

struct LoopEvaluation {
  std::size_t relevant_pairs = 0;  ///< (later, earlier) pairs of the same place with true frames
  std::size_t hypotheses = 0;      ///< hypotheses between maps with true frames
  std::size_t correct = 0;         ///< of them: the pose within the errors of the true relative pose
  std::vector<PrecisionRecall> curve;  ///< one point per distinct confidence, decreasing
  double max_f1 = 0.0;
  double recall_at_full_precision = 0.0;  ///< largest recall with every accepted hypothesis correct
  std::size_t relevant_queries = 0;       ///< maps with at least one relevant earlier map
  /// Share of relevant_queries with a correct hypothesis to a relevant map, at the same threshold (the places
  /// where the loop is closed, rather than every pair of the place's submaps).
  double query_recall_at_full_precision = 0.0;
  double confidence_at_full_precision = 0.0;  ///< the threshold that gives it
  /// Per input closure: its pose is correct (1), wrong (0), or it involves a map without a true frame (-1).
  std::vector<int> verdicts;
};

/// `true_frames[i]`: the true T_world_map of maps[i], or nullopt when unknown (left out of everything).
LoopEvaluation evaluate_loop_closures(const std::vector<LoopClosure>& closures, const Submaps& maps,
                                      const std::vector<std::optional<Pose2>>& true_frames,
                                      const LoopTruthConfig& config = {});

}  // namespace partslam
