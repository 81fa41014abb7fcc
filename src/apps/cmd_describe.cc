// partslam describe DB --dict NAME: the offline half of PartSLAM (docs/DESIGN.md data flow, "CPD" and "MD"). Runs
// common pattern discovery of every stored submap (of one dataset, or all) against a stored dictionary, keeps
// up to P parts per map, and stores in one transaction the packed descriptor of the top K parts for each K of
// --k, plus the whole P-part list under K = P (with appearance scores when P > 16: the hMM query list). Each
// set's codec (core/parts/descriptor_layout.h) is stored with it, so `match` decodes without the dictionary.
// Tested by: apps/cli_parts_test.cc
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <numeric>
#include <set>

#include "apps/commands.h"
#include "apps/cpd_options.h"
#include "apps/json_text.h"
#include "apps/mpi_split.h"
#include "core/evaluation/evaluation.h"
#include "io/files/atomic_file.h"
#include "io/store/descriptor_store.h"
#include "apps/progress_bar.h"
#include "core/parts/cpd.h"
#include "core/parts/descriptor_layout.h"
#include "core/error.h"
#include "io/store/map_database.h"

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

// Every K to store, increasing: those of --k and P itself (the hMM query list).
std::vector<int> checked_ks(DescribeOptions& o) {
  if (o.parts < 1 || o.parts > 10000)
    throw InputError("--parts must be in [1, 10000], got " + std::to_string(o.parts));
  if (o.threads < 1 || o.threads > 1024) throw InputError("--threads must be in [1, 1024]");
  std::set<int> ks;
  for (int k : o.ks) {
    if (k < 1 || k > o.parts)
      throw InputError("--k: every K must be in [1, P = " + std::to_string(o.parts) + "], got " + std::to_string(k));
    ks.insert(k);
  }
  ks.insert(o.parts);
  o.cpd.max_parts = o.parts;
  validate(o.cpd);
  io::check_outputs({{"--json", o.json}}, {{"DB", o.db}});
  return {ks.begin(), ks.end()};
}

// The maps to describe: every submap of the chosen datasets.
struct Described {
  std::vector<Submaps> loaded;
  std::vector<std::int64_t> ids;
  std::vector<const Points2*> points;
  std::string names;  ///< the datasets, quoted
  std::vector<CpdResult> cpd;
  double cpd_s = 0;
};

void load_maps(const io::MapDatabase& db, const DescribeOptions& o, Described& d) {
  for (const io::DatasetInfo& info : chosen_datasets(db, o.dataset)) {
    d.loaded.push_back(db.load_submaps(info.id));
    d.names += (d.names.empty() ? "'" : ", '") + info.spec.name + "'";
  }
  for (const Submaps& s : d.loaded)
    for (const Submap& m : s) d.ids.push_back(m.id), d.points.push_back(&m.points);
  if (d.ids.empty()) throw InputError(o.db + ": no submaps to describe (run 'partslam submaps LOG --db " + o.db + "')");
}

