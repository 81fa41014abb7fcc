#include "core/slam/submap_graph.h"

#include <cmath>
#include <string>
#include <utility>

#include "core/error.h"

namespace partslam {

void validate(const SubmapGraphWeights& w) {
  const std::pair<double, const char*> weights[] = {{w.chain_translation, "chain_translation"},
                                                    {w.chain_rotation, "chain_rotation"},
                                                    {w.loop_translation, "loop_translation"},
                                                    {w.loop_rotation, "loop_rotation"}};
  for (const auto& [v, name] : weights)
    if (!(v > 0) || !std::isfinite(v))
      throw InputError(std::string("submap graph config: ") + name + " must be finite and > 0, got " +
                       std::to_string(v));
}

std::vector<Pose2> optimize_submap_graph(const Submaps& maps, const std::vector<LoopClosure>& closures,
                                         const SubmapGraphWeights& w, const PoseGraphConfig& graph,
                                         PoseGraphSummary* summary) {
  std::vector<Pose2> initial;
  for (const Submap& m : maps) initial.push_back(m.T_world_map);
  std::vector<PoseGraphEdge> edges;
  for (std::size_t i = 1; i < maps.size(); ++i)
    edges.push_back({i - 1, i, initial[i - 1].inverse() * initial[i], w.chain_translation, w.chain_rotation, false});
  for (const LoopClosure& l : closures)
    edges.push_back({l.match, l.query, l.T_match_query, w.loop_translation, w.loop_rotation, true});
  return optimize_pose_graph(initial, edges, graph, summary);
}

}  // namespace partslam
