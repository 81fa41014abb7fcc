// partslam submaps LOG --db FILE: reads a CARMEN log (or "sim[:SEED]"), builds its submaps (docs/DESIGN.md,
// "Submap") and stores them as one dataset, atomically. With --scan-match the scan poses come from the front
// end (core/slam/front_end.h) instead of the log: for raw logs, whose poses are drifting odometry. Optionally
// checks the ground truth against a Freiburg .relations file (--relations, with --raw LOG when the submaps come
// from a re-timed corrected log); every input is read before anything is stored.
// Tested by: apps/cli_eval_test.cc, apps/cli_locate_test.cc
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "apps/log_inputs.h"
#include "core/error.h"
#include "core/evaluation/relation_check.h"
#include "core/maps/submap.h"
#include "core/evaluation/tasks.h"
#include "io/store/map_database.h"
#include "io/logs/relations.h"
#include "io/logs/scan_source.h"
#include "apps/scan_input.h"
#include "apps/progress_bar.h"
#include "apps/json_text.h"
#include "io/files/atomic_file.h"
#include "core/slam/front_end.h"

namespace partslam::apps {
namespace {

struct SubmapsOptions {
  std::string log;
  io::LogReadOptions read;  ///< LOG and --raw
  std::string db;
  std::string name;
  SubmapConfig config;
  bool no_align = false;
  std::string relations;
  std::string raw;
  TaskConfig tasks;
  bool scan_match = false;
  FrontEndConfig front_end;
  bool quiet = false;
  std::string json;
};

// Replaces the scans' poses by the front end's and prints what it did.
void scan_match(io::ScanSource& source, const SubmapsOptions& o, nlohmann::json& report) {
  FrontEndResult fe;
  {
    ProgressBar bar(!o.quiet);
    fe = scan_match_log(source.scans, o.front_end,
                        [&bar](const std::string& s, std::size_t d, std::size_t n) { bar(s, d, n); });
  }
  const FrontEndStats& st = fe.stats;
  std::cout << std::fixed << std::setprecision(1) << "scan matching: " << st.scans << " scans in " << st.seconds
            << " s (" << std::setprecision(0) << st.log_seconds / std::max(st.seconds, 1e-9) << "x the log's "
            << st.log_seconds << " s), mean score " << std::setprecision(3) << st.mean_score << ", "
            << st.rejected << " matches rejected (odometry kept)\n";
  if (st.time_reversals > 0)
    std::cerr << "partslam: warning: " << o.log << ": " << st.time_reversals
              << " scans dropped because their timestamp goes backwards\n";
  if (!st.odometry_moves)
    std::cerr << "partslam: warning: " << o.log << ": the odometry never moves (no odometry in the log?): the "
              << "front end predicts a standing robot, so fast motion may break it\n";
  if (st.mirrored) std::cerr << "partslam: warning: " << o.log << ": " << mirrored_description(st) << "\n";
  if (st.rejected * 10 > st.scans)
    std::cerr << "partslam: warning: " << o.log << ": " << st.rejected << " of " << st.scans
              << " scans matched nowhere (score < " << o.front_end.min_score << "): their poses are odometry\n";
  report["scan_matching"] = {{"scans", st.scans}, {"seconds", st.seconds}, {"log_seconds", st.log_seconds},
                             {"mean_score", st.mean_score}, {"rejected", st.rejected},
                             {"time_reversals", st.time_reversals}, {"mirrored", st.mirrored}};
  source.scans = std::move(fe.scans);
}

// --relations: the relevant pairs of the stored submaps checked against the relations (printed; for the report).
nlohmann::json check_relations(const SubmapsOptions& o, const Submaps& submaps, const Scans& scans, const Scans& raw,
                               const Relations& relations) {
  const auto pairs = relevant_pairs(submaps, o.tasks);
  const RelationCheck check = check_relevant_pairs(submaps, pairs, scans, o.raw.empty() ? scans : raw, relations);
  std::cout << "relations: " << check.relevant_pairs << " relevant pairs (R " << o.tasks.radius << " m, G "
            << o.tasks.min_travel_gap << " m); " << check.with_relation << " linked by a relation, "
            << check.confirmed << " confirmed";
  if (o.raw.empty())
    std::cout << " (no --raw: the relations' scans looked up in the log itself)\n";
  else
    std::cout << " (" << check.associated_scans << " of " << scans.size() << " scans found in the raw log)\n";
  if (check.relevant_pairs > 0 && check.with_relation == 0)
    std::cerr << "partslam: warning: " << o.relations
              << ": no relevant pair is linked by a relation (are they " << o.log << "'s relations?)\n";
  return {{"relevant_pairs", check.relevant_pairs}, {"with_relation", check.with_relation},
          {"confirmed", check.confirmed}, {"associated_scans", check.associated_scans},
          {"radius", o.tasks.radius}, {"gap", o.tasks.min_travel_gap}};
}

void run_submaps(SubmapsOptions o) {
  o.config.align = !o.no_align;
  validate(o.config);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  validate(o.front_end);
  if (!o.relations.empty()) validate(o.tasks);  // before anything is stored
  io::check_outputs({{"--db", o.db}, {"--json", o.json}},
                    {{"LOG", o.log}, {"--relations", o.relations}, {"--raw", o.raw}});
  nlohmann::json report;
  io::ScanSource source = load_scans(o.log, o.read);
  const double read_s = std::chrono::duration<double>(Clock::now() - t0).count();
  // Everything else that is read, before anything is stored.
  const Relations relations = o.relations.empty() ? Relations{} : io::read_relations(o.relations);
  const Scans raw = o.raw.empty() ? Scans{} : load_scans(o.raw, o.read).scans;
  if (o.scan_match) scan_match(source, o, report);
  const auto t1 = Clock::now();
  const Submaps submaps = build_submaps(source.scans, o.config);
  const auto t2 = Clock::now();
  if (submaps.empty()) throw InputError(o.log + ": no submap could be built (too little travel or too few points)");

  io::DatasetSpec spec;
  spec.name = o.name.empty() ? source.name : o.name;
  spec.source = o.log;
  spec.config = o.config;
  spec.scan_matched = o.scan_match;
  spec.front_end = o.front_end;
  auto db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kCreate);
  db.store_dataset(spec, submaps);

