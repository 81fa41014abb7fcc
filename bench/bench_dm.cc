// Descriptor matcher speed (paper §"Time Efficiency"; docs/DESIGN.md "DM": target <= 5 ns per map pair).
// One query against 1,000,000 stored descriptors of K parts on a 60 m x 40 m dictionary, seeded and
// plausible: a map's parts have sides of 2-10 m and overlap one another (the GC criterion); a "tight"
// scenario (bigger parts on a smaller dictionary) shows the kernel without much block pruning. Compares
// DescriptorDatabase::score_all with the naive per-pair match_score() in the same run.
//   iMM: query of K parts vs database of K parts (Sum-Max).       hMM: query of 100 parts vs K = 3 (SMW).
// Counters: ns_per_map = time per stored map (= per map pair), ms = time per query, bytes_per_map.
// score_all runs with the origin gate the CLI uses (kDefaultOriginGate) unless its gate argument is 0.
//
// The succinct matcher's index (core/matching/grid_index.h) against its scan, top 100, on real and on synthetic
// databases (BM_Grid*; --benchmark_filter=Grid): the real grids are fr079's, intel's and aces' submaps (the
// simulator's when ../shared/data is absent) with their hubness values; a synthetic database of N maps holds
// revisits of the real maps: a real grid moved by -1..1 cells each way and a quarter turn, about a tenth of its
// occupied cells cleared and two cells set at random, with its map's mu moved by -1..1 levels. Queries: the
// real submaps' own query grids (every 97th). Both report ms per query, ns per stored map and bytes per map;
// the index also the maps it scored; a benchmark stops with an error if the index's top 100 differs from the
// scan's.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>
#include <random>

#include "core/maps/submap.h"
#include "core/matching/grid_index.h"
#include "core/parts/descriptor_database.h"
#include "core/parts/part_codec.h"
#include "core/sim/simulator.h"
#include "io/carmen_log.h"

