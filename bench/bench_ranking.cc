// Online ranking speed of every method through the one entry point (core/ranking/ranking.h): one query against the
// other submaps of fr101 (229 maps, ../shared/data) or, without the data, of the simulator. Counters:
// us_per_pair = the ranker's matching time per stored map, ms_query_prep = the query's own preparation,
// bits_per_map = what the method stores. dMM is the baseline of the same run. BM_Query: one query against N = 100
// stored maps with their laser origins, as `eval` and `match` rank them (dMM verified with free space), in ms per
// query, on fr101's submaps (data set #1's input, ~190 points) and fr079's (#5's, ~500 points); x_eq1 is the
// ratio to Eq. 1's branch-and-bound alone (`dmm:eq1`, run first on the same queries in the same run).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>

#include "core/ranking/ranking.h"
#include "core/sim/simulator.h"
#include "core/maps/submap.h"
#include "io/logs/carmen_log.h"

namespace partslam {
namespace {

// A building's submaps from ../shared/data, or the simulator's without the data.
const Submaps& maps(const std::string& building = "fr101") {
  static std::map<std::string, Submaps> cache;
  if (auto it = cache.find(building); it != cache.end()) return it->second;
  const std::filesystem::path log =
      std::filesystem::path(PARTSLAM_SHARED_DATA) / building / (building + "-corrected.log.gz");
  return cache[building] = std::filesystem::exists(log) ? build_submaps(io::read_carmen_log(log).scans)
                                                        : build_submaps(simulate().scans);
}

void BM_Rank(benchmark::State& state, const char* spec) {
  const Submaps& m = maps();
  std::vector<MapView> views;
  for (const Submap& s : m) views.push_back({&s.points, nullptr});
  const std::unique_ptr<Ranker> ranker = make_ranker(parse_method_spec(spec), {});
  ranker->prepare(views, 1);
  std::vector<std::size_t> candidates;
  for (std::size_t i = 1; i < m.size(); ++i) candidates.push_back(i);
  double match_ms = 0, prep_ms = 0;
  std::size_t queries = 0;
  for (auto _ : state) {
    const Ranking r = ranker->rank(views[queries % m.size()], candidates);
    benchmark::DoNotOptimize(r.scores.data());
    match_ms += r.match_ms, prep_ms += r.prep_ms, ++queries;
  }
  state.counters["us_per_pair"] = 1e3 * match_ms / static_cast<double>(queries * candidates.size());
  state.counters["ms_query_prep"] = prep_ms / static_cast<double>(queries);
  state.counters["bits_per_map"] = ranker->bits_per_map();
  state.counters["maps"] = static_cast<double>(candidates.size());
}

// One query against the next 100 stored maps (laser origins given), cycling through the queries.
void BM_Query(benchmark::State& state, const char* spec, const char* building) {
  static std::map<std::string, double> eq1_ms;  // per building, from the dmm:eq1 run
  const Submaps& m = maps(building);
  std::vector<MapView> views;
  for (const Submap& s : m) views.push_back({&s.points, nullptr, &s.origins});
  const std::unique_ptr<Ranker> ranker = make_ranker(parse_method_spec(spec), {});
  ranker->prepare(views, 1);
  const std::size_t n = std::min<std::size_t>(100, m.size() - 1);
  std::size_t queries = 0;
  double ms = 0;
  for (auto _ : state) {
    const std::size_t q = (37 * queries) % m.size();
    std::vector<std::size_t> candidates;
    for (std::size_t k = 1; k <= n; ++k) candidates.push_back((q + k) % m.size());
    const Ranking r = ranker->rank(views[q], candidates);
    benchmark::DoNotOptimize(r.scores.data());
    ms += r.match_ms + r.prep_ms, ++queries;
  }
  const double per_query = ms / static_cast<double>(queries);
  state.counters["ms_per_query"] = per_query;
  state.counters["maps"] = static_cast<double>(n);
  if (std::string(spec) == "dmm:eq1") eq1_ms[building] = per_query;
  if (auto it = eq1_ms.find(building); it != eq1_ms.end() && it->second > 0)
    state.counters["x_eq1"] = per_query / it->second;
  state.SetLabel(building);
}
BENCHMARK_CAPTURE(BM_Query, dmm_eq1_fr101, "dmm:eq1", "fr101")->Iterations(20)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, dmm_fr101, "dmm", "fr101")->Iterations(20)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, rerank20_fr101, "rerank:20", "fr101")->Iterations(20)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, dmm_eq1_fr079, "dmm:eq1", "fr079")->Iterations(10)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, dmm_fr079, "dmm", "fr079")->Iterations(10)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Query, rerank20_fr079, "rerank:20", "fr079")->Iterations(10)->Unit(benchmark::kMillisecond);

BENCHMARK_CAPTURE(BM_Rank, dmm, "dmm")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rank, succinct, "succinct")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rank, rerank20, "rerank:20")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rank, grid11, "grid:11")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rank, sc, "sc")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Rank, sc128, "sc:128")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace partslam

BENCHMARK_MAIN();
