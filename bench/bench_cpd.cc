// CPD cost per map (the offline part of PartSLAM): fr101 submaps against the fr079 dictionary (paper data set
// #1), or the simulator when ../shared/data is absent. Serial and 2 threads in the same run; the default
// corner candidates (partitions:0) and the paper's random partitions with every box a candidate (partitions:1,
// MC inlier share >= 0, so all P parts are searched).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>

#include "core/parts/cpd.h"
#include "core/maps/dictionary.h"
#include "core/sim/simulator.h"
#include "core/maps/submap.h"
#include "io/logs/carmen_log.h"

namespace partslam {
namespace {

struct Fixture {
  Submaps maps;
  Dictionary dictionary;
};

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture f;
    const char* env = std::getenv("PARTSLAM_SHARED_DATA");
    const std::filesystem::path data = env ? env : PARTSLAM_SHARED_DATA;
    if (std::filesystem::exists(data / "fr101")) {
      f.maps = build_submaps(io::read_carmen_log(data / "fr101/fr101-corrected.log.gz").scans);
      f.dictionary = build_dictionary("fr079", io::read_carmen_log(data / "fr079/fr079-corrected.log.gz").scans);
    } else {
      SimulatorConfig a, b;
      b.seed = 2;
      f.maps = build_submaps(simulate(a).scans);
      f.dictionary = build_dictionary("sim-2", simulate(b).scans);
    }
    f.maps.resize(std::min<std::size_t>(f.maps.size(), 16));
    return f;
  }();
  return f;
}

void BM_Cpd(benchmark::State& state) {
  const Fixture& f = fixture();
  CpdConfig config;
  config.max_parts = static_cast<int>(state.range(0));
  if (state.range(2) == 1) {
    config.candidates = CandidateMode::kPartitions;
    config.maximality = MaximalityMode::kInlierShare;
    config.t_size = 0.0;
  }
  const PreparedDictionary dict = prepare_dictionary(f.dictionary.points, config);
  std::vector<const Points2*> maps;
  std::vector<std::uint64_t> keys;
  for (const Submap& m : f.maps) maps.push_back(&m.points), keys.push_back(static_cast<std::uint64_t>(m.id));
  const int threads = static_cast<int>(state.range(1));
  double parts = 0, matched = 0, candidates = 0, seconds = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto results = discover_parts_many(maps, keys, dict, config, threads);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const CpdResult& r : results) {
      parts += r.parts.size();
      matched += r.stats.matched;
      candidates += r.stats.candidates;
    }
  }
  const double n = static_cast<double>(state.iterations() * maps.size());
  state.counters["ms_per_map"] = 1e3 * seconds / n;  // wall time per map, all threads together
  state.counters["parts_per_map"] = parts / n;
  state.counters["matched_per_map"] = matched / n;
  state.counters["candidates_per_map"] = candidates / n;
}
BENCHMARK(BM_Cpd)->ArgsProduct({{100}, {1, 2}, {0, 1}})->ArgNames({"parts", "threads", "partitions"})->Unit(benchmark::kMillisecond)
    ->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace partslam

BENCHMARK_MAIN();
