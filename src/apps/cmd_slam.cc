// partslam slam RAW_LOG --out DIR: the whole chain for a raw log (core/slam/slam.h): front end, submaps, loop
// closures (succinct shortlist, dMM and context verification, drift gate), a pose graph with a robust loss,
// corrected scan poses. Writes DIR/corrected.log (CARMEN, corrected poses), DIR/map.png (the corrected map),
// DIR/loops.json and, with --relations, DIR/relations_error.json (the Kuemmerle et al. 2009 metric). Every
// file is written atomically; DIR is created when missing.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/json_text.h"
#include "apps/progress_bar.h"
#include "core/error.h"
#include "core/evaluation/trajectory_check.h"
#include "core/slam/slam.h"
#include "io/atomic_file.h"
#include "io/carmen_log.h"
#include "io/relations.h"
#include "io/scan_source.h"
#include "plot/render.h"

namespace partslam::apps {
namespace {

struct SlamOptions {
  std::string log;
  std::string out;
  std::string relations;
  SlamConfig config;
  bool quiet = false;
};

nlohmann::json relations_json(const RelationsError& e) {
  return {{"translation", {{"mean", e.translation_mean}, {"std", e.translation_std}}},
          {"rotation", {{"mean", e.rotation_mean}, {"std", e.rotation_std}}},
          {"relations", e.relations},
          {"missing", e.missing}};
}

void write_map_png(const std::filesystem::path& path, const Scans& scans, const std::string& title) {
  Points2 all;
  for (const Scan& s : scans) {
    const Points2 p = points_world(s, kDefaultMaxRange);
    all.insert(all.end(), p.begin(), p.end());
  }
  plot::PartsFigure figure;
  figure.map_title = title;
  figure.map_points = voxel_downsample(all, 0.05);
  plot::write_parts_figure(path, figure);
}

void run_slam_command(const SlamOptions& o) {
  namespace fs = std::filesystem;
  const fs::path dir(o.out);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw InputError(o.out + ": cannot create the output folder");
  for (const char* name : {"corrected.log", "map.png", "loops.json", "relations_error.json"})
    io::check_writable(dir / name);
  const Relations relations = o.relations.empty() ? Relations{} : io::read_relations(o.relations);
  const io::ScanSource source = io::load_scan_source(o.log);

  SlamResult r;
  {
    ProgressBar bar(!o.quiet);
    r = run_slam(source.scans, o.config, [&bar](const std::string& s, std::size_t d, std::size_t n) { bar(s, d, n); });
  }
  const FrontEndStats& fe = r.front_end;
  std::cout << std::fixed << std::setprecision(1) << source.name << ": " << fe.scans << " scans, front end "
            << r.front_end_s << " s (" << std::setprecision(0) << fe.log_seconds / std::max(r.front_end_s, 1e-9)
            << "x the log's " << fe.log_seconds << " s), " << fe.rejected << " matches rejected\n"
            << std::setprecision(1) << r.submaps.size() << " submaps; " << r.closures.size()
            << " loop-closure hypotheses, " << r.accepted << " accepted (confidence >= " << std::setprecision(2)
            << o.config.min_confidence << std::setprecision(1) << "), " << r.loops_s << " s\n"
            << "pose graph: cost " << std::setprecision(3) << r.graph.initial_cost << " -> " << r.graph.final_cost
            << " in " << r.graph.iterations << " iterations, " << std::setprecision(1) << r.graph_s << " s\n";
  if (fe.time_reversals > 0)
    std::cerr << "partslam: warning: " << o.log << ": " << fe.time_reversals << " scans dropped (time goes backwards)\n";
  if (!fe.odometry_moves)
    std::cerr << "partslam: warning: " << o.log << ": the odometry never moves (no odometry in the log?)\n";

  io::write_carmen_log(dir / "corrected.log", r.scans, "partslam slam " + o.log + ": corrected poses");
  write_map_png(dir / "map.png", r.scans, source.name + ": corrected map (" + std::to_string(r.accepted) + " loop closures)");
  nlohmann::json loops = nlohmann::json::array();
  for (const LoopClosure& l : r.closures) {
    if (l.confidence < o.config.min_confidence) continue;
    loops.push_back({{"query", l.query}, {"match", l.match}, {"score", l.score}, {"confidence", l.confidence},
                     {"pose", {{"x", l.T_match_query.x}, {"y", l.T_match_query.y}, {"theta", l.T_match_query.theta}}}});
  }
  io::write_atomically(dir / "loops.json", [&](std::ostream& out) {
    out << json_text({{"log", o.log}, {"submaps", r.submaps.size()}, {"accepted", loops}});
  });
  std::cout << "wrote " << (dir / "corrected.log").string() << ", map.png, loops.json";
  if (!o.relations.empty()) {
    const RelationsError before = relations_error(source.scans, relations);
    const RelationsError after = relations_error(r.scans, relations);
    io::write_atomically(dir / "relations_error.json",
                         [&](std::ostream& out) { out << json_text(relations_json(after)); });
    std::cout << ", relations_error.json\n"
              << std::setprecision(3) << "relations (" << after.relations << " of " << relations.size()
              << "): translation " << after.translation_mean << " +- " << after.translation_std << " m, rotation "
              << after.rotation_mean << " +- " << after.rotation_std << " rad (odometry: " << before.translation_mean
              << " +- " << before.translation_std << " m, " << before.rotation_mean << " +- " << before.rotation_std
              << " rad)";
  }
  std::cout << "\n";
  if (!o.relations.empty() && relations_error(r.scans, relations).relations == 0)
    std::cerr << "partslam: warning: " << o.relations << ": no relation names a scan of " << o.log
              << " (its timestamps are not the log's: a re-timed bag, or another run?)\n";
}

}  // namespace

void register_slam(CLI::App& app) {
  auto o = std::make_shared<SlamOptions>();
  CLI::App* cmd = app.add_subcommand("slam", "Raw log -> front end, loop closures, pose graph -> corrected log and map");
  cmd->add_option("log", o->log, "raw CARMEN log (odometry in the pose fields), or sim[:SEED]")->required();
  cmd->add_option("--out", o->out, "output folder (created when missing)")->required();
  cmd->add_option("--relations", o->relations, "Freiburg .relations file: report the relation errors");
  cmd->add_option("--min-confidence", o->config.min_confidence, "loop closures at least this confident join the graph")
      ->capture_default_str();
  cmd->add_option("--threads", o->config.loops.num_threads, "threads (results do not depend on it)")->capture_default_str();
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  cmd->callback([o] { run_slam_command(*o); });
}

}  // namespace partslam::apps
