// Descriptor matcher speed (paper §"Time Efficiency"; docs/DESIGN.md "DM": target <= 5 ns per map pair).
// One query against 1,000,000 stored descriptors of K parts on a 60 m x 40 m dictionary, seeded and
// plausible: a map's parts have sides of 2-10 m and overlap one another (the GC criterion); a "tight"
// scenario (bigger parts on a smaller dictionary) shows the kernel without much block pruning. Compares
// DescriptorDatabase::score_all with the naive per-pair match_score() in the same run.
//   iMM: query of K parts vs database of K parts (Sum-Max).       hMM: query of 100 parts vs K = 3 (SMW).
// Counters: ns_per_map = time per stored map (= per map pair), ms = time per query, bytes_per_map.
// score_all runs with the origin gate the CLI uses (kDefaultOriginGate) unless its gate argument is 0.
#include <benchmark/benchmark.h>

#include <memory>
#include <random>

#include "core/parts/descriptor_database.h"
#include "core/parts/part_codec.h"

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

}  // namespace
}  // namespace partslam

BENCHMARK_MAIN();
