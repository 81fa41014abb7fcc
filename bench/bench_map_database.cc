// Map database throughput: storing and loading a dataset shaped like fr079 (1234 submaps of 500
// points), one submap by id, and all descriptors of one (dictionary, K).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <vector>

#include "io/store/map_database.h"

namespace {

namespace fs = std::filesystem;
using partslam::io::MapDatabase;

constexpr int kSubmaps = 1234;
constexpr int kPoints = 500;

partslam::Submaps make_submaps() {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> coord(-6.4, 6.4);
  partslam::Submaps submaps(kSubmaps);
  for (auto& m : submaps) {
    for (int j = 0; j < kPoints; ++j) m.points.emplace_back(coord(rng), coord(rng));
    m.scan_timestamps.assign(40, 1.0e9);
  }
  return submaps;
}

fs::path scratch(const char* name) {
  return fs::temp_directory_path() / ("partslam_bench_" + std::to_string(::getpid()) + "_" + name + ".db");
}

void BM_StoreDataset(benchmark::State& state) {
  const partslam::Submaps submaps = make_submaps();
  const fs::path path = scratch("store");
  for (auto _ : state) {
    fs::remove(path);
    MapDatabase db = MapDatabase::open(path, MapDatabase::Mode::kCreate);
    benchmark::DoNotOptimize(db.store_dataset({"fr079", "bench", {}, {}}, submaps));
  }
  state.counters["bytes_per_submap"] = static_cast<double>(fs::file_size(path)) / kSubmaps;
  fs::remove(path);
}
BENCHMARK(BM_StoreDataset)->Unit(benchmark::kMillisecond);

class Loaded : public benchmark::Fixture {
 public:
  void SetUp(const benchmark::State&) override {
    path_ = scratch("load");
    fs::remove(path_);
    MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kCreate);
    dataset_ = db.store_dataset({"fr079", "bench", {}, {}}, make_submaps());
    std::vector<partslam::io::DescriptorRecord> records;
    for (std::int64_t id : db.map_ids(dataset_))
      records.push_back({id, {std::vector<std::uint8_t>(16, 0x5a), 126}});
    partslam::CodecConfig codec;  // 42 bits per part: 126 bits are K = 3 parts
    codec.dictionary_extent = {-20.0, 30.0, -5.0, 45.0};
    codec.rotation_bits = 0;
    db.put_descriptors("albert", 3, codec, records);
  }
  void TearDown(const benchmark::State&) override { fs::remove(path_); }

 protected:
  fs::path path_;
  std::int64_t dataset_ = 0;
};

BENCHMARK_DEFINE_F(Loaded, LoadDataset)(benchmark::State& state) {
  const MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kReadOnly);
  for (auto _ : state) benchmark::DoNotOptimize(db.load_submaps(dataset_));
}
BENCHMARK_REGISTER_F(Loaded, LoadDataset)->Unit(benchmark::kMillisecond);

BENCHMARK_DEFINE_F(Loaded, LoadOneSubmap)(benchmark::State& state) {
  const MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kReadOnly);
  std::int64_t id = 1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(db.load_submap(id));
    id = id % kSubmaps + 1;
  }
}
BENCHMARK_REGISTER_F(Loaded, LoadOneSubmap)->Unit(benchmark::kMicrosecond);

BENCHMARK_DEFINE_F(Loaded, LoadDescriptors)(benchmark::State& state) {
  const MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kReadOnly);
  for (auto _ : state) benchmark::DoNotOptimize(db.load_descriptors("albert", 3));
  state.counters["maps"] = kSubmaps;
}
BENCHMARK_REGISTER_F(Loaded, LoadDescriptors)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