namespace partslam {
namespace {

constexpr std::size_t kMaps = 1'000'000;
constexpr std::size_t kNaiveHmmMaps = 100'000;  // the naive hMM baseline is slow; scored on a prefix
// "roomy": the default above. "tight": parts of 6-12.8 m on a 40 m x 25 m dictionary, so most blocks overlap
// most query parts and block pruning helps little (close to the kernel's worst case).
struct Scenario {
  double dict_w, dict_h;   // dictionary extent [m]
  int min_side, max_side;  // part sides [0.1 m cells]
};
constexpr Scenario kRoomy{60.0, 40.0, 20, 100}, kTight{40.0, 25.0, 60, 128};

// A part whose descriptor box lies within `spread` of (cx, cy); coordinates on the 0.1 m grid.
Part random_part(std::mt19937& rng, const Scenario& sc, double cx, double cy, double spread) {
  std::uniform_int_distribution<int> side(sc.min_side, sc.max_side),
      jitter(-static_cast<int>(spread * 10), static_cast<int>(spread * 10));
  std::uniform_int_distribution<int> corner(-64, 0), turns(0, 3);
  const int w = side(rng), h = side(rng);
  Part p;
  const int kx = std::max(-64, corner(rng) - w / 4), ky = std::max(-64, corner(rng) - h / 4);
  p.keypoint_box = {0.1 * kx, 0.1 * std::min(64, kx + w), 0.1 * ky, 0.1 * std::min(64, ky + h)};
  p.rotation = turns(rng);
  const int ox = static_cast<int>(cx * 10) + jitter(rng) - w / 2,
            oy = static_cast<int>(cy * 10) + jitter(rng) - h / 2;
  p.descriptor_box = place_rotated_box(p.keypoint_box, p.rotation, {0.1 * ox, 0.1 * oy});
  p.appearance_score = std::uniform_real_distribution<double>(0.3, 1.0)(rng);
  return p;
}

MapDescriptor random_map(std::mt19937& rng, int parts, const Scenario& sc = kRoomy, double spread = 2.0) {
  const double cx = std::uniform_real_distribution<double>(0, sc.dict_w)(rng);
  const double cy = std::uniform_real_distribution<double>(0, sc.dict_h)(rng);
  MapDescriptor d;
  for (int k = 0; k < parts; ++k) d.parts.push_back(random_part(rng, sc, cx, cy, spread));
  return d;
}

// 100 query parts: "spread" puts each anywhere on the dictionary (pessimistic for block pruning),
// otherwise they cluster within 5 m of one place.
MapDescriptor hmm_query(std::mt19937& rng, bool spread, const Scenario& sc) {
  if (!spread) return random_map(rng, 100, sc, 5.0);
  MapDescriptor d;
  for (int i = 0; i < 100; ++i) d.parts.push_back(random_map(rng, 1, sc).parts[0]);
  return d;
}

// Keeps one data set alive at a time (1M descriptors of 5 parts take ~0.4 GB as MapDescriptors).
struct DataSet {
  int k = 0;
  bool tight = false;
  std::vector<MapDescriptor> maps;
  std::unique_ptr<DescriptorDatabase> sorted, unsorted;
};

DataSet& data(int k, bool tight = false) {
  static DataSet d;
  if (d.k != k || d.tight != tight) {
    d = DataSet{};
    std::mt19937 rng(1000 + k);
    d.maps.reserve(kMaps);
    for (std::size_t i = 0; i < kMaps; ++i) d.maps.push_back(random_map(rng, k, tight ? kTight : kRoomy));
    d.sorted = std::make_unique<DescriptorDatabase>(d.maps, DescriptorDatabaseConfig{.parts_per_map = k});
    d.unsorted = std::make_unique<DescriptorDatabase>(
        d.maps, DescriptorDatabaseConfig{.parts_per_map = k, .spatial_order = false});
    d.k = k;
    d.tight = tight;
  }
  return d;
}

void set_counters(benchmark::State& state, std::size_t maps, std::size_t bytes = 0) {
  state.counters["ns_per_map"] =
      benchmark::Counter(static_cast<double>(maps) * 1e-9,
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["ms"] =
      benchmark::Counter(1e-3, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  if (bytes) state.counters["bytes_per_map"] = static_cast<double>(bytes) / static_cast<double>(maps);
}

ScoreOptions options(const benchmark::State& state) {
  return {.num_threads = static_cast<int>(state.range(2)), .origin_gate = state.range(4) ? kDefaultOriginGate : 0.0};
}

// args: K, spatial order (1/0), threads, tight scenario (1/0), origin gate (1/0)
void BM_ScoreAll_iMM(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const bool tight = state.range(3) != 0;
  DataSet& d = data(k, tight);
  const DescriptorDatabase& db = state.range(1) ? *d.sorted : *d.unsorted;
  std::mt19937 rng(7);
  const MapDescriptor query = random_map(rng, k, tight ? kTight : kRoomy);
  for (auto _ : state)
    benchmark::DoNotOptimize(
        db.score_all(query, Matcher::kSumMax, options(state)));
  set_counters(state, kMaps, db.memory_bytes());
}

void BM_Naive_iMM(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const DataSet& d = data(k);
  std::mt19937 rng(7);
  const MapDescriptor query = random_map(rng, k);
  std::vector<float> scores(kMaps);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kMaps; ++i)
      scores[i] = static_cast<float>(match_score(query, d.maps[i], Matcher::kSumMax));
    benchmark::DoNotOptimize(scores.data());
  }
  set_counters(state, kMaps);
}

// args: spread query (1/0), spatial order (1/0), threads, tight scenario (1/0)
void BM_ScoreAll_hMM(benchmark::State& state) {
  const bool tight = state.range(3) != 0;
  DataSet& d = data(3, tight);
  const DescriptorDatabase& db = state.range(1) ? *d.sorted : *d.unsorted;
  std::mt19937 rng(11);
  const MapDescriptor query = hmm_query(rng, state.range(0) != 0, tight ? kTight : kRoomy);
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        db.score_all(query, Matcher::kSumMaxWeighted, options(state)));
  }
  set_counters(state, kMaps, db.memory_bytes());
}

