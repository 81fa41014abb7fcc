// Ranks simulated submaps against each other with the library's one ranking entry point: what a program
// linking the installed partslam::core / partslam::io does. Exits 0 when the succinct matcher puts a revisit
// of the query's place in its top 10 and dMM returns a pose for it.
#include <core/ranking/ranking.h>
#include <core/maps/submap.h>
#include <core/evaluation/tasks.h>
#include <io/logs/scan_source.h>

#include <cstdio>

int main() {
  using namespace partslam;
  const Submaps maps = build_submaps(io::load_scan_source("sim:1").scans);
  const std::vector<RelevantPair> pairs = relevant_pairs(maps, {});
  if (pairs.empty()) return 1;
  std::vector<MapView> views;
  for (const Submap& m : maps) views.push_back({&m.points, nullptr});
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < maps.size(); ++i)
    if (i != pairs.front().query) candidates.push_back(i);
  const std::unique_ptr<Ranker> ranker = make_ranker(parse_method_spec("rerank:10"), {});
  ranker->prepare(views, 2);
  const Ranking ranking = ranker->rank(views[pairs.front().query], candidates);
  const std::vector<std::size_t> order = ranking_order(ranking.scores);
  const std::size_t best = candidates[order.front()];
  std::printf("query %zu: best match %zu (%.2f m away), %zu maps ranked\n", pairs.front().query, best,
              (maps[best].T_world_map.translation() - maps[pairs.front().query].T_world_map.translation()).norm(),
              candidates.size());
  return ranking.direct[order.front()].has_value() ? 0 : 1;
}
