// Descriptor matcher speed (paper §"Time Efficiency"; docs/DESIGN.md "DM": target <= 5 ns per map pair).
// One query against 1,000,000 stored descriptors of K parts on a 60 m x 40 m dictionary, seeded and
// plausible: a map's parts have sides of 2-10 m and overlap one another (the GC criterion); a "tight"
// scenario (bigger parts on a smaller dictionary) shows the kernel without much block pruning. Compares
// DescriptorDatabase::score_all with the naive per-pair match_score() in the same run.
//   iMM: query of K parts vs database of K parts (Sum-Max).       hMM: query of 100 parts vs K = 3 (SMW).
// Counters: ns_per_map = time per stored map (= per map pair), ms = time per query, bytes_per_map.
// score_all runs with the origin gate the CLI uses (kDefaultOriginGate) unless its gate argument is 0.
//
// The succinct matcher at fleet scale (BM_Succinct*; --benchmark_filter=Succinct; the last argument is the
// number of stored maps): the exact scan (AVX-512 kernels; BM_SuccinctScalarScan: the scalar scan_top_k it
// replaces) and the cascade of core/matching/grid_cascade.h, top 100, on a database of real-looking maps
// (large_grid_db below: real submaps of the other buildings turned, moved and thinned, with the real relevant
// maps of 32 queries planted). They report ms per query, ns per stored map, bytes per map and in_top100: the
// queries whose relevant map the top 100 holds; the scan also the quartiles of the relevant maps' ranks, the
// cascade its stages' ms and the queries both it and the scan found.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <random>

#include "core/evaluation/tasks.h"
#include "core/maps/submap.h"
#include "core/matching/grid_cascade.h"
#include "core/parallel.h"
#include "core/parts/descriptor_database.h"
#include "core/parts/part_codec.h"
#include "core/sim/simulator.h"
#include "io/logs/carmen_log.h"

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
  return {.num_threads = static_cast<int>(state.range(2)),
          .origin_gate = state.range(4) ? kDefaultOriginGate : 0.0};
}

// args: K, spatial order (1/0), threads, tight scenario (1/0), origin gate (1/0)
void BM_ScoreAll_iMM(benchmark::State& state) {
  const int k = static_cast<int>(state.range(0));
  const bool tight = state.range(3) != 0;
  DataSet& d = data(k, tight);
  const DescriptorDatabase& db = state.range(1) ? *d.sorted : *d.unsorted;
  std::mt19937 rng(7);
  const MapDescriptor query = random_map(rng, k, tight ? kTight : kRoomy);
  for (auto _ : state) benchmark::DoNotOptimize(db.score_all(query, Matcher::kSumMax, options(state)));
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
    benchmark::DoNotOptimize(db.score_all(query, Matcher::kSumMaxWeighted, options(state)));
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
BENCHMARK(BM_ScoreAll_iMM)
    ->Args({3, 0, 1, 0, 1})
    ->Args({3, 1, 1, 0, 1})
    ->Args({3, 1, 1, 0, 0})
    ->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({3, 1, 2, 0, 1})->Apply(threaded);
BENCHMARK(BM_ScoreAll_Matchers)->DenseRange(0, 2)->Apply(single);
BENCHMARK(BM_Build)->Apply(single);
BENCHMARK(BM_Naive_hMM)->Arg(1)->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)
    ->Args({1, 0, 1, 0, 1})
    ->Args({1, 1, 1, 0, 1})
    ->Args({0, 1, 1, 0, 1})
    ->Args({1, 1, 1, 0, 0})
    ->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)->Args({1, 1, 2, 0, 1})->Apply(threaded);
BENCHMARK(BM_ScoreAll_iMM)->Args({3, 1, 1, 1, 1})->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)->Args({1, 1, 1, 1, 1})->Args({0, 1, 1, 1, 1})->Apply(single);
BENCHMARK(BM_ScoreAll_hMM)->Args({1, 1, 2, 1, 1})->Apply(threaded);
BENCHMARK(BM_Naive_iMM)->Arg(4)->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({4, 0, 1, 0, 1})->Args({4, 1, 1, 0, 1})->Apply(single);
BENCHMARK(BM_Naive_iMM)->Arg(5)->Apply(single);
BENCHMARK(BM_ScoreAll_iMM)->Args({5, 0, 1, 0, 1})->Args({5, 1, 1, 0, 1})->Apply(single);

// ---- the succinct matcher at fleet scale: the cascade against the scan ----