void BM_Naive_hMM(benchmark::State& state) {
  const DataSet& d = data(3);
  std::mt19937 rng(11);
  const MapDescriptor query = hmm_query(rng, state.range(0) != 0, kRoomy);
  std::vector<float> scores(kNaiveHmmMaps);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kNaiveHmmMaps; ++i) {
      scores[i] = static_cast<float>(match_score(query, d.maps[i], Matcher::kSumMaxWeighted));
    }
    benchmark::DoNotOptimize(scores.data());
  }
  set_counters(state, kNaiveHmmMaps);
}

void BM_ScoreAll_Matchers(benchmark::State& state) {
  DataSet& d = data(3);
  std::mt19937 rng(7);
  const MapDescriptor query = random_map(rng, 3);
  const Matcher m = static_cast<Matcher>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(d.sorted->score_all(query, m));
  state.SetLabel(to_string(m));
  set_counters(state, kMaps);
}

// Encode + decode of one stored descriptor; reports its exact size.
void BM_Codec(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  CodecConfig c;
  c.dictionary_extent = {-20, kRoomy.dict_w + 20, -20, kRoomy.dict_h + 20};
  c.score_bits = static_cast<int>(state.range(1));
  std::mt19937 rng(5);
  const MapDescriptor d = random_map(rng, k);
  for (auto _ : state) benchmark::DoNotOptimize(decode(encode(d, c), c));
  state.counters["bits_per_map"] = packed_bits(k, c);
  state.counters["bytes_per_map"] = static_cast<double>((packed_bits(k, c) + 7) / 8);
}

// Bulk construction of the 1M-map database (K = 3, Morton order).
void BM_Build(benchmark::State& state) {
  const DataSet& d = data(3);
  for (auto _ : state) benchmark::DoNotOptimize(DescriptorDatabase(d.maps));
  set_counters(state, kMaps);
}

BENCHMARK(BM_Codec)->ArgsProduct({{1, 2, 3, 4, 5}, {0, 4}});
// Per K: the naive baseline, then the database unsorted (no effective pruning: the raw kernel) and sorted.
// Threaded runs report wall time (the machine may be shared: compare with care).
// Single-threaded runs are timed in CPU time (the machine may be shared); threaded runs in wall time.
void single(benchmark::internal::Benchmark* b) { b->Unit(benchmark::kMillisecond); }
void threaded(benchmark::internal::Benchmark* b) {
  b->UseRealTime()->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);
}
BENCHMARK(BM_Naive_iMM)->Arg(1)->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({1, 0, 1, 0, 1})->Args({1, 1, 1, 0, 1})->Apply(single);
BENCHMARK(BM_Naive_iMM)->Arg(2)->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({2, 0, 1, 0, 1})->Args({2, 1, 1, 0, 1})->Apply(single);
BENCHMARK(BM_Naive_iMM)->Arg(3)->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({3, 0, 1, 0, 1})->Args({3, 1, 1, 0, 1})->Args({3, 1, 1, 0, 0})->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({3, 1, 2, 0, 1})->Apply(threaded);
BENCHMARK(BM_ScoreAll_Matchers)->DenseRange(0, 2)->Apply(single);
BENCHMARK(BM_Build)->Apply(single);
BENCHMARK(BM_Naive_hMM)->Arg(1)->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)->Args({1, 0, 1, 0, 1})->Args({1, 1, 1, 0, 1})->Args({0, 1, 1, 0, 1})->Args({1, 1, 1, 0, 0})
    ->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)->Args({1, 1, 2, 0, 1})->Apply(threaded);
