// large_db: a large map database on disk (docs/NOTES.md, "A large database on disk (measured)").
//
//   large_db generate SOURCE.db --dict NAME --out OUT.db --maps N [--k 3] [--seed 1] [--points 8] [--batch 100000]
//     Writes a new database OUT.db (which must not exist) holding the dictionary NAME of SOURCE.db, one dataset
//     'synthetic' of N submaps, and one K-part descriptor per submap under the codec of SOURCE.db's set
//     (NAME, K), drawn from the statistics of SOURCE.db's real descriptors of that set:
//       synthetic map i takes a real descriptor s (uniform over the set; the generator is std::mt19937_64(seed)
//       consumed in order, so the file's content depends only on the arguments), then
//       * shifts all its descriptor boxes together by (a, b) origin-lattice steps, a, b uniform in [-2, 2]
//         (the same parts fitting the dictionary a little elsewhere: a nearby place; redrawn, at most 20 times,
//         then 0, when a shifted origin leaves the codec's dictionary extent),
//       * moves each edge of each part's keypoint box by a uniform integer in [-1, 1] keypoint cells (0.1 m),
//         kept inside the crop and at least one cell wide; the descriptor box keeps its (shifted) corner and
//         takes the new keypoint box's shape under the part's rotation,
//       and is packed with the set's codec. Its submap row carries --points points drawn uniformly (with
//       replacement) from the real map's points, the real map's alignment angle, its pose moved by the
//       origin shift in metres, travel 0.5 i m, anchor scan i, timestamp 0.1 i s and one scan timestamp.
//     The rows are written through MapDatabase (add_submaps, put_descriptors) in batches inside one
//     transaction. Prints the build time, the file size and bytes per map.
//
//   large_db query DB [--dict NAME] [--k 3] [--map ID] [--repeat 20] [--load set|stream] [--threads 1]
//     What one query over the whole stored set costs in this process: open, load the set (--load set:
//     io::load_descriptor_set, a std::map of decoded descriptors, then DescriptorDatabase's bulk constructor;
//     --load stream: io::load_descriptor_database, rows straight into the matcher), then rank the stored
//     descriptor of map ID (default: the middle map) against every map with the default part matcher of
//     `partslam match --method imm:K` (Sum-Max, origin gate 2 m) and take the top 10; then the same rank
//     --repeat more times (warm). Prints each stage in ms and the top 10.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/parts/descriptor_database.h"
#include "core/parts/part_codec.h"
#include "core/timing.h"
#include "io/store/descriptor_store.h"
#include "io/store/map_database.h"

using namespace partslam;
namespace fs = std::filesystem;

namespace {

// --name value pairs after the positional arguments.
struct Args {
  std::vector<std::string> positional;
  std::map<std::string, std::string> named;

