// dMM speed (docs/DESIGN.md "dMM"; paper: 33 ms per map pair; floor <= 1 ms, aim <= 0.2 ms): milliseconds per map
// pair for dmm (exact branch-and-bound), dmm-ransac (the paper's baseline) and the exhaustive search over the
// same discretisation, on the same pairs in the same run. Pairs: fr079 submaps (../shared/data), half
// relevant (loop closures, docs/DESIGN.md "Tasks") and half random; without the data folder, submaps of the
// built-in simulator. Each benchmark cycles through the pairs and reports, per pair, the median / 90th
// percentile / mean time (counters median_ms, p90_ms, mean_ms; thread CPU time, so other processes on the
// machine matter less) besides Google Benchmark's own mean. Also: 1-to-N (one query against 100 maps,
// every exact score vs top-1 pruning), the best of N = 100 and 1000 maps by every search (BM_DmmTop1OfN: exact
// scores, a carried bar, the joint search, exhaustive) and CPD's case, a small crop against a whole dictionary map.
// BM_Dmm/0 and BM_Exhaustive cycle through the same pairs in the same order; BM_Dmm/1 and /2 split them into
// relevant and irrelevant. Run: build/bench_dmm [--benchmark_filter=...]
#include <benchmark/benchmark.h>
#include <time.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <random>

#include "core/maps/dictionary.h"
#include "core/matching/dmm.h"
#include "core/matching/dmm_ransac.h"
#include "core/sim/simulator.h"
#include "core/evaluation/tasks.h"
#include "io/logs/carmen_log.h"

