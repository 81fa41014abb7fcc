// partslam submaps LOG --db FILE: reads a CARMEN log (or "sim[:SEED]"), builds its submaps (docs/DESIGN.md,
// "Submap") and stores them as one dataset, atomically. Optionally checks the ground truth against a
// Freiburg .relations file (--relations, with --raw LOG when the submaps come from a re-timed corrected log).
#include <CLI/CLI.hpp>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "core/error.h"
#include "core/evaluation/relation_check.h"
#include "core/maps/submap.h"
#include "core/evaluation/tasks.h"
#include "io/map_database.h"
#include "io/relations.h"
#include "io/scan_source.h"

namespace partslam::apps {
namespace {

struct SubmapsOptions {
  std::string log;
  std::string db;
  std::string name;
  SubmapConfig config;
  bool no_align = false;
  std::string relations;
  std::string raw;
  TaskConfig tasks;
};

void run_submaps(SubmapsOptions o) {
  o.config.align = !o.no_align;
  validate(o.config);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  io::ScanSource source = io::load_scan_source(o.log);
  const auto t1 = Clock::now();
  const Submaps submaps = build_submaps(source.scans, o.config);
  const auto t2 = Clock::now();
  if (submaps.empty()) throw InputError(o.log + ": no submap could be built (too little travel or too few points)");

  io::DatasetSpec spec;
  spec.name = o.name.empty() ? source.name : o.name;
  spec.source = o.log;
  spec.config = o.config;
  auto db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kCreate);
  db.store_dataset(spec, submaps);

  double points = 0;
  for (const Submap& m : submaps) points += static_cast<double>(m.points.size());
  const double read_s = std::chrono::duration<double>(t1 - t0).count();
  const double build_s = std::chrono::duration<double>(t2 - t1).count();
  std::cout << std::fixed << std::setprecision(1) << spec.name << ": " << submaps.size() << " submaps, mean "
            << points / static_cast<double>(submaps.size()) << " points, from " << source.scans.size()
            << " scans, travel " << travel_distances(source.scans).back() << " m\n"
            << std::setprecision(0) << "read " << read_s * 1e3 << " ms, submaps " << build_s * 1e3 << " ms: "
            << static_cast<double>(source.scans.size()) / (read_s + build_s) << " scans/s\n"
            << "stored in " << o.db << "\n";

  if (!o.relations.empty()) {
    const Relations relations = io::read_relations(o.relations);
    const Scans raw = o.raw.empty() ? Scans{} : io::load_scan_source(o.raw).scans;
    const auto pairs = relevant_pairs(submaps, o.tasks);
    const RelationCheck check =
        check_relevant_pairs(submaps, pairs, source.scans, o.raw.empty() ? source.scans : raw, relations);
    std::cout << "relations: " << check.relevant_pairs << " relevant pairs (R " << o.tasks.radius << " m, G "
              << o.tasks.min_travel_gap << " m); " << check.with_relation << " linked by a relation, "
              << check.confirmed << " confirmed (" << check.associated_scans << " of " << source.scans.size()
              << " scans found in the raw log)\n";
  }
}

}  // namespace

void register_submaps(CLI::App& app) {
  auto o = std::make_shared<SubmapsOptions>();
  CLI::App* cmd = app.add_subcommand("submaps", "Build submaps from a laser log and store them in a map database");
  cmd->add_option("log", o->log, "CARMEN log (plain or .gz), or sim[:SEED] for the built-in simulator")->required();
  cmd->add_option("--db", o->db, "map database file (created when missing)")->required();
  cmd->add_option("--name", o->name, "dataset name (default: the log's file name)");
  cmd->add_option("--window", o->config.window_length, "travel covered by one submap [m]")->capture_default_str();
  cmd->add_option("--spacing", o->config.spacing, "travel between submaps [m]")->capture_default_str();
  cmd->add_option("--resolution", o->config.resolution, "downsampling cell [m]")->capture_default_str();
  cmd->add_option("--crop", o->config.crop_size, "side of the square crop [m]")->capture_default_str();
  cmd->add_option("--max-range", o->config.max_range, "usable range: farther beam endpoints are dropped [m]")
      ->capture_default_str();
  cmd->add_flag("--no-align", o->no_align, "keep the log's axes (no Manhattan alignment)");
  cmd->add_option("--relations", o->relations, "check relevant pairs against this .relations file");
  cmd->add_option("--raw", o->raw, "raw log the relations refer to (when LOG is a re-timed corrected log)");
  cmd->add_option("--radius", o->tasks.radius, "R for the relations check [m]")->capture_default_str();
  cmd->add_option("--gap", o->tasks.min_travel_gap, "G for the relations check [m]")->capture_default_str();
  cmd->callback([o] { run_submaps(*o); });
}

}  // namespace partslam::apps