  double points = 0;
  for (const Submap& m : submaps) points += static_cast<double>(m.points.size());
  const double build_s = std::chrono::duration<double>(t2 - t1).count();
  std::cout << std::fixed << std::setprecision(1) << spec.name << ": " << submaps.size() << " submaps, mean "
            << points / static_cast<double>(submaps.size()) << " points, from " << source.scans.size()
            << " scans, travel " << travel_distances(source.scans).back() << " m\n"
            << std::setprecision(0) << "read " << read_s * 1e3 << " ms, submaps " << build_s * 1e3 << " ms: "
            << static_cast<double>(source.scans.size()) / (read_s + build_s) << " scans/s\n"
            << "stored in " << o.db << "\n";

  if (!o.relations.empty()) report["relations"] = check_relations(o, submaps, source.scans, raw, relations);
  if (!o.json.empty()) {
    report["dataset"] = spec.name;
    report["source"] = o.log;
    report["warnings"] = source.warnings;  // the reader's: a recording cut short, damage skipped
    report["submaps"] = submaps.size();
    report["mean_points"] = points / static_cast<double>(submaps.size());
    report["scans"] = source.scans.size();
    report["travel"] = travel_distances(source.scans).back();
    report["read_ms"] = read_s * 1e3;
    report["submaps_ms"] = build_s * 1e3;
    report["db"] = o.db;
    io::write_atomically(o.json, [&](std::ostream& out) { out << json_text(report); });
  }
}

}  // namespace

void register_submaps(CLI::App& app) {
  auto o = std::make_shared<SubmapsOptions>();
  CLI::App* cmd = app.add_subcommand("submaps", "Build submaps from a laser log and store them in a map database");
  cmd->add_option("log", o->log, "the log: " + kLogInputs + " (sim: the built-in simulator)")->required();
  add_log_read_options(*cmd, o->read);
  cmd->add_option("--db", o->db, "map database file (created when missing)")->required();
  cmd->add_option("--name", o->name, "dataset name (default: the log's file name)");
  cmd->add_option("--window", o->config.window_length, "travel covered by one submap [m]")->capture_default_str();
  cmd->add_option("--spacing", o->config.spacing, "travel between submaps [m]")->capture_default_str();
  cmd->add_option("--resolution", o->config.resolution, "downsampling cell [m]")->capture_default_str();
  cmd->add_option("--crop", o->config.crop_size, "side of the square crop [m]")->capture_default_str();
  cmd->add_option("--max-range", o->config.max_range, "usable range: farther beam endpoints are dropped [m]")
      ->capture_default_str();
  cmd->add_flag("--no-align", o->no_align, "keep the log's axes (no Manhattan alignment)");
  cmd->add_flag("--scan-match", o->scan_match,
                "poses from scan matching seeded by odometry (raw logs), not from the log");
  cmd->add_option("--scan-match-window", o->front_end.matcher.linear_window,
                  "scan matching: search half-width [m]")->capture_default_str();
  cmd->add_option("--scan-match-turn", o->front_end.matcher.angular_window,
                  "scan matching: search half-width in rotation [rad]")->capture_default_str();
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  cmd->add_option("--json", o->json, "write what was built (counts, travel, times, relations check) as JSON");
  cmd->add_option("--relations", o->relations, "check relevant pairs against this .relations file");
  cmd->add_option("--raw", o->raw, "raw log the relations refer to (when LOG is a re-timed corrected log)");
  cmd->add_option("--radius", o->tasks.radius, "R for the relations check [m]")->capture_default_str();
  cmd->add_option("--gap", o->tasks.min_travel_gap, "G for the relations check [m]")->capture_default_str();
  cmd->callback([o] { run_submaps(*o); });
}

}  // namespace partslam::apps