// CPD of every map (Eq. 2 against the dictionary). Seeded by the map id, so results do not depend on which maps
// are described together, on the threads or, under mpirun (each rank its slice), on the ranks.
void discover(const io::Dictionary& dictionary, const DescribeOptions& o, Described& d) {
  const auto t0 = std::chrono::steady_clock::now();
  const PreparedDictionary prepared = prepare_dictionary(dictionary.points, o.cpd);
  ProgressBar bar(!o.quiet && is_reporting_process());
  std::vector<std::uint64_t> keys(d.ids.begin(), d.ids.end());
  d.cpd = discover_parts_split(d.points, keys, prepared, o.cpd, o.threads,
                               [&bar](const std::string&, std::size_t done, std::size_t n) { bar("CPD", done, n); },
                               world_split());
  d.cpd_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void print_summary(const DescribeOptions& o, const Described& d, const std::vector<io::EncodedSet>& sets) {
  std::vector<double> ms;
  std::vector<std::size_t> counts;
  for (const CpdResult& r : d.cpd) ms.push_back(r.ms), counts.push_back(r.parts.size());
  const auto mean = [](const auto& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  };
  if (o.verbose)
    for (std::size_t i = 0; i < d.ids.size(); ++i)
      std::cout << "  map " << d.ids[i] << ": " << d.cpd[i].parts.size() << " parts, best AS " << std::setprecision(2)
                << (d.cpd[i].parts.empty() ? 0.0 : d.cpd[i].parts.front().appearance_score) << std::setprecision(1)
                << ", CPD " << d.cpd[i].ms << " ms\n";
  std::cout << "CPD: " << mean(ms) << " ms per map (min " << *std::min_element(ms.begin(), ms.end()) << ", max "
            << *std::max_element(ms.begin(), ms.end()) << "), " << d.cpd_s << " s on " << o.threads << " thread"
            << (o.threads > 1 ? "s" : "") << "\n";
  std::cout << "parts per map: mean " << mean(counts) << ", min " << *std::min_element(counts.begin(), counts.end())
            << ", max " << *std::max_element(counts.begin(), counts.end()) << "\n";
  std::cout << std::setw(6) << "K" << std::setw(12) << "bits/part" << std::setw(12) << "mean parts" << std::setw(12)
            << "bits/map" << std::setw(10) << "min" << std::setw(10) << "max" << "\n";
  for (const io::EncodedSet& set : sets) {
    const int per_part = bits_per_part(set.codec);
    const bool list = set.k == o.parts;
    std::cout << std::setw(6) << set.k << std::setw(12) << per_part << std::setw(12) << set.mean_bits / per_part
              << std::setw(12) << set.mean_bits << std::setw(10) << set.min_bits << std::setw(10) << set.max_bits
              << (!list ? "" : set.k > kMaxUnscoredParts ? "  (hMM query list, with AS)" : "  (hMM query list)") << "\n";
  }
  std::cout << "stored " << sets.size() * d.ids.size() << " descriptors in " << o.db << "\n";
}

nlohmann::json summary_json(const DescribeOptions& o, const Described& d, const std::string& dictionary,
                            const std::vector<io::EncodedSet>& sets) {
  double ms = 0, parts = 0;
  for (const CpdResult& r : d.cpd) ms += r.ms, parts += static_cast<double>(r.parts.size());
  const double n = static_cast<double>(d.ids.size());
  nlohmann::json j = {{"maps", d.ids.size()},  {"dictionary", dictionary}, {"parts", o.parts},
                      {"cpd_ms_per_map", ms / n}, {"cpd_seconds", d.cpd_s}, {"threads", o.threads},
                      {"mean_parts", parts / n}, {"db", o.db}};
  j["sets"] = nlohmann::json::array();
  for (const io::EncodedSet& set : sets)
    j["sets"].push_back({{"k", set.k}, {"bits_per_part", bits_per_part(set.codec)}, {"mean_bits", set.mean_bits}});
  return j;
}

void run_describe(DescribeOptions o) {
  const std::vector<int> ks = checked_ks(o);
  const bool reporting = is_reporting_process();  // rank 0 of mpirun (or the only process) stores and prints
  io::MapDatabase db =
      io::MapDatabase::open(o.db, reporting ? io::MapDatabase::Mode::kReadWrite : io::MapDatabase::Mode::kReadOnly);
  const io::Dictionary dictionary = db.load_dictionary(o.dictionary);
  Described d;
  load_maps(db, o, d);
  if (reporting) {
    std::cout << "describe " << d.ids.size() << " maps of " << d.names << " against dictionary '" << dictionary.name
              << "' (" << dictionary.points.size() << " points): P = " << o.parts << " parts, K =";
    for (int k : ks) std::cout << " " << k;
    std::cout << "\n";
    if (o.parts <= kMaxUnscoredParts)
      std::cout << "note: P <= " << kMaxUnscoredParts << " stores no appearance score; hMM's Sum-Max-Weighted "
                << "then weighs every query part by 1\n";
  }
  discover(dictionary, o, d);
  if (!reporting) return;
  std::vector<std::vector<Part>> parts;
  for (CpdResult& r : d.cpd) parts.push_back(r.parts);
  const std::vector<io::EncodedSet> sets = io::encode_descriptor_sets(dictionary.points, ks, d.ids, parts);
  io::store_descriptor_sets(db, dictionary.name, sets);
  std::cout << std::fixed << std::setprecision(1);
  print_summary(o, d, sets);
  if (!o.json.empty())
    io::write_atomically(o.json, [&](std::ostream& out) { out << json_text(summary_json(o, d, dictionary.name, sets)); });
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
