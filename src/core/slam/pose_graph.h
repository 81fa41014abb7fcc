// 2D pose-graph optimisation with Ceres (the back end of `slam`, core/slam/back_end.h): nodes are poses, edges relative-pose
// measurements with a diagonal information (weights on x, y and theta); loop-closure edges go through a Cauchy
// loss so that a wrong one is down-weighted rather than bending the map. The first node is held fixed.
#pragma once

#include <cstddef>
#include <vector>

#include "core/types.h"

namespace partslam {

struct PoseGraphEdge {
  std::size_t from = 0;
  std::size_t to = 0;
  Pose2 T_from_to;               ///< measured pose of `to` in the frame of `from`
  double translation_weight = 1; ///< information of x and y [1/m^2]
  double rotation_weight = 1;    ///< information of theta [1/rad^2]
  bool robust = false;           ///< Cauchy loss (loop closures)
};

struct PoseGraphConfig {
  double robust_scale = 1.0;  ///< Cauchy loss scale, in units of the weighted residual
  int max_iterations = 100;
};

/// Throws InputError naming the offending field.
void validate(const PoseGraphConfig& config);

struct PoseGraphSummary {
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int iterations = 0;
  bool converged = false;
};

/// Optimised poses. Throws InputError for an edge naming a node out of range, a non-finite or non-positive
/// weight, or a non-finite pose.
std::vector<Pose2> optimize_pose_graph(const std::vector<Pose2>& initial, const std::vector<PoseGraphEdge>& edges,
                                       const PoseGraphConfig& config = {}, PoseGraphSummary* summary = nullptr);

}  // namespace partslam