namespace partslam {
namespace {

std::filesystem::path shared_data() {
  const char* env = std::getenv("PARTSLAM_SHARED_DATA");
  return env != nullptr && *env != '\0' ? std::filesystem::path(env) : std::filesystem::path(PARTSLAM_SHARED_DATA);
}

struct Data {
  std::string source;
  Submaps maps;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (query, map)
  Scans dictionary_scans;                                   // another building, for the crop benchmark
};

const Data& data() {
  static const Data d = [] {
    Data out;
    const std::filesystem::path fr079 = shared_data() / "fr079" / "fr079-corrected.log.gz";
    const std::filesystem::path intel = shared_data() / "intel" / "intel-corrected.log.gz";
    if (std::filesystem::exists(fr079) && std::filesystem::exists(intel)) {
      out.source = "fr079 (dictionary: intel)";
      out.maps = build_submaps(io::read_carmen_log(fr079).scans);
      out.dictionary_scans = io::read_carmen_log(intel).scans;
    } else {
      out.source = "simulator (data folder absent)";
      out.maps = build_submaps(simulate().scans);
      SimulatorConfig other;
      other.seed = 2;
      out.dictionary_scans = simulate(other).scans;
    }
    // Alternating relevant / irrelevant pairs, so that any prefix is balanced. Irrelevant: centroids more
    // than 2R = 4 m apart (what fills a task's database).
    const std::vector<RelevantPair> relevant = relevant_pairs(out.maps, TaskConfig{});
    std::mt19937_64 rng(7);
    for (int k = 0; k < 100 && !relevant.empty(); ++k) {
      const RelevantPair& p = relevant[rng() % relevant.size()];
      out.pairs.emplace_back(p.query, p.global);
      std::size_t q = 0, m = 0;
      do {
        q = rng() % out.maps.size();
        m = rng() % out.maps.size();
      } while ((out.maps[q].T_world_map.translation() - out.maps[m].T_world_map.translation()).norm() <= 4.0);
      out.pairs.emplace_back(q, m);
    }
    return out;
  }();
  return d;
}

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

// Times one call per iteration, cycling through `n` cases; reports per-case statistics.
template <typename F>
void run_cycled(benchmark::State& state, std::size_t n, F&& call) {
  std::vector<double> ms;
  std::size_t k = 0;
  for (auto _ : state) {
    const double t0 = cpu_ms();
    benchmark::DoNotOptimize(call(k));
    ms.push_back(cpu_ms() - t0);
    k = (k + 1) % n;
  }
  std::sort(ms.begin(), ms.end());
  double sum = 0;
  for (double t : ms) sum += t;
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["p90_ms"] = ms[ms.size() * 9 / 10];
  state.counters["mean_ms"] = sum / static_cast<double>(ms.size());
  state.counters["pairs"] = static_cast<double>(std::min(n, ms.size()));
  state.SetLabel(data().source);
}

struct Prepared {
  std::vector<PreparedQuery> queries;
  std::vector<PreparedMap> maps;
};

const Prepared& prepared() {
  static const Prepared p = [] {
    Prepared out;
    for (const auto& [q, m] : data().pairs) {
      out.queries.push_back(prepare_query(data().maps[q].points));
      out.maps.push_back(prepare_map(data().maps[m].points));
    }
    return out;
  }();
  return p;
}

// Arg: 0 every pair, 1 relevant pairs only, 2 irrelevant pairs only (a task's database is 99 % irrelevant).
void BM_Dmm(benchmark::State& state) {
  const Prepared& p = prepared();
  const int kind = static_cast<int>(state.range(0));
  const std::size_t stride = kind == 0 ? 1 : 2, offset = kind == 2 ? 1 : 0;
  double inliers = 0, candidates = 0;
  run_cycled(state, p.maps.size() / stride, [&](std::size_t k) {
    const std::size_t m = offset + k * stride;
    const DmmResult r = match_dmm(p.queries[m], p.maps[m]);
    inliers += r.inlier_fraction;
    candidates += static_cast<double>(r.candidates_scored);
    return r.inliers;
  });
  state.counters["inlier_frac"] = inliers / static_cast<double>(state.iterations());
  state.counters["nodes"] = candidates / static_cast<double>(state.iterations());
}
BENCHMARK(BM_Dmm)->Arg(0)->Arg(1)->Arg(2)->Iterations(1000);

// The best pose and the next three elsewhere (the verified ranking's alternatives: >= 1 m / 0.3 rad apart):
// Arg 0 four depth-first searches (match_dmm, match_dmm_elsewhere), 1 one best-first DmmSearch, 2 one lazy
// DmmSearch (what verify_dmm uses). Same scores.
void BM_DmmNextBest(benchmark::State& state) {
  const Prepared& p = prepared();
  const bool shared = state.range(0) >= 1;
  run_cycled(state, p.maps.size(), [&](std::size_t k) {
    if (shared) {
      DmmSearch search(p.queries[k], p.maps[k], 1.0, 0.3, /*lazy=*/state.range(0) == 2);
      int inliers = 0;
      for (int a = 0; a < 4; ++a) inliers += search.next().inliers;
      return inliers;
    }
    const DmmResult best = match_dmm(p.queries[k], p.maps[k]);
    std::vector<Pose2> avoid{best.T_map_query};
    int inliers = best.inliers;
    for (int a = 0; a < 3; ++a) {
      const DmmResult r = match_dmm_elsewhere(p.queries[k], p.maps[k], avoid, 1.0, 0.3);
      avoid.push_back(r.T_map_query);
      inliers += r.inliers;
    }
    return inliers;
  });
}
BENCHMARK(BM_DmmNextBest)->Arg(0)->Arg(1)->Arg(2)->Iterations(300);

void BM_Exhaustive(benchmark::State& state) {
  const Prepared& p = prepared();
  run_cycled(state, p.maps.size(),
             [&](std::size_t k) { return match_exhaustive(p.queries[k], p.maps[k]).inliers; });
}
BENCHMARK(BM_Exhaustive)->Iterations(200)->Unit(benchmark::kMillisecond);

void BM_DmmRansac(benchmark::State& state) {
  DmmRansacConfig config;
  config.iterations = static_cast<int>(state.range(0));
  std::vector<PreparedRansacMap> maps;
  for (const auto& [q, m] : data().pairs) maps.push_back(prepare_ransac_map(data().maps[m].points, config));
  double inliers = 0;
  run_cycled(state, maps.size(), [&](std::size_t k) {
    const DmmResult r = match_dmm_ransac(data().maps[data().pairs[k].first].points, maps[k], config);
    inliers += r.inlier_fraction;
    return r.inliers;
  });
  state.counters["inlier_frac"] = inliers / static_cast<double>(state.iterations());
}
BENCHMARK(BM_DmmRansac)->Arg(1000)->Iterations(200)->Unit(benchmark::kMillisecond);

// One query against 100 database maps: every exact score (ranking) vs top-1 pruning.
void BM_DmmOneToN(benchmark::State& state) {
  const Prepared& p = prepared();
  const std::span<const PreparedMap> maps(p.maps.data(), 100);
  const int top_k = static_cast<int>(state.range(0));
  run_cycled(state, 10, [&](std::size_t k) { return match_dmm_many(p.queries[k * 10], maps, top_k).size(); });
  state.counters["ms_per_pair"] = state.counters["mean_ms"] / 100.0;
}
BENCHMARK(BM_DmmOneToN)->Arg(0)->Arg(1)->Iterations(10)->Unit(benchmark::kMillisecond);

// A database of N real maps and ten queries not in it (issue "scale", joint 1-to-N): N = 100 is every 8th fr079
// submap, the queries fr079 submaps between them (4, 84, 164, ...); N = 1000 is every fr079 submap but the query
// and intel submaps after them. Without the data folder, the simulator's submaps (N = 100 only).
struct Database {
  std::vector<PreparedQuery> queries;
  std::vector<std::vector<PreparedMap>> maps;  // per query (the query itself left out)
};

const Database& database(std::size_t n, int depth) {
  static std::map<std::pair<std::size_t, int>, Database> cache;
  if (auto it = cache.find({n, depth}); it != cache.end()) return it->second;
  DmmConfig config;
  config.search_depth = depth;
  static const Submaps others = build_submaps(data().dictionary_scans);
  const Submaps& own = data().maps;
  Database d;
  for (std::size_t q = 4; d.queries.size() < 10 && q < own.size(); q += 80) {
    d.queries.push_back(prepare_query(own[q].points));
    std::vector<PreparedMap> maps;
    for (std::size_t m = 0; m < own.size() && maps.size() < n; m += n <= 100 ? 8 : 1) {
      if (m != q) maps.push_back(prepare_map(own[m].points, config));
    }
    for (std::size_t m = 0; m < others.size() && maps.size() < n; ++m) maps.push_back(prepare_map(others[m].points, config));
    d.maps.push_back(std::move(maps));
  }
  return cache.emplace(std::pair(n, depth), std::move(d)).first->second;
}

// One query against N maps, the best map with its pose (arg 1: N; arg 2: the search depth, 0 automatic = 3 here,
// 4 = one root block per rotation). Arg 0 is the search: 0 every map's exact score (what ranking needs), 1 per-map
// branch-and-bound with the best score so far carried from map to map as the bar (Cartographer's global
// localiser), 2 the joint search (match_dmm_joint), 3 the exhaustive search (N = 100 only). Every search's best
// score is checked against the exact one.
void BM_DmmTop1OfN(benchmark::State& state) {
  const int mode = static_cast<int>(state.range(0));
  const auto n = static_cast<std::size_t>(state.range(1));
  const Database& d = database(n, static_cast<int>(state.range(2)));
  std::vector<std::vector<const PreparedMap*>> pointers(d.queries.size());
  std::vector<int> best(d.queries.size(), 0);
  for (std::size_t q = 0; q < d.queries.size(); ++q) {
    for (const PreparedMap& m : d.maps[q]) pointers[q].push_back(&m);
    for (const DmmResult& r : match_dmm_many(d.queries[q], pointers[q])) best[q] = std::max(best[q], r.inliers);
  }
  run_cycled(state, d.queries.size(), [&](std::size_t q) {
    int top = 0;
    if (mode == 3) {
      for (const PreparedMap* m : pointers[q]) top = std::max(top, match_exhaustive(d.queries[q], *m).inliers);
    } else {
      const std::vector<DmmResult> r = mode == 2 ? match_dmm_joint(d.queries[q], pointers[q], 1)
                                                 : match_dmm_many(d.queries[q], pointers[q], mode == 1 ? 1 : 0);
      for (const DmmResult& x : r) top = std::max(top, x.inliers);
    }
    if (top != best[q]) state.SkipWithError("the search missed the best score");
    return top;
  });
  state.counters["maps"] = static_cast<double>(d.maps.front().size());
  state.counters["ms_per_map"] = state.counters["mean_ms"] / static_cast<double>(d.maps.front().size());
}
BENCHMARK(BM_DmmTop1OfN)
    ->Args({0, 100, 0})->Args({1, 100, 0})->Args({2, 100, 0})->Args({3, 100, 0})
    ->Args({0, 1000, 0})->Args({1, 1000, 0})->Args({2, 1000, 0})
    ->Args({1, 100, 4})->Args({2, 100, 4})->Args({1, 1000, 4})->Args({2, 1000, 4})
    ->Iterations(10)->Unit(benchmark::kMillisecond);

std::size_t bytes(const PreparedMap& m);

// CPD (Eq. 2): 2-10 m crops of the submaps against a whole dictionary map (another building), translation
// window = the whole dictionary (dmm_config_for_dictionary).
void BM_DmmCropOnDictionary(benchmark::State& state) {
  const DmmConfig config = dmm_config_for_dictionary();
  static const Dictionary dictionary = build_dictionary("bench", data().dictionary_scans);
  static const PreparedMap map = prepare_map(dictionary.points, config);
  std::vector<PreparedQuery> crops;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> side(2.0, 10.0), corner(-6.4, 6.4);
  double points = 0;
  while (crops.size() < 50) {
    const Submap& m = data().maps[rng() % data().maps.size()];
    const double w = side(rng), h = side(rng), x = corner(rng), y = corner(rng);
    Points2 crop;
    for (const Vec2& p : m.points) {
      if (p.x() >= x && p.x() < x + w && p.y() >= y && p.y() < y + h) crop.push_back(p);
    }
    if (crop.size() < 20) continue;
    const Vec2 c = centroid(crop);
    for (Vec2& p : crop) p -= c;
    points += static_cast<double>(crop.size());
    crops.push_back(prepare_query(crop, config));
  }
  run_cycled(state, crops.size(), [&](std::size_t k) { return match_dmm(crops[k], map).inliers; });
  const Box2 box = bounding_box(dictionary.points);
  state.counters["dict_m2"] = box.area();
  state.counters["dict_MB"] = static_cast<double>(bytes(map)) / (1024.0 * 1024.0);
  state.counters["crop_points"] = points / static_cast<double>(crops.size());
}
BENCHMARK(BM_DmmCropOnDictionary)->Iterations(100)->Unit(benchmark::kMillisecond);

// Preparation: once per stored map (grid + packed pyramid) and once per query (rotated cell sets).
std::size_t bytes(const PreparedMap& m) {
  std::size_t total = m.grid.cells.size();
  for (const PackedLevel& p : m.packed) total += p.cells.size() * sizeof(std::uint16_t);
  return total;
}

void BM_PrepareMap(benchmark::State& state) {
  run_cycled(state, data().maps.size(), [&](std::size_t k) { return prepare_map(data().maps[k].points).packed.size(); });
  double total = 0;
  for (const PreparedMap& m : prepared().maps) total += static_cast<double>(bytes(m));
  state.counters["kB_per_map"] = total / static_cast<double>(prepared().maps.size()) / 1024.0;
}
BENCHMARK(BM_PrepareMap)->Iterations(400);

void BM_PrepareQuery(benchmark::State& state) {
  run_cycled(state, data().maps.size(),
             [&](std::size_t k) { return prepare_query(data().maps[k].points).rotations.size(); });
}
BENCHMARK(BM_PrepareQuery)->Iterations(400);

}  // namespace
}  // namespace partslam

BENCHMARK_MAIN();