BENCHMARK(BM_ScoreAll_iMM)->Args({3, 1, 1, 1, 1})->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)->Args({1, 1, 1, 1, 1})->Args({0, 1, 1, 1, 1})->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)->Args({1, 1, 2, 1, 1})->Apply(threaded);
BENCHMARK(BM_Naive_iMM)->Arg(4)->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({4, 0, 1, 0, 1})->Args({4, 1, 1, 0, 1})->Apply(single);
BENCHMARK(BM_Naive_iMM)->Arg(5)->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({5, 0, 1, 0, 1})->Args({5, 1, 1, 0, 1})->Apply(single);

// ---- the succinct matcher: index vs scan ----

struct GridData {
  std::vector<GridBits> real_grids;
  std::vector<double> real_mu;
  std::vector<std::vector<GridBits>> queries;  // query grids of every 97th real submap
};

const GridData& grid_data() {
  static const GridData d = [] {
    GridData out;
    const GridConfig config = succinct_grid_config();
    const char* env = std::getenv("PARTSLAM_SHARED_DATA");
    const std::filesystem::path shared = env != nullptr && *env != '\0' ? env : PARTSLAM_SHARED_DATA;
    std::vector<Submap> maps;
    for (const char* log : {"fr079/fr079-corrected.log.gz", "intel/intel-corrected.log.gz", "aces/aces-corrected.log.gz"})
      if (std::filesystem::exists(shared / log))
        for (Submap& m : build_submaps(io::read_carmen_log(shared / log).scans)) maps.push_back(std::move(m));
    if (maps.empty()) maps = build_submaps(simulate().scans);
    std::vector<const Points2*> points;
    for (const Submap& m : maps) out.real_grids.push_back(make_grid(m.points, config)), points.push_back(&m.points);
    out.real_mu = grid_hubness(points, out.real_grids, config);
    for (std::size_t i = 0; i < maps.size(); i += 97) out.queries.push_back(make_query_grids(maps[i].points, config));
    return out;
  }();
  return d;
}

// A real grid moved by (dx, dy) cells and turned k quarter turns about the grid's centre.
GridBits move_grid(const GridBits& g, int dx, int dy, int k, int s) {
  GridBits out;
  for (int y = 0; y < s; ++y)
    for (int x = 0; x < s; ++x) {
      const int i = x + s * y;
      if (!((g.words[static_cast<std::size_t>(i >> 6)] >> (i & 63)) & 1)) continue;
      int u = x + dx, v = y + dy;
      for (int t = 0; t < k; ++t) std::tie(u, v) = std::pair{s - 1 - v, u};
      if (u < 0 || v < 0 || u >= s || v >= s) continue;
      const int j = u + s * v;
      out.words[static_cast<std::size_t>(j >> 6)] |= std::uint64_t{1} << (j & 63);
    }
  return out;
}

struct GridDatabase {
  std::vector<GridBits> grids;
  std::vector<double> mu;
  std::unique_ptr<GridIndex> index;
  double build_s = 0;
};