// The real buildings: every log of ../shared/data there is, as submaps (8 m range, as eval) and grids.
struct Building {
  std::string name;
  Submaps maps;
  std::vector<GridBits> grids;
};
constexpr const char* kLogs[] = {"fr079/fr079-corrected.log.gz",
                                 "intel/intel-corrected.log.gz",
                                 "aces/aces-corrected.log.gz",
                                 "fr101/fr101-corrected.log.gz",
                                 "corrected/acapulco-corrected.log.gz",
                                 "corrected/belgioioso-corrected.log.gz",
                                 "corrected/edmonton-corrected.log.gz",
                                 "corrected/fhw-corrected.log.gz",
                                 "corrected/freiburg-campus-corrected.log.gz",
                                 "corrected/infinite-corridor-corrected.log.gz",
                                 "corrected/orebro-corrected.log.gz",
                                 "corrected/seattle-corrected.log.gz"};
constexpr std::size_t kQueryBuildings = 3;  // the queries' buildings: the first three logs (the tuning sets)
constexpr int kQueriesPerBuilding = 20;
constexpr std::size_t kHubProbes = 32;  // probes of the large database's mu (the ranker's default: 256)

Building building(std::string name, Submaps maps) {
  const GridConfig config = succinct_grid_config();
  Building b{std::move(name), std::move(maps), {}};
  for (const Submap& m : b.maps) b.grids.push_back(make_grid(m.points, config));
  return b;
}

const std::vector<Building>& buildings() {
  static const std::vector<Building> out = [] {
    std::vector<Building> v;
    const char* env = std::getenv("PARTSLAM_SHARED_DATA");
    const std::filesystem::path shared = env != nullptr && *env != '\0' ? env : PARTSLAM_SHARED_DATA;
    for (const char* log : kLogs) {
      if (!std::filesystem::exists(shared / log)) continue;
      v.push_back(building(log, build_submaps(io::read_carmen_log(shared / log).scans)));
    }
    if (v.size() <= kQueryBuildings) {  // no real data: the simulator's submaps stand in for every building
      v.assign(kQueryBuildings + 1, building("simulated", build_submaps(simulate().scans)));
    }
    return v;
  }();
  return out;
}

// A database of n maps: the relevant maps of the queries (eval's tasks of the first three buildings, R = 2 m,
// seed 1, 20 a building whose relevant maps lie farther than 2R from the other queries) planted at spread
// positions, and distractors: real submaps of the other buildings, each turned by a random quarter turn and
// +-3 degrees, moved by up to 0.75 m each way, a fifth of its points dropped, with its map's mu. (Distractors
// from the queries' own buildings would include copies of the queries' places.)
struct LargeGridDb {
  std::vector<GridBits> grids;
  std::vector<double> mu;
  std::vector<std::vector<GridBits>> queries;
  std::vector<std::size_t> relevant;  // the planted map of each query
  std::unique_ptr<GridCascade> cascade;
  double build_s = 0;
  std::vector<char> scan_hit;  // the scan's top 100 holds the relevant map (filled by the scan's run)
};

Points2 perturbed(const Points2& points, std::mt19937_64& rng) {
  const int turn = std::uniform_int_distribution<int>(0, 3)(rng);
  const double a = turn * std::numbers::pi / 2 +
                   std::uniform_real_distribution<double>(-3, 3)(rng) * std::numbers::pi / 180;
  std::uniform_real_distribution<double> shift(-0.75, 0.75);
  const Vec2 d{shift(rng), shift(rng)};
  std::bernoulli_distribution kept(0.8);
  const double c = std::cos(a), s = std::sin(a);
  Points2 out;
  for (const Vec2& p : points)
    if (kept(rng)) out.push_back(Vec2{c * p.x() - s * p.y(), s * p.x() + c * p.y()} + d);
  return out;
}

