// Parse throughput of the CARMEN log reader on the paper's fr079 corrected log (4791 scans x 360 beams,
// gzip). Prints scans/s and beams/s; skips when the shared data folder is absent.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "io/logs/carmen_log.h"
#include "io/logs/relations.h"

namespace {

/// The data folder: $PARTSLAM_SHARED_DATA if set (worktrees sit elsewhere), else the compiled-in path.
std::filesystem::path shared_data() {
  const char* env = std::getenv("PARTSLAM_SHARED_DATA");
  return env != nullptr && *env != '\0' ? std::filesystem::path(env)
                                        : std::filesystem::path(PARTSLAM_SHARED_DATA);
}

const std::filesystem::path kData = shared_data();

void BM_ReadCarmenLog(benchmark::State& state, const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("data file absent: " + path.string()).c_str());
    return;
  }
  std::size_t scans = 0, beams = 0;
  for (auto _ : state) {
    const partslam::io::CarmenLog log = partslam::io::read_carmen_log(path);
    benchmark::DoNotOptimize(log.scans.data());
    scans += log.scans.size();
    beams += log.stats.beams;
  }
  state.counters["scans/s"] = benchmark::Counter(static_cast<double>(scans), benchmark::Counter::kIsRate);
  state.counters["beams/s"] = benchmark::Counter(static_cast<double>(beams), benchmark::Counter::kIsRate);
}

void BM_ReadRelations(benchmark::State& state, const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) {
    state.SkipWithError(("data file absent: " + path.string()).c_str());
    return;
  }
  std::size_t relations = 0;
  for (auto _ : state) relations += partslam::io::read_relations(path).size();
  state.counters["relations/s"] =
      benchmark::Counter(static_cast<double>(relations), benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(BM_ReadCarmenLog, fr079_corrected, kData / "fr079/fr079-corrected.log.gz")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadCarmenLog, fr079_raw, kData / "fr079/fr079.clf.gz")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ReadRelations, fr079, kData / "fr079/fr079.relations")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
