// partslam describe DB --dict NAME: the offline half of PartSLAM (docs/DESIGN.md data flow, "CPD" and "MD"). Runs
// common pattern discovery of every stored submap (of one dataset, or all) against a stored dictionary, keeps
// up to P parts per map, and stores in one transaction the packed descriptor of the top K parts for each K of
// --k, plus the whole P-part list under K = P (with appearance scores when P > 16: the hMM query list). Each
// set's codec (core/parts/descriptor_layout.h) is stored with it, so `match` decodes without the dictionary.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <set>

#include "apps/commands.h"
#include "apps/cpd_options.h"
#include "apps/json_text.h"
#include "apps/mpi_split.h"
#include "core/evaluation/evaluation.h"
#include "io/atomic_file.h"
#include "io/descriptor_store.h"
#include "apps/progress_bar.h"
#include "core/parts/cpd.h"
#include "core/parts/descriptor_layout.h"
#include "core/error.h"
#include "io/map_database.h"

namespace partslam::apps {
namespace {

struct DescribeOptions {
  std::string db;
  std::string dictionary;
  std::string dataset;
  int parts = 100;
  std::vector<int> ks = {1, 2, 3, 4, 5};
  int threads = 1;
  bool verbose = false;
  bool quiet = false;
  std::string json;
  CpdConfig cpd;
};

struct MapParts {
  std::int64_t map_id = -1;
  const Submap* submap = nullptr;
  std::vector<Part> parts;
  double cpd_ms = 0;
};

std::vector<io::DatasetInfo> chosen_datasets(const io::MapDatabase& db, const std::string& name) {
  if (!name.empty()) {
    const std::optional<io::DatasetInfo> d = db.find_dataset(name);
    if (!d) throw InputError(db.path().string() + ": no dataset named '" + name + "'");
    return {*d};
  }
  std::vector<io::DatasetInfo> out;
  for (const io::DatasetInfo& d : db.datasets())
    if (d.spec.kind == io::DatasetKind::kSubmaps) out.push_back(d);
  return out;
}

void run_describe(DescribeOptions o) {
  if (o.parts < 1 || o.parts > 10000)
    throw InputError("--parts must be in [1, 10000], got " + std::to_string(o.parts));
  if (o.threads < 1 || o.threads > 1024) throw InputError("--threads must be in [1, 1024]");
  std::set<int> ks;
  for (int k : o.ks) {
    if (k < 1 || k > o.parts)
      throw InputError("--k: every K must be in [1, P = " + std::to_string(o.parts) + "], got " +
                       std::to_string(k));
    ks.insert(k);
  }
  ks.insert(o.parts);  // the hMM query list
  o.cpd.max_parts = o.parts;
  validate(o.cpd);
  if (!o.json.empty()) io::check_writable(o.json);

  using Clock = std::chrono::steady_clock;
  const bool reporting = is_reporting_process();  // rank 0 of mpirun (or the only process) stores and prints
  io::MapDatabase db =
      io::MapDatabase::open(o.db, reporting ? io::MapDatabase::Mode::kReadWrite : io::MapDatabase::Mode::kReadOnly);
  const io::Dictionary dictionary = db.load_dictionary(o.dictionary);
  const std::vector<io::DatasetInfo> datasets = chosen_datasets(db, o.dataset);
  std::vector<Submaps> loaded;
  std::vector<MapParts> maps;
  std::string names;
  for (const io::DatasetInfo& d : datasets) {
    loaded.push_back(db.load_submaps(d.id));
    names += (names.empty() ? "'" : ", '") + d.spec.name + "'";
  }
  for (const Submaps& s : loaded)
    for (const Submap& m : s) maps.push_back({m.id, &m, {}, 0});
  if (maps.empty())
    throw InputError(o.db + ": no submaps to describe (run 'partslam submaps LOG --db " + o.db + "')");
  if (reporting) std::cout << "describe " << maps.size() << " maps of " << names << " against dictionary '"
            << dictionary.name << "' (" << dictionary.points.size() << " points): P = " << o.parts
            << " parts, K =";
  for (int k : ks) if (reporting) std::cout << " " << k;
  if (reporting) std::cout << "\n";
  if (o.parts <= kMaxUnscoredParts && reporting) {
    std::cout << "note: P <= " << kMaxUnscoredParts << " stores no appearance score; hMM's Sum-Max-Weighted "
              << "then weighs every query part by 1\n";
  }

  // Offline: CPD of every map (Eq. 2 against the dictionary). Seeded by the map id, so results do not depend
  // on which maps are described together or on the thread count.
  const auto t0 = Clock::now();
  const PreparedDictionary prepared = prepare_dictionary(dictionary.points, o.cpd);
  ProgressBar bar(!o.quiet && is_reporting_process());
  std::vector<const Points2*> points;
  std::vector<std::uint64_t> keys;
  for (const MapParts& m : maps) points.push_back(&m.submap->points), keys.push_back(static_cast<std::uint64_t>(m.map_id));
  // Under mpirun, each rank describes its slice of the maps (apps/mpi_split.h); rank 0 stores and reports.
  std::vector<CpdResult> results =
      discover_parts_split(points, keys, prepared, o.cpd, o.threads,
                           [&bar](const std::string&, std::size_t d, std::size_t n) { bar("CPD", d, n); },
                           world_split());
  if (!reporting) return;
  for (std::size_t i = 0; i < maps.size(); ++i) maps[i].parts = std::move(results[i].parts), maps[i].cpd_ms = results[i].ms;
  const double cpd_s = std::chrono::duration<double>(Clock::now() - t0).count();

  // Encode every K and write them in one transaction.
  std::cout << std::fixed << std::setprecision(1);
  struct Set {
    int k;
    CodecConfig codec;
    std::vector<io::DescriptorRecord> records;
  };
  std::vector<Set> sets;
  for (int k : ks) {
    const CodecConfig codec = descriptor_codec_config(dictionary.points, k);
    std::vector<io::DescriptorRecord> records;
    for (const MapParts& m : maps) {
      try {
        records.push_back({m.map_id, encode(select_top_parts(m.parts, k), codec)});
      } catch (const InputError& e) {
        throw InputError("map " + std::to_string(m.map_id) + ", K=" + std::to_string(k) + ": " + e.what());
      }
    }
    sets.push_back({k, codec, std::move(records)});
  }
  {
    io::MapDatabase::Transaction transaction(db);
    for (const Set& set : sets) db.put_descriptors(dictionary.name, set.k, set.codec, set.records);
    transaction.commit();
  }

  if (o.verbose) {
    for (const MapParts& m : maps) {
      std::cout << "  map " << m.map_id << ": " << m.parts.size() << " parts, best AS "
                << std::setprecision(2) << (m.parts.empty() ? 0.0 : m.parts.front().appearance_score)
                << std::setprecision(1) << ", CPD " << m.cpd_ms << " ms\n";
    }
  }
  std::vector<double> cpd_ms;
  std::vector<std::size_t> counts;
  for (const MapParts& m : maps) cpd_ms.push_back(m.cpd_ms), counts.push_back(m.parts.size());
  double mean_parts = 0;
  for (std::size_t c : counts) mean_parts += static_cast<double>(c);
  mean_parts /= static_cast<double>(maps.size());
  double mean_ms = 0;
  for (double t : cpd_ms) mean_ms += t;
  mean_ms /= static_cast<double>(maps.size());
  std::cout << "CPD: " << mean_ms << " ms per map (min " << *std::min_element(cpd_ms.begin(), cpd_ms.end())
            << ", max " << *std::max_element(cpd_ms.begin(), cpd_ms.end()) << "), " << cpd_s << " s on "
            << o.threads << " thread" << (o.threads > 1 ? "s" : "") << "\n";
  std::cout << "parts per map: mean " << mean_parts << ", min "
            << *std::min_element(counts.begin(), counts.end()) << ", max "
            << *std::max_element(counts.begin(), counts.end()) << "\n";
  std::cout << std::setw(6) << "K" << std::setw(12) << "bits/part" << std::setw(12) << "mean parts"
            << std::setw(12) << "bits/map" << std::setw(10) << "min" << std::setw(10) << "max"
            << "\n";
  for (const auto& [k, codec, records] : sets) {
    double bits = 0;
    int lo = records.front().descriptor.bits, hi = lo;
    for (const io::DescriptorRecord& r : records) {
      bits += r.descriptor.bits;
      lo = std::min(lo, r.descriptor.bits), hi = std::max(hi, r.descriptor.bits);
    }
    const int per_part = bits_per_part(codec);
    std::cout << std::setw(6) << k << std::setw(12) << per_part << std::setw(12)
              << bits / per_part / records.size() << std::setw(12)
              << bits / static_cast<double>(records.size()) << std::setw(10) << lo << std::setw(10) << hi
              << (k == o.parts ? "  (hMM query list" : "")
              << (k == o.parts && k > kMaxUnscoredParts ? ", with AS)"
                  : k == o.parts                        ? ")"
                                                        : "")
              << "\n";
  }
  std::cout << "stored " << sets.size() * maps.size() << " descriptors in " << o.db << "\n";
  if (!o.json.empty()) {
    nlohmann::json j = {{"maps", maps.size()},
                        {"dictionary", dictionary.name},
                        {"parts", o.parts},
                        {"cpd_ms_per_map", mean_ms},
                        {"cpd_seconds", cpd_s},
                        {"threads", o.threads},
                        {"mean_parts", mean_parts},
                        {"db", o.db}};
    j["sets"] = nlohmann::json::array();
    for (const auto& [k, codec, records] : sets) {
      double bits = 0;
      for (const io::DescriptorRecord& r : records) bits += r.descriptor.bits;
      j["sets"].push_back({{"k", k}, {"bits_per_part", bits_per_part(codec)},
                           {"mean_bits", bits / static_cast<double>(records.size())}});
    }
    io::write_atomically(o.json, [&](std::ostream& out) { out << json_text(j); });
  }
}

}  // namespace

void register_describe(CLI::App& app) {
  auto o = std::make_shared<DescribeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "describe",
      "Find every stored map's parts against a dictionary (CPD) and store their packed descriptors");
  cmd->add_option("db", o->db, "map database file")->required();
  cmd->add_option("--dict", o->dictionary, "stored dictionary to describe against")->required();
  cmd->add_option("--parts", o->parts, "P: parts kept per map, stored as K = P (the hMM query list)")
      ->capture_default_str();
  cmd->add_option("--k", o->ks, "parts per stored descriptor, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--dataset", o->dataset, "describe only this dataset (default: every submaps dataset)");
  cmd->add_option("--threads", o->threads, "threads (results do not depend on it)")->capture_default_str();
  add_cpd_options(*cmd, o->cpd, "");
  cmd->add_flag("--verbose", o->verbose, "print one line per map");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  cmd->add_option("--json", o->json, "write the summary (CPD time, parts, bits per K) as JSON");
  cmd->callback([o] { run_describe(*o); });
}

}  // namespace partslam::apps