// n = 0: the real grids themselves.
const GridDatabase& grid_database(std::size_t n) {
  static std::map<std::size_t, GridDatabase> cache;
  if (auto it = cache.find(n); it != cache.end()) return it->second;
  cache.clear();  // one at a time (10 M maps: ~0.6 GB with the index)
  const GridData& real = grid_data();
  GridDatabase db;
  if (n == 0) {
    db.grids = real.real_grids;
    db.mu = real.real_mu;
  } else {
    const int s = succinct_grid_config().cells;
    std::mt19937_64 rng(n);
    std::uniform_int_distribution<std::size_t> pick(0, real.real_grids.size() - 1);
    std::uniform_int_distribution<int> shift(-1, 1), turn(0, 3), cell(0, s * s - 1);
    std::bernoulli_distribution clear(0.1);
    db.grids.reserve(n);
    db.mu.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t r = pick(rng);
      GridBits g = move_grid(real.real_grids[r], shift(rng), shift(rng), turn(rng), s);
      for (int w = 0; w < 2; ++w)
        for (std::uint64_t bits = g.words[static_cast<std::size_t>(w)]; bits != 0; bits &= bits - 1)
          if (clear(rng)) g.words[static_cast<std::size_t>(w)] &= ~(bits & -bits);
      for (int extra = 0; extra < 2; ++extra) {
        const int j = cell(rng);
        g.words[static_cast<std::size_t>(j >> 6)] |= std::uint64_t{1} << (j & 63);
      }
      db.grids.push_back(g);
      db.mu.push_back(std::clamp(real.real_mu[r] + shift(rng) / 127.0, 0.0, 1.0));
    }
  }
  const auto t0 = std::chrono::steady_clock::now();
  db.index = std::make_unique<GridIndex>(db.grids, db.mu, succinct_grid_config().hub_weight);
  db.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return cache.emplace(n, std::move(db)).first->second;
}

constexpr std::size_t kGridTop = 100;

// arg: stored maps (0: the real database)
void BM_GridScan(benchmark::State& state) {
  const GridDatabase& db = grid_database(static_cast<std::size_t>(state.range(0)));
  const GridData& real = grid_data();
  const GridConfig config = succinct_grid_config();
  std::size_t q = 0;
  for (auto _ : state) {
    const GridQuery query(real.queries[q++ % real.queries.size()], config);
    benchmark::DoNotOptimize(scan_top_k(query, db.grids, db.mu, config.hub_weight, kGridTop));
  }
  set_counters(state, db.grids.size(), db.grids.size() * sizeof(GridBits) + db.mu.size());  // mu: 7 bits
}

void BM_GridIndex(benchmark::State& state) {
  const GridDatabase& db = grid_database(static_cast<std::size_t>(state.range(0)));
  const GridData& real = grid_data();
  const GridConfig config = succinct_grid_config();
  // Identical top 100 on every query first (untimed).
  std::vector<GridQuery> queries;
  GridSearchStats stats;
  for (const auto& grids : real.queries) {
    queries.emplace_back(grids, config);
    if (state.range(0) <= 1'000'000 || queries.size() <= 3) {
      if (db.index->top_k(queries.back(), kGridTop) !=
          scan_top_k(queries.back(), db.grids, db.mu, config.hub_weight, kGridTop)) {
        state.SkipWithError("the index's top 100 differs from the scan's");
        return;
      }
    }
  }
  std::size_t q = 0;
  for (auto _ : state) benchmark::DoNotOptimize(db.index->top_k(queries[q++ % queries.size()], kGridTop, &stats));
  set_counters(state, db.grids.size(), db.index->memory_bytes());
  state.counters["maps_scored"] = static_cast<double>(stats.maps_scored) / static_cast<double>(q);
  state.counters["nodes"] = static_cast<double>(stats.nodes_visited) / static_cast<double>(q);
  state.counters["build_s"] = db.build_s;
}

// Real database; synthetic at 1 M and 10 M. The 10 M scan takes seconds per query: a few iterations only.
BENCHMARK(BM_GridScan)->Arg(0)->Apply(single);
BENCHMARK(BM_GridIndex)->Arg(0)->Apply(single);
BENCHMARK(BM_GridScan)->Arg(100'000)->Iterations(18)->Apply(single);  // 18: every query once
BENCHMARK(BM_GridIndex)->Arg(100'000)->Apply(single);
BENCHMARK(BM_GridScan)->Arg(1'000'000)->Iterations(6)->Apply(single);
BENCHMARK(BM_GridIndex)->Arg(1'000'000)->Apply(single);
BENCHMARK(BM_GridScan)->Arg(10'000'000)->Iterations(3)->Apply(single);
BENCHMARK(BM_GridIndex)->Arg(10'000'000)->Apply(single);

}  // namespace
}  // namespace partslam

BENCHMARK_MAIN();