LargeGridDb& large_grid_db(std::size_t n) {
  static std::map<std::size_t, LargeGridDb> cache;
  if (auto it = cache.find(n); it != cache.end()) return it->second;
  cache.clear();  // one at a time (10 M maps: ~0.6 GB)
  const std::vector<Building>& all = buildings();
  const GridConfig config = succinct_grid_config();
  LargeGridDb db;
  std::vector<GridBits> planted;
  for (std::size_t b = 0; b < kQueryBuildings; ++b) {
    const Submaps& maps = all[b].maps;
    std::vector<Task> chosen;
    for (const Task& t : make_tasks(maps, TaskConfig{})) {
      auto far = [&](std::size_t i, std::size_t j) {
        return (maps[i].T_world_map.translation() - maps[j].T_world_map.translation()).norm() > 4.0;
      };
      if (std::all_of(chosen.begin(), chosen.end(),
                      [&](const Task& c) { return far(c.query, t.relevant) && far(t.query, c.relevant); }))
        chosen.push_back(t);
      if (chosen.size() == kQueriesPerBuilding) break;
    }
    for (const Task& t : chosen) {
      db.queries.push_back(make_query_grids(maps[t.query].points, config));
      planted.push_back(all[b].grids[t.relevant]);
    }
  }
  std::vector<const Submap*> sources;
  for (std::size_t b = kQueryBuildings; b < all.size(); ++b)
    for (std::size_t i = 0; i < all[b].maps.size(); ++i) sources.push_back(&all[b].maps[i]);
  db.grids.resize(n);
  constexpr std::size_t kChunk = 65536;  // one seed a chunk: the same maps for any thread count
  parallel_for((n + kChunk - 1) / kChunk, 2, [&](std::size_t chunk) {
    std::mt19937_64 rng(chunk + 1);
    std::uniform_int_distribution<std::size_t> pick(0, sources.size() - 1);
    for (std::size_t i = chunk * kChunk; i < std::min(n, (chunk + 1) * kChunk); ++i) {
      db.grids[i] = make_grid(perturbed(sources[pick(rng)]->points, rng), config);
    }
  });
  for (std::size_t j = 0; j < planted.size() && j < n; ++j) {
    db.relevant.push_back(j * (n / planted.size()) + n / (2 * planted.size()));
    db.grids[db.relevant.back()] = planted[j];
  }
  db.queries.resize(db.relevant.size());
  // Every map's mu from its own grid, as the ranker computes it (grid_hubness: the mean best-pose similarity
  // of probe queries), over kHubProbes probes spread over the distractors' buildings, on the exact-scan
  // kernels.
  std::vector<const Points2*> probes;
  for (std::size_t k = 0; k < kHubProbes; ++k)
    probes.push_back(&sources[k * sources.size() / kHubProbes]->points);
  const GridCascade plain(db.grids, {}, config, {.coarse_min = n});
  std::vector<double> sum(n, 0.0);
  for (std::size_t k = 0; k < probes.size(); k += 2) {
    std::array<std::vector<double>, 2> s;
    parallel_for(std::min<std::size_t>(2, probes.size() - k), 2,
                 [&](std::size_t j) { s[j] = plain.scores(make_query_grids(*probes[k + j], config)); });
    for (const std::vector<double>& one : s)
      for (std::size_t i = 0; i < one.size(); ++i) sum[i] += one[i];
  }
  const double levels = std::ldexp(1.0, config.hub_bits) - 1;
  db.mu.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    db.mu[i] = std::round(sum[i] / static_cast<double>(probes.size()) * levels) / levels;
  const auto t0 = std::chrono::steady_clock::now();
  db.cascade = std::make_unique<GridCascade>(db.grids, db.mu, config);
  db.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return cache.emplace(n, std::move(db)).first->second;
}

constexpr std::size_t kGridTop = 100;

// How many queries' relevant maps the top 100 holds (untimed), and the rank counters.
template <typename TopK>
std::vector<char> top100_hits(const LargeGridDb& db, TopK top_k) {
  std::vector<char> hit;
  for (std::size_t q = 0; q < db.queries.size(); ++q) {
    const std::vector<GridMatch> top = top_k(db.queries[q]);
    hit.push_back(
        std::any_of(top.begin(), top.end(), [&](const GridMatch& m) { return m.index == db.relevant[q]; }));
  }
  return hit;
}

void rank_counters(benchmark::State& state, const std::vector<char>& hit) {
  state.counters["queries"] = static_cast<double>(hit.size());
  state.counters["in_top100"] = static_cast<double>(std::count(hit.begin(), hit.end(), 1));
}

// The relevant map's rank in the exact scan (1 = first; ties by index, as top_k orders them), from every
// map's score (untimed).
std::vector<std::size_t> scan_ranks(const LargeGridDb& db, const GridCascade& scan) {
  std::vector<std::size_t> ranks;
  for (std::size_t q = 0; q < db.queries.size(); ++q) {
    const std::vector<double> s = scan.scores(db.queries[q]);
    const std::size_t rel = db.relevant[q];
    std::size_t above = 0;
    for (std::size_t i = 0; i < s.size(); ++i) above += s[i] > s[rel] || (s[i] == s[rel] && i < rel);
    ranks.push_back(above + 1);
  }
  return ranks;
}

// Quartiles of the relevant maps' ranks: rank_q1, rank_median, rank_q3.
void rank_quartiles(benchmark::State& state, std::vector<std::size_t> ranks) {
  std::sort(ranks.begin(), ranks.end());
  const auto at = [&](double share) {
    return static_cast<double>(
        ranks[static_cast<std::size_t>(share * static_cast<double>(ranks.size() - 1))]);
  };
  state.counters["rank_q1"] = at(0.25);
  state.counters["rank_median"] = at(0.5);
  state.counters["rank_q3"] = at(0.75);
}

