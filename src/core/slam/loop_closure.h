// Loop closures: for every submap, the earlier submaps (beyond a travel gap) of the same place, found by a ranking
// method that verifies its shortlist by dMM (core/ranking/ranking.h: rerank:R[:SPEC], the succinct shortlist
// reordered by dMM, or dmm itself). Every verified candidate is a hypothesis (unless the drift gate rules it out)
// with the dMM relative pose, its score (inlier fraction), a context score (the submaps a few metres of travel around
// the query and around the match, joined, matched around that pose: a corridor that looks the same over one 2 m
// submap rarely does over 10 m; the pose is refined by it) and a confidence: the context score minus the best one
// among the query's hypotheses at another place (stored frames other_place.distance or more apart), so a place that
// looks like several others gets a low confidence even when its score is high, less 1 for each consistency check
// it fails (the largest group that agrees pairwise through the front end's chain, closure_consistency.h; a robust
// pose graph of that group). Only the earlier submaps the drift gate can admit are ranked. Their precision and
// recall against true map frames: core/evaluation/loop_evaluation.h; the pose graph they join, and the LoopClosure
// type: submap_graph.h.
#pragma once

#include <string>
#include <vector>

#include "core/matching/distinctiveness.h"
#include "core/work_split.h"
#include "core/maps/submap.h"
#include "core/parallel.h"
#include "core/slam/closure_consistency.h"
#include "core/slam/submap_graph.h"
#include "core/types.h"

namespace partslam {

struct LoopClosureConfig {
  std::string method = "rerank:20";  ///< a method spec whose candidates carry a dMM pose (rerank:R..., dmm)
  double min_travel_gap = 20.0;      ///< G: candidates were anchored at least this much travel earlier [m]
  OtherPlace other_place{4.0};       ///< stored frames this far apart are another place (confidence)
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
  /// Only the earlier submaps that can pass the drift gate are ranked (their stored offset within the gate plus
  /// dMM's translation window): a shortlist of the places the robot can be, not of the whole log.
  bool gate_candidates = true;
  /// Closures accepted as a consistent group: a hypothesis of positive confidence outside the largest set that
  /// agrees pairwise through the front end's chain (closure_consistency.h) loses 1 of confidence; `slam` offers
  /// its back end only what keeps enough, so `loops` and `slam` accept by one rule.
  ClosureConsistencyConfig consistency;
  /// Then a robust pose graph of the stored frames and the group: a hypothesis whose pose disagrees with it loses
  /// 1 of confidence too (see loop_closure.cc).
  bool graph_check = true;
  /// A hypothesis the graph check finds consistent reports the optimised graph's relative pose of its two
  /// submaps (the front end's chain and every other closure agree on it) instead of its own match's: a match
  /// that slid along a corridor is pulled back by its neighbours (docs/NOTES.md, "Loop closures"). What
  /// `partslam loops` reports; `slam` keeps each match's own pose, as its back end solves the graph itself.
  bool graph_pose = false;
  /// dMM's candidates are verified (RankingConfig::verify_dmm: Eq. 1's best poses re-scored by the same-place
  /// probability, the most probable one refined) before the context stage; false: Eq. 1's optimum.
  bool verify_dmm = false;
  int num_threads = 1;               ///< results do not depend on it
};

/// Throws InputError naming the offending field.
void validate(const LoopClosureConfig& config);

/// How many hypotheses failed each consistency check (LoopClosure::in_group, graph_agrees).
struct FailedChecks {
  std::size_t outside_group = 0;
  std::size_t at_odds_with_graph = 0;
};
FailedChecks failed_checks(const std::vector<LoopClosure>& closures);

/// Hypotheses of every query, in query order, each query's by decreasing score. Over a split of several
/// processes (MPI ranks), each takes every size-th query (later queries have more candidates) and the hypotheses
/// are gathered before the consistency checks, so every process returns the one-process result.
std::vector<LoopClosure> find_loop_closures(const Submaps& maps, const LoopClosureConfig& config = {},
                                            const Progress& progress = {}, const WorkSplit& split = local_work());

}  // namespace partslam
