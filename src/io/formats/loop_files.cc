#include "io/formats/loop_files.h"

#include <iomanip>

namespace partslam::io {

void write_g2o(std::ostream& out, const Submaps& maps, const std::vector<LoopClosure>& accepted) {
  auto edge = [&out](std::int64_t from, std::int64_t to, const Pose2& T, const char* info) {
    out << "EDGE_SE2 " << from << " " << to << " " << T.x << " " << T.y << " " << T.theta << " " << info << "\n";
  };
  out << std::setprecision(9);
  for (const Submap& m : maps)
    out << "VERTEX_SE2 " << m.id << " " << m.T_world_map.x << " " << m.T_world_map.y << " " << m.T_world_map.theta << "\n";
  for (std::size_t i = 1; i < maps.size(); ++i)
    edge(maps[i - 1].id, maps[i].id, maps[i - 1].T_world_map.inverse() * maps[i].T_world_map, "400 0 0 400 0 2500");
  for (const LoopClosure& c : accepted) edge(maps[c.match].id, maps[c.query].id, c.T_match_query, "25 0 0 25 0 100");
}

nlohmann::json closures_json(const Submaps& maps, const std::vector<LoopClosure>& closures, double min_confidence) {
  nlohmann::json out = nlohmann::json::array();
  for (const LoopClosure& c : closures) {
    out.push_back({{"query", maps[c.query].id},
                   {"match", maps[c.match].id},
                   {"pose", {{"x", c.T_match_query.x}, {"y", c.T_match_query.y}, {"theta", c.T_match_query.theta}}},
                   {"score", c.score},
                   {"context_score", c.context_score},
                   {"confidence", c.confidence},
                   {"probability", c.probability},
                   {"consistent_group", c.in_group},
                   {"graph_agrees", c.graph_agrees},
                   {"accepted", c.confidence >= min_confidence}});
  }
  return out;
}

nlohmann::json loop_evaluation_json(const LoopEvaluation& e) {
  nlohmann::json curve = nlohmann::json::array();
  for (const PrecisionRecall& p : e.curve)
    curve.push_back({{"confidence", p.confidence}, {"precision", p.precision}, {"recall", p.recall}});
  return {{"relevant_pairs", e.relevant_pairs},
          {"hypotheses", e.hypotheses},
          {"correct", e.correct},
          {"max_f1", e.max_f1},
          {"recall_at_full_precision", e.recall_at_full_precision},
          {"relevant_queries", e.relevant_queries},
          {"query_recall_at_full_precision", e.query_recall_at_full_precision},
          {"confidence_at_full_precision", e.confidence_at_full_precision},
          {"curve", curve}};
}

}  // namespace partslam::io
