// partslam info FILE: what a map database holds — datasets with their submap counts, dictionaries and
// descriptor sets — as text or, with --json, as one JSON object.
// Tested by: apps/cli_test.cc
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/json_text.h"
#include "io/store/map_database.h"

namespace partslam::apps {
namespace {

struct InfoOptions {
  std::string file;
  bool json = false;
  bool check = false;
  bool upgrade = false;
};

std::string map_id_range(const io::DatasetInfo& d) {
  if (d.submap_count == 0) return "no map ids";
  const bool contiguous = d.last_map_id - d.first_map_id + 1 == d.submap_count;
  return std::string(contiguous ? "map ids " : "map ids within ") + std::to_string(d.first_map_id) + ".." +
         std::to_string(d.last_map_id);
}

nlohmann::json to_json(const io::DatabaseSummary& s, const std::string& file) {
  nlohmann::json j = {{"file", file},
                      {"schema_version", s.schema_version},
                      {"counts_kept", s.counts_kept},
                      {"submaps", s.submap_count},
                      {"points", s.point_count}};
  j["datasets"] = nlohmann::json::array();
  for (const io::DatasetInfo& d : s.datasets) {
    j["datasets"].push_back({{"id", d.id},
                             {"name", d.spec.name},
                             {"source", d.spec.source},
                             {"kind", io::to_string(d.spec.kind)},
                             {"scan_matched", d.spec.scan_matched},
                             {"created", d.created},
                             {"submaps", d.submap_count},
                             {"mean_points", d.mean_points},
                             {"first_map_id", d.first_map_id},
                             {"last_map_id", d.last_map_id}});
  }
  j["dictionaries"] = nlohmann::json::array();
  for (const io::DictionaryInfo& d : s.dictionaries) {
    j["dictionaries"].push_back({{"name", d.name},
                                 {"source", d.source},
                                 {"resolution", d.resolution},
                                 {"points", d.point_count},
                                 {"created", d.created}});
  }
  j["descriptor_sets"] = nlohmann::json::array();
  for (const io::DescriptorSetInfo& d : s.descriptor_sets) {
    j["descriptor_sets"].push_back(
        {{"dictionary", d.dictionary}, {"k", d.k}, {"maps", d.count}, {"mean_bits", d.mean_bits}});
  }
  return j;
}

void print_text(const io::DatabaseSummary& s, const std::string& file, std::ostream& out) {
  const auto bytes = static_cast<double>(std::filesystem::file_size(file));
  out << std::fixed << std::setprecision(1);
  out << file << ": PartSLAM map database, schema version " << s.schema_version << ", ";
  if (bytes < 1e6) {
    out << bytes / 1e3 << " kB\n";
  } else {
    out << bytes / 1e6 << " MB\n";
  }
  out << "datasets: " << s.datasets.size() << "\n";
  for (const io::DatasetInfo& d : s.datasets) {
    out << "  " << d.spec.name << ": " << d.submap_count << " submaps, mean " << d.mean_points << " points, "
        << map_id_range(d) << " (" << io::to_string(d.spec.kind) << ", from " << d.spec.source
        << (d.spec.scan_matched ? " scan-matched" : "") << ", "
        << d.created << ")\n";
  }
  out << "total: " << s.submap_count << " submaps, " << s.point_count << " points\n";
  out << "dictionaries: " << s.dictionaries.size() << "\n";
  for (const io::DictionaryInfo& d : s.dictionaries) {
    out << "  " << d.name << ": " << d.point_count << " points at " << std::setprecision(2) << d.resolution
        << std::setprecision(1) << " m (from " << d.source << ", " << d.created << ")\n";
  }
  out << "descriptor sets: " << s.descriptor_sets.size() << "\n";
  for (const io::DescriptorSetInfo& d : s.descriptor_sets) {
    out << "  dictionary " << d.dictionary << ", K=" << d.k << ": " << d.count << " maps, mean "
        << d.mean_bits << " bits\n";
  }
}

void run_info(const InfoOptions& options, std::ostream& out) {
  // --upgrade opens for writing, which migrates an older file to the current schema (io/store/map_database.h).
  const io::MapDatabase db = io::MapDatabase::open(
      options.file, options.upgrade ? io::MapDatabase::Mode::kReadWrite : io::MapDatabase::Mode::kReadOnly);
  if (options.check) db.check_integrity();
  const io::DatabaseSummary summary = db.summary();
  if (options.json) {
    out << json_text(to_json(summary, options.file));
  } else {
    print_text(summary, options.file, out);
    if (!summary.counts_kept) {
      out << "note: schema version " << summary.schema_version << " keeps no counts, so they were computed by "
          << "reading every row (slow on a large file); 'partslam info " << options.file
          << " --upgrade' (or any write) migrates it to version " << io::kMapDatabaseSchemaVersion
          << ", which keeps them\n";
    }
    if (options.check) out << "integrity: ok\n";
  }
}

}  // namespace

void register_info(CLI::App& app) {
  auto options = std::make_shared<InfoOptions>();
  CLI::App* cmd =
      app.add_subcommand("info", "Summarise a map database: datasets, submaps, dictionaries, descriptors");
  cmd->add_option("file", options->file, "map database file")->required();
  cmd->add_flag("--json", options->json, "print the summary as JSON");
  cmd->add_flag("--check", options->check, "also verify the whole file (SQLite quick_check)");
  cmd->add_flag("--upgrade", options->upgrade,
                "migrate an older file to the current schema version (which keeps counts, so info is fast)");
  cmd->callback([options] { run_info(*options, std::cout); });
}

}  // namespace partslam::apps