// The exact scan, 1156 poses a map on every map (the cascade's last stage over the whole database, AVX-512
// where the CPU has it; equal to scan_top_k, grid_cascade_test), and the relevant maps' ranks in it
// (quartiles). arg: stored maps.
void BM_SuccinctScan(benchmark::State& state) {
  LargeGridDb& db = large_grid_db(static_cast<std::size_t>(state.range(0)));
  const GridConfig config = succinct_grid_config();
  const GridCascade scan(db.grids, db.mu, config, {.coarse_min = db.grids.size()});
  const std::vector<std::size_t> ranks = scan_ranks(db, scan);
  db.scan_hit.clear();
  for (std::size_t r : ranks) db.scan_hit.push_back(r <= kGridTop);
  std::size_t q = 0;
  for (auto _ : state) benchmark::DoNotOptimize(scan.top_k(db.queries[q++ % db.queries.size()], kGridTop));
  set_counters(state, db.grids.size(), scan.memory_bytes());
  rank_counters(state, db.scan_hit);
  rank_quartiles(state, ranks);
  state.counters["avx512"] = scan.simd();
}

// Today's scalar scan (scan_top_k), the reference the cascade's kernels replace. arg: stored maps.
void BM_SuccinctScalarScan(benchmark::State& state) {
  const LargeGridDb& db = large_grid_db(static_cast<std::size_t>(state.range(0)));
  const GridConfig config = succinct_grid_config();
  std::size_t q = 0;
  for (auto _ : state)
    benchmark::DoNotOptimize(
        scan_top_k(db.queries[q++ % db.queries.size()], db.grids, db.mu, config.hub_weight, kGridTop));
  set_counters(state, db.grids.size(), db.grids.size() * sizeof(GridBits) + db.mu.size());  // mu: 7 bits
}

// The cascade (grid_cascade.h, default configuration). arg: stored maps. in_top100 against the scan's: run
// after BM_SuccinctScan of the same size (both_top100: queries both put in their top 100).
void BM_SuccinctFast(benchmark::State& state) {
  const LargeGridDb& db = large_grid_db(static_cast<std::size_t>(state.range(0)));
  const std::vector<char> hit =
      top100_hits(db, [&](const std::vector<GridBits>& q) { return db.cascade->top_k(q, kGridTop); });
  GridCascadeStats stats, sum;
  std::size_t q = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(db.cascade->top_k(db.queries[q++ % db.queries.size()], kGridTop, &stats));
    sum.turns_ms += stats.turns_ms, sum.coarse_ms += stats.coarse_ms, sum.full_ms += stats.full_ms;
  }
  set_counters(state, db.grids.size(), db.cascade->memory_bytes());
  rank_counters(state, hit);
  if (db.scan_hit.size() == hit.size()) {
    std::size_t both = 0;
    for (std::size_t i = 0; i < hit.size(); ++i) both += hit[i] && db.scan_hit[i];
    state.counters["scan_in_top100"] =
        static_cast<double>(std::count(db.scan_hit.begin(), db.scan_hit.end(), 1));
    state.counters["both_top100"] = static_cast<double>(both);
  }
  state.counters["turns_ms"] = sum.turns_ms / static_cast<double>(q);
  state.counters["coarse_ms"] = sum.coarse_ms / static_cast<double>(q);
  state.counters["full_ms"] = sum.full_ms / static_cast<double>(q);
  state.counters["kept_turns"] = static_cast<double>(stats.turns_kept);
  state.counters["kept_coarse"] = static_cast<double>(stats.coarse_kept);
  state.counters["build_s"] = db.build_s;
  state.counters["avx512"] = db.cascade->simd();
}

BENCHMARK(BM_SuccinctScalarScan)->Arg(100'000)->Iterations(10)->Apply(single);
BENCHMARK(BM_SuccinctScan)->Arg(100'000)->Iterations(20)->Apply(single);
BENCHMARK(BM_SuccinctFast)->Arg(100'000)->Apply(single);
BENCHMARK(BM_SuccinctScan)->Arg(1'000'000)->Iterations(10)->Apply(single);
BENCHMARK(BM_SuccinctFast)->Arg(1'000'000)->Apply(single);
BENCHMARK(BM_SuccinctScan)->Arg(10'000'000)->Iterations(3)->Apply(single);
BENCHMARK(BM_SuccinctFast)->Arg(10'000'000)->Apply(single);

}  // namespace
}  // namespace partslam

BENCHMARK_MAIN();
