// Loop closures (core/slam/loop_closure.h) measured against true map frames: precision-recall over the
// confidence, where a hypothesis is correct when its pose is (0.5 m, 0.2 rad) and recall is the share of the
// relevant pairs (true frames within R, beyond the travel gap) found by a correct hypothesis. Every verified
// shortlist candidate is a hypothesis, so recall is bounded by how many of a query's relevant pairs its
// shortlist of R holds.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "core/maps/submap.h"
#include "core/slam/loop_closure.h"
#include "core/types.h"

namespace partslam {

struct LoopTruthConfig {
  double radius = 2.0;               ///< R: true frames at most this far apart are the same place [m]
  double min_travel_gap = 20.0;      ///< G: as LoopClosureConfig::min_travel_gap [m]
  double max_translation_error = 0.5;  ///< a correct hypothesis's pose error [m]
  double max_rotation_error = 0.2;     ///< [rad]
};

/// Throws InputError naming the offending field.
void validate(const LoopTruthConfig& config);

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
