// partslam dictionary LOG|map.yaml --db FILE --name NAME: builds a whole-building dictionary map from a corrected
// log (or "sim[:SEED]") or from a ROS map_server map's occupied cells, one point per 0.1 m cell, Manhattan-aligned
// (docs/DESIGN.md, "Dictionary map"), and stores it.
#include <CLI/CLI.hpp>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "apps/log_inputs.h"
#include "apps/json_text.h"
#include "core/maps/dictionary.h"
#include "core/maps/grid_map.h"
#include "io/files/atomic_file.h"
#include "io/store/map_database.h"
#include "io/formats/map_server.h"
#include "io/logs/scan_source.h"
#include "apps/scan_input.h"

namespace partslam::apps {
namespace {

struct DictionaryOptions {
  std::string log;
  io::LogReadOptions read;
  std::string db;
  std::string name;
  DictionaryConfig config;
  std::string json;
};

void run_dictionary(const DictionaryOptions& o) {
  io::check_outputs({{"--db", o.db}, {"--json", o.json}}, {{"LOG", o.log}});
  Dictionary d;
  const std::filesystem::path path(o.log);
  // A .yaml that no log format reads as a bag (a rosbag2 folder's metadata.yaml is one) is a map_server map.
  if (path.extension() == ".yaml" && !io::scan_source_format(o.log).bag) {
    d = build_dictionary(o.name.empty() ? path.stem().string() : o.name, occupied_points(io::read_map_yaml(path)),
                         o.config);
  } else {
    const io::ScanSource source = load_scans(o.log, o.read);
    d = build_dictionary(o.name.empty() ? source.name : o.name, source.scans, o.config);
  }
  d.source = o.log;
  const Box2 box = bounding_box(d.points);
  auto db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kCreate);
  db.add_dictionary(d);
  std::cout << "dictionary '" << d.name << "': " << d.points.size() << " points, " << box.width() << " m x "
            << box.height() << " m, aligned by " << d.alignment_angle * kDegreesPerRadian << " deg; stored in "
            << o.db << "\n";
  if (!o.json.empty()) {
    const nlohmann::json j = {{"dictionary", d.name}, {"source", d.source}, {"points", d.points.size()},
                              {"width", box.width()}, {"height", box.height()},
                              {"alignment_angle", d.alignment_angle}, {"db", o.db}};
    io::write_atomically(o.json, [&](std::ostream& out) { out << json_text(j); });
  }
}

}  // namespace

void register_dictionary(CLI::App& app) {
  auto o = std::make_shared<DictionaryOptions>();
  CLI::App* cmd = app.add_subcommand("dictionary", "Build a whole-building dictionary map and store it");
  cmd->add_option("log", o->log, "a log with good poses (corrected): " + kLogInputs + "; or a map_server map.yaml")
      ->required();
  add_log_read_options(*cmd, o->read);
  cmd->add_option("--db", o->db, "map database file (created when missing)")->required();
  cmd->add_option("--name", o->name, "dictionary name (default: the log's file name)");
  cmd->add_option("--resolution", o->config.resolution, "downsampling cell [m]")->capture_default_str();
  cmd->add_option("--max-range", o->config.max_range, "usable range: farther beam endpoints are dropped [m]")
      ->capture_default_str();
  cmd->add_option("--json", o->json, "write what was stored (points, extent, alignment) as JSON");
  cmd->callback([o] { run_dictionary(*o); });
}

}  // namespace partslam::apps
