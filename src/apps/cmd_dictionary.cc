// partslam dictionary LOG --db FILE --name NAME: builds a whole-building dictionary map from a corrected log
// (or "sim[:SEED]"), one point per 0.1 m cell, Manhattan-aligned (docs/DESIGN.md, "Dictionary map"), and stores it.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "core/maps/dictionary.h"
#include "io/map_database.h"
#include "io/scan_source.h"

namespace partslam::apps {
namespace {

struct DictionaryOptions {
  std::string log;
  std::string db;
  std::string name;
  DictionaryConfig config;
};

void run_dictionary(const DictionaryOptions& o) {
  const io::ScanSource source = io::load_scan_source(o.log);
  Dictionary d = build_dictionary(o.name.empty() ? source.name : o.name, source.scans, o.config);
  d.source = o.log;
  const Box2 box = bounding_box(d.points);
  auto db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kCreate);
  db.add_dictionary(d);
  std::cout << "dictionary '" << d.name << "': " << d.points.size() << " points, " << box.width() << " m x "
            << box.height() << " m, aligned by " << d.alignment_angle * 180 / std::numbers::pi << " deg; stored in "
            << o.db << "\n";
}

}  // namespace

void register_dictionary(CLI::App& app) {
  auto o = std::make_shared<DictionaryOptions>();
  CLI::App* cmd = app.add_subcommand("dictionary", "Build a whole-building dictionary map and store it");
  cmd->add_option("log", o->log, "corrected CARMEN log (plain or .gz), or sim[:SEED]")->required();
  cmd->add_option("--db", o->db, "map database file (created when missing)")->required();
  cmd->add_option("--name", o->name, "dictionary name (default: the log's file name)");
  cmd->add_option("--resolution", o->config.resolution, "downsampling cell [m]")->capture_default_str();
  cmd->add_option("--max-range", o->config.max_range, "usable range: farther beam endpoints are dropped [m]")
      ->capture_default_str();
  cmd->callback([o] { run_dictionary(*o); });
}

}  // namespace partslam::apps
