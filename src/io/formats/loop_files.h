// What `partslam loops` writes: the submap graph with its accepted loop closures as g2o (one VERTEX_SE2 per
// submap frame, an EDGE_SE2 between consecutive submaps and one per closure), and the closures and their
// evaluation against ground truth as JSON.
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <vector>

#include "core/evaluation/loop_evaluation.h"
#include "core/maps/submap.h"
#include "core/slam/loop_closure.h"

namespace partslam::io {

/// The graph in g2o's text format. Information: consecutive submaps (the front end's relative pose,
/// 400 / 400 / 2500) are trusted more than loop closures (25 / 25 / 100).
void write_g2o(std::ostream& out, const Submaps& maps, const std::vector<LoopClosure>& accepted);

/// Every closure: the submap ids, the pose, the scores and whether its confidence reaches min_confidence.
nlohmann::json closures_json(const Submaps& maps, const std::vector<LoopClosure>& closures, double min_confidence);

/// The evaluation's figures and its precision-recall curve.
nlohmann::json loop_evaluation_json(const LoopEvaluation& evaluation);

}  // namespace partslam::io