  std::string get(const std::string& name, const std::string& fallback) const {
    const auto it = named.find(name);
    return it == named.end() ? fallback : it->second;
  }
  long long integer(const std::string& name, long long fallback, long long lo, long long hi) const {
    const auto it = named.find(name);
    if (it == named.end()) return fallback;
    char* end = nullptr;
    const long long v = std::strtoll(it->second.c_str(), &end, 10);
    if (it->second.empty() || *end != '\0' || v < lo || v > hi) {
      throw InputError("--" + name + " must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                       "], got '" + it->second + "'");
    }
    return v;
  }
};

Args parse(int argc, char** argv, int first) {
  Args a;
  for (int i = first; i < argc; ++i) {
    const std::string s = argv[i];
    if (s.starts_with("--")) {
      if (i + 1 >= argc) throw InputError(s + " needs a value");
      a.named[s.substr(2)] = argv[++i];
    } else {
      a.positional.push_back(s);
    }
  }
  return a;
}

struct Source {
  MapDescriptor descriptor;
  Points2 points;
  Pose2 pose;
  double alignment_angle = 0;
};

// The dictionary name: as given, or the only one with descriptors.
std::string pick_dictionary(const io::MapDatabase& db, const std::string& name) {
  if (!name.empty()) return name;
  std::vector<std::string> names;
  for (const io::DescriptorSetInfo& s : db.descriptor_sets())
    if (std::find(names.begin(), names.end(), s.dictionary) == names.end()) names.push_back(s.dictionary);
  if (names.size() != 1) throw InputError(db.path().string() + ": choose the dictionary with --dict");
  return names.front();
}

// One synthetic descriptor from a real one (see the file comment).
MapDescriptor jitter(const MapDescriptor& real, const CodecConfig& codec, std::mt19937_64& rng, Vec2& shift) {
  std::uniform_int_distribution<int> lattice(-2, 2), edge(-1, 1);
  const Vec2 step = origin_step(codec);
  const Box2& e = codec.dictionary_extent;
  const int a = lattice(rng), b = lattice(rng);
  shift = Vec2(a * step.x(), b * step.y());
  auto inside = [&](const Vec2& s) {
    for (const Part& p : real.parts) {
      const double x = p.descriptor_box.x_min + s.x(), y = p.descriptor_box.y_min + s.y();
      if (x < e.x_min || x > e.x_max || y < e.y_min || y > e.y_max) return false;
    }
    return true;
  };
  for (int attempt = 0; attempt < 20 && !inside(shift); ++attempt) shift = Vec2(lattice(rng) * step.x(), lattice(rng) * step.y());
  if (!inside(shift)) shift = Vec2(0, 0);
  const double cell = codec.keypoint_resolution;
  const double half = codec.crop_size / 2;
  MapDescriptor out;
  for (const Part& p : real.parts) {
    Part q = p;
    Box2& k = q.keypoint_box;
    const double x0 = std::clamp(k.x_min + edge(rng) * cell, -half, half - cell);
    const double x1 = std::clamp(k.x_max + edge(rng) * cell, x0 + cell, half);
    const double y0 = std::clamp(k.y_min + edge(rng) * cell, -half, half - cell);
    const double y1 = std::clamp(k.y_max + edge(rng) * cell, y0 + cell, half);
    k = {x0, x1, y0, y1};
    q.descriptor_box = place_rotated_box(k, q.rotation, {p.descriptor_box.x_min + shift.x(), p.descriptor_box.y_min + shift.y()});
    out.parts.push_back(q);
  }
  return out;
}

int generate(const Args& args) {
  if (args.positional.size() != 1) throw InputError("generate: give one SOURCE database");
  const std::string out_path = args.get("out", "");
  if (out_path.empty()) throw InputError("generate: --out OUT.db is required");
  if (fs::exists(out_path)) throw InputError(out_path + ": exists; remove it first (generate writes a new database)");
  const long long n = args.integer("maps", 1000, 1, 100'000'000);
  const int k = static_cast<int>(args.integer("k", 3, 1, 16));
  const auto seed = static_cast<std::uint64_t>(args.integer("seed", 1, 0, 1LL << 62));
  const int points = static_cast<int>(args.integer("points", 8, 0, 100000));
  const long long batch = args.integer("batch", 100000, 1, 10'000'000);

  const auto t_source = Clock::now();
  const io::MapDatabase src = io::MapDatabase::open(args.positional[0], io::MapDatabase::Mode::kReadOnly);
  const std::string dictionary = pick_dictionary(src, args.get("dict", ""));
  const std::optional<CodecConfig> codec = src.descriptor_codec(dictionary, k);
  if (!codec) throw InputError(src.path().string() + ": no descriptors of dictionary '" + dictionary + "', K=" + std::to_string(k) + ": " + io::describe_hint(dictionary, k));
  std::vector<Source> pool;
  for (auto& [id, d] : io::load_descriptor_set(src, dictionary, k)) {
    const Submap m = src.load_submap(id);
    if (d.parts.empty() || (points > 0 && m.points.empty())) continue;
    pool.push_back({std::move(d), m.points, m.T_world_map, m.alignment_angle});
  }
  if (pool.empty()) throw InputError(src.path().string() + ": no usable descriptor to resample");
  std::printf("source: %zu real descriptors of dictionary '%s', K=%d, from %s (%.0f ms)\n", pool.size(),
              dictionary.c_str(), k, src.path().c_str(), ms_since(t_source));

  const auto t0 = Clock::now();
  io::MapDatabase db = io::MapDatabase::open(out_path, io::MapDatabase::Mode::kCreate);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
  double generate_ms = 0, submaps_ms = 0, descriptors_ms = 0;
  {
    io::MapDatabase::Transaction transaction(db);
    db.add_dictionary(src.load_dictionary(dictionary));
    io::DatasetSpec spec;
    spec.name = "synthetic";
    spec.source = "large_db generate " + src.path().string() + " --dict " + dictionary + " --k " + std::to_string(k) +
                  " --seed " + std::to_string(seed) + " --points " + std::to_string(points);
    const std::int64_t dataset = db.add_dataset(spec);
    for (long long first = 0; first < n; first += batch) {
      const long long count = std::min(batch, n - first);
      auto t = Clock::now();
      Submaps submaps(static_cast<std::size_t>(count));
      std::vector<PackedDescriptor> packed(static_cast<std::size_t>(count));
      for (long long j = 0; j < count; ++j) {
        const long long i = first + j;
        const Source& s = pool[pick(rng)];
        Vec2 shift;
        packed[j] = encode(jitter(s.descriptor, *codec, rng, shift), *codec);
        Submap& m = submaps[static_cast<std::size_t>(j)];
        m.anchor_scan = i;
        m.anchor_timestamp = 0.1 * static_cast<double>(i);
        m.travel = 0.5 * static_cast<double>(i);
        m.alignment_angle = s.alignment_angle;
        m.T_world_map = Pose2{s.pose.x + shift.x(), s.pose.y + shift.y(), s.pose.theta};
        std::uniform_int_distribution<std::size_t> point(0, s.points.size() - 1);
        for (int p = 0; p < points; ++p) m.points.push_back(s.points[point(rng)]);
        m.scan_timestamps = {m.anchor_timestamp};
      }
      generate_ms += ms_since(t);
      t = Clock::now();
      const std::vector<std::int64_t> ids = db.add_submaps(dataset, submaps);
      submaps_ms += ms_since(t);
      t = Clock::now();
      std::vector<io::DescriptorRecord> records(ids.size());
      for (std::size_t j = 0; j < ids.size(); ++j) records[j] = {ids[j], std::move(packed[j])};
      db.put_descriptors(dictionary, k, *codec, records);
      descriptors_ms += ms_since(t);
      std::fprintf(stderr, "\r%lld / %lld maps", first + count, n);
    }
    std::fprintf(stderr, "\n");
    const auto t = Clock::now();
    transaction.commit();
    submaps_ms += ms_since(t);  // the commit's write-out, counted with the submaps
  }
  const double total_ms = ms_since(t0);
  const auto bytes = static_cast<double>(fs::file_size(out_path));
  std::printf("wrote %lld maps (%d points each) and their K=%d descriptors to %s\n", n, points, k, out_path.c_str());
  std::printf("build %.1f s (synthesis %.1f s, submaps + commit %.1f s, descriptors %.1f s): %.0f maps/s\n",
              total_ms / 1e3, generate_ms / 1e3, submaps_ms / 1e3, descriptors_ms / 1e3,
              static_cast<double>(n) / (total_ms / 1e3));
  std::printf("file %.1f MB, %.1f bytes per map\n", bytes / 1e6, bytes / static_cast<double>(n));
  return 0;
}

struct Loaded {
  DescriptorDatabase database;
  std::vector<std::int64_t> map_ids;
};

Loaded load_via_set(const io::MapDatabase& db, const std::string& dictionary, int k, double& load_ms, double& build_ms) {
  auto t = Clock::now();
  std::map<std::int64_t, MapDescriptor> set = io::load_descriptor_set(db, dictionary, k);
  load_ms = ms_since(t);
  t = Clock::now();
  Loaded out;
  std::vector<MapDescriptor> maps;
  maps.reserve(set.size());
  for (auto& [id, d] : set) {
    out.map_ids.push_back(id);
    maps.push_back(std::move(d));
  }
  set.clear();
  DescriptorDatabaseConfig config;
  config.parts_per_map = k;
  out.database = DescriptorDatabase(maps, config);
  build_ms = ms_since(t);
  return out;
}

int query(const Args& args) {
  if (args.positional.size() != 1) throw InputError("query: give one database");
  const int k = static_cast<int>(args.integer("k", 3, 1, 16));
  const int repeat = static_cast<int>(args.integer("repeat", 20, 0, 1000));
  const int threads = static_cast<int>(args.integer("threads", 1, 1, 1024));
  const std::string load = args.get("load", "set");
  if (load != "set" && load != "stream") throw InputError("--load must be set or stream, got '" + load + "'");

  const auto t_start = Clock::now();
  auto t = Clock::now();
  const io::MapDatabase db = io::MapDatabase::open(args.positional[0], io::MapDatabase::Mode::kReadOnly);
  const std::string dictionary = pick_dictionary(db, args.get("dict", ""));
  const double open_ms = ms_since(t);
  double load_ms = 0, build_ms = 0;
  Loaded loaded;
  if (load == "set") {
    loaded = load_via_set(db, dictionary, k, load_ms, build_ms);
  } else {
    t = Clock::now();
    DescriptorDatabaseConfig config;
    config.parts_per_map = k;
    io::LoadedDescriptors l = io::load_descriptor_database(db, dictionary, k, config);
    loaded.database = std::move(l.database);
    loaded.map_ids = std::move(l.map_ids);
    load_ms = ms_since(t);
  }
  if (loaded.map_ids.empty()) throw InputError(db.path().string() + ": no descriptors of dictionary '" + dictionary + "', K=" + std::to_string(k));
  const std::int64_t query_id =
      args.integer("map", loaded.map_ids[loaded.map_ids.size() / 2], 1, std::numeric_limits<std::int64_t>::max());
  t = Clock::now();
  const std::optional<MapDescriptor> query = io::load_descriptor(db, dictionary, k, query_id);
  if (!query) throw InputError(db.path().string() + ": map " + std::to_string(query_id) + " has no descriptor of the set");
  const MapDescriptor query_form = select_top_parts(query->parts, k);
  const double query_ms = ms_since(t);

  const ScoreOptions options{threads, kDefaultOriginGate};
  // The 11 best (the query itself among them), without sorting 10 M scores; scores reuse one buffer (score_all's
  // overload), so warm runs time the matcher, not the page faults of a new result.
  std::vector<float> scores;
  std::vector<std::size_t> top;
  auto rank = [&] {
    loaded.database.score_all(query_form, Matcher::kSumMax, options, scores);
    auto better = [&](std::size_t a, std::size_t b) { return scores[a] > scores[b] || (scores[a] == scores[b] && a < b); };
    top.clear();
    for (std::size_t i = 0; i < scores.size(); ++i) {
      if (top.size() == 11 && !better(i, top.back())) continue;
      if (top.size() == 11) top.pop_back();
      top.insert(std::upper_bound(top.begin(), top.end(), i, better), i);
    }
  };
  t = Clock::now();
  rank();
  const double first_ms = ms_since(t);
  const double cold_ms = ms_since(t_start);
  std::vector<double> warm;
  for (int r = 0; r < repeat; ++r) {
    t = Clock::now();
    rank();
    warm.push_back(ms_since(t));
  }
  std::sort(warm.begin(), warm.end());
  std::printf("%s: %zu maps, dictionary '%s', K=%d, load %s; query map %lld, imm:%d (sum-max, gate %.0f m), %d thread(s)\n",
              db.path().c_str(), loaded.map_ids.size(), dictionary.c_str(), k, load.c_str(),
              static_cast<long long>(query_id), k, kDefaultOriginGate, threads);
  std::printf("open %.1f ms, load %.1f ms, build %.1f ms, query descriptor %.1f ms, rank %.1f ms: cold %.1f ms\n",
              open_ms, load_ms, build_ms, query_ms, first_ms, cold_ms);
  if (!warm.empty())
    std::printf("warm rank: median %.2f ms, min %.2f ms over %d runs (%.2f ns per map)\n", warm[warm.size() / 2],
                warm.front(), repeat, warm[warm.size() / 2] * 1e6 / static_cast<double>(loaded.map_ids.size()));
  std::printf("matcher memory %.1f MB\ntop:", static_cast<double>(loaded.database.memory_bytes()) / 1e6);
  for (std::size_t i : top) std::printf(" %lld:%.4f", static_cast<long long>(loaded.map_ids[i]), scores[i]);
  std::printf("\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string usage =
      "usage: large_db generate SOURCE.db --dict NAME --out OUT.db --maps N [--k 3] [--seed 1] [--points 8] "
      "[--batch 100000]\n"
      "       large_db query DB [--dict NAME] [--k 3] [--map ID] [--repeat 20] [--load set|stream] [--threads 1]\n";
  if (argc < 2) {
    std::fputs(usage.c_str(), stderr);
    return 2;
  }
  try {
    const std::string mode = argv[1];
    const Args args = parse(argc, argv, 2);
    if (mode == "generate") return generate(args);
    if (mode == "query") return query(args);
    std::fputs(usage.c_str(), stderr);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "large_db: error: %s\n", e.what());
    return 1;
  }
}
