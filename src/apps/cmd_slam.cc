// partslam slam RAW_LOG --out DIR: the whole chain for a raw log (core/slam/slam.h): front end, submaps, loop
// closures (succinct shortlist, dMM and context verification, drift gate), a pose graph with a robust loss,
// corrected scan poses. Writes DIR/corrected.log (CARMEN, corrected poses), DIR/map.yaml + map.pgm (the corrected
// map for map_server and `locate`), DIR/map.png (the same occupancy grid with the path, its start and end, the used
// closures and the verdict; --compare: the odometry's beside it), DIR/result.mcap (the same as ROS 2 messages:
// io/formats/result_mcap.h),
// DIR/loops.json, DIR/slam.json (closures used and set aside, the verdict: core/slam/back_end.h) and, with
// --relations, DIR/relations_error.json (the Kuemmerle et al. 2009 metric, rotation in degrees). Every
// file is written atomically; DIR is created when missing. --config FILE.yaml sets any field of SlamConfig
// (io/formats/config_file.h; flags given override it), --print-config shows them all.
// Tested by: apps/cli_slam_test.cc, apps/cli_eval_test.cc
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/config_options.h"
#include "apps/cpd_options.h"
#include "apps/json_text.h"
#include "apps/log_inputs.h"
#include "apps/progress_bar.h"
#include "apps/scan_input.h"
#include "core/error.h"
#include "core/evaluation/trajectory_check.h"
#include "core/maps/grid_map.h"
#include "core/slam/slam.h"
#include "io/files/atomic_file.h"
#include "io/logs/carmen_log.h"
#include "io/formats/config_file.h"
#include "io/formats/map_server.h"
#include "io/formats/result_mcap.h"
#include "io/logs/relations.h"
#include "io/logs/scan_source.h"
#include "plot/grid_map_image.h"

namespace partslam::apps {
namespace {

struct SlamOptions {
  std::string log;
  std::string config_file;  ///< --config
  io::LogReadOptions read;
  std::string out;
  std::string relations;
  bool relations_at_laser = false;
  SlamConfig config;
  int threads = 1;
  bool compare = false;
  int picture_side = 4000;
  bool quiet = false;
};

std::string relations_text(const RelationsError& e) {
  if (e.relations == 0) return "no relation matched";
  std::ostringstream out;
  out << std::fixed << std::setprecision(3) << e.translation_mean << " +- " << e.translation_std << " m, "
      << std::setprecision(2) << e.rotation_mean * kDegreesPerRadian << " +- "
      << e.rotation_std * kDegreesPerRadian << " deg";
  return out.str();
}

// What the map check (core/slam/map_check.h) read and found.
nlohmann::json map_check_json(const MapCheck& m, const MapCheckConfig& c) {
  return {{"what", "beams of one visit that cross a wall another visit saw"},
          {"scans", m.scans},
          {"beams", m.beams},
          {"revisiting_beams", m.revisiting_beams},
          {"crossing_beams", m.crossing_beams},
          {"crossing_share", m.crossing_share},
          {"max_crossing_share", c.max_crossing_share},
          {"worst_place",
           {{"x", m.worst_place.x()},
            {"y", m.worst_place.y()},
            {"crossing_beams", m.worst_place_crossings},
            {"crossing_share", m.worst_place_share}}},
          {"max_place_share", c.max_place_share},
          {"judged", m.judged},
          {"passed", m.passed}};
}

// The second front end's path against the first's (core/slam/front_end_agreement.h); the window nearest to its
// limits by its log times and where it starts and ends in the map.
nlohmann::json second_opinion_json(const SlamResult& r, const SecondOpinionConfig& c) {
  const FrontEndAgreement& a = r.second_opinion;
  nlohmann::json j{{"what", "the log scan-matched again with another fine field, the two paths compared"},
                   {"enabled", c.enabled},
                   {"fine_sigma", c.fine_sigma},
                   {"window_m", c.window},
                   {"paired_scans", a.paired},
                   {"windows", a.windows},
                   {"pinned_windows", a.pinned},
                   {"max_turn_deg", a.max_turn * kDegreesPerRadian},
                   {"max_shift_m", a.max_shift},
                   {"limit_turn_deg", c.max_turn * kDegreesPerRadian},
                   {"limit_shift_m", c.max_shift},
                   {"judged", a.judged},
                   {"passed", a.passed}};
  if (a.judged && a.worst_last < r.scans.size()) {
    const Scan &from = r.scans[a.worst_first], &to = r.scans[a.worst_last];
    j["worst_window"] = {{"from_time", from.timestamp}, {"to_time", to.timestamp},
                         {"from", {{"x", from.T_world_laser.x}, {"y", from.T_world_laser.y}}},
                         {"to", {{"x", to.T_world_laser.x}, {"y", to.T_world_laser.y}}}};
  }
  return j;
}

nlohmann::json slam_json(const SlamOptions& o, const SlamResult& r) {
  const BackEndResult& b = r.back_end;
  const FailedChecks failed = failed_checks(r.closures);
  return {{"log", o.log},
          {"scans", r.scans.size()},
          {"submaps", r.submaps.size()},
          {"front_end",
           {{"rejected_matches", r.front_end.rejected},
            {"degenerate_scans", r.front_end.degenerate},
            {"half_constrained_scans", r.front_end.half_constrained},
            {"scaled_scans", r.front_end.scaled},
            {"odometry_scale", r.front_end.odometry_scale},
            {"heading_jumps", r.front_end.heading_jumps},
            {"time_reversals", r.front_end.time_reversals},
            {"turning_steps", r.front_end.turning_steps},
            {"wide_searches", r.front_end.wide_searches},
            {"wide_kept", r.front_end.wide_kept},
            {"weak_matches", r.front_end.weak_matches},
            {"weakest_score", r.front_end.weakest_score},
            {"weakest_scan", r.front_end.weakest_scan},
            {"turn_slope", r.front_end.turn_slope()},
            {"mirrored", r.front_end.mirrored},
            {"wall_axis_deg", r.wall_axis * kDegreesPerRadian},
            {"seconds", r.front_end_s}}},
          {"closures",
           {{"hypotheses", r.closures.size()},
            {"outside_consistent_group", failed.outside_group},
            {"at_odds_with_graph", failed.at_odds_with_graph},
            {"offered", r.accepted},
            {"used", b.used_count},
            {"set_aside", b.rejected},
            {"min_confidence", o.config.min_confidence}}},
          {"graph",
           {{"rounds", b.rounds},
            {"initial_cost", b.graph.initial_cost},
            {"final_cost", b.graph.final_cost},
            {"chain_bends", b.chain_bends},
            {"max_chain_bend_m", b.max_chain_translation},
            {"max_chain_bend_deg", b.max_chain_rotation * kDegreesPerRadian}}},
          {"neighbours",
           {{"rounds", o.config.neighbours.rounds},
            {"refined", r.neighbours.refined},
            {"too_far", r.neighbours.too_far},
            {"mean_move_m", r.neighbours.mean_move}}},
          {"map_check", map_check_json(r.map_check, o.config.map_check)},
          {"front_end_map_check", map_check_json(r.front_end_map_check, o.config.map_check)},
          {"second_opinion", second_opinion_json(r, o.config.second_opinion)},
          {"verdict", b.verdict},
          {"trusted", b.trusted()},
          {"front_end_written", b.front_end_written},
          {"reason", b.reason},
          {"verdict_checks", verdict_checks(r, o.config)},
          {"seconds",
           {{"front_end", r.front_end_s},
            {"loops", r.loops_s},
            {"refine", r.refine_s},
            {"graph", r.graph_s},
            {"neighbours", r.neighbours_s},
            {"check", r.check_s},
            {"second_opinion", r.second_opinion_s}}}};
}

// The laser's positions along a log: the path drawn over its map.
Points2 laser_path(const Scans& scans) {
  Points2 path;
  for (const Scan& s : scans) path.push_back(s.T_world_laser.translation());
  return path;
}

// The used closures as lines between their two submaps' centres (their frames' origins, corrected): the places
// matched. (Between the robot's positions at the submaps' anchors the lines run far across: a place is seen from
// up to the laser's range away.)
std::vector<std::pair<Vec2, Vec2>> closure_links(const SlamResult& r) {
  const auto at = [&](std::size_t submap) { return r.submaps.at(submap).T_world_map.translation(); };
  std::vector<std::pair<Vec2, Vec2>> links;
  for (std::size_t k = 0; k < r.offered.size(); ++k)
    if (r.back_end.used[k]) links.emplace_back(at(r.offered[k].query), at(r.offered[k].match));
  return links;
}

// DIR/map.yaml + map.pgm (map_server, occupancy by ray casting), DIR/map.png showing the same grid with the
// robot's path (start green, end red), the used closures and, when the map check failed, its worst place circled,
// when the second front end parted from the first, where its worst window starts and ends (the odometry's map and
// path beside it when asked), and DIR/result.mcap holding the same as ROS 2 messages.
void write_maps(const std::filesystem::path& dir, const SlamResult& r, const Scans& raw, const std::string& title,
                bool compare, int side) {
  const GridMap map = build_grid_map(r.scans);
  io::write_map_yaml(dir / "map.yaml", map);
  Points2 marks;
  if (!r.map_check.passed) marks.push_back(r.map_check.worst_place);
  const FrontEndAgreement& second = r.second_opinion;
  if (!second.passed && second.worst_last < r.scans.size())
    for (std::size_t k : {second.worst_first, second.worst_last}) marks.push_back(r.scans[k].T_world_laser.translation());
  const std::vector<std::pair<Vec2, Vec2>> closures = closure_links(r);
  std::vector<plot::TitledGrid> grids{{&map, title, laser_path(r.scans), marks, closures}};
  GridMap odometry;
  if (compare) {
    try {
      odometry = build_grid_map(raw);
      grids.push_back({&odometry, "odometry", laser_path(raw), {}, {}});
    } catch (const InputError& e) {
      std::cerr << "partslam: warning: the odometry's map is not drawn: " << e.what() << "\n";
    }
  }
  plot::write_grid_maps_png(dir / "map.png", grids, side);
  io::write_result_mcap(dir / "result.mcap", {&map, &r.scans, &raw, closures});
}

// DIR, created when missing (created: whether this run made it), and every file to be written there checked
// before the work.
std::filesystem::path output_folder(const SlamOptions& o, bool& created) {
  namespace fs = std::filesystem;
  const fs::path dir(o.out);
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw InputError(o.out + ": exists and is not a folder (--out names the folder the results go to)");
  created = fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw InputError(o.out + ": cannot create the output folder");
  for (const char* name :
       {"corrected.log", "map.png", "map.yaml", "map.pgm", "result.mcap", "loops.json", "slam.json",
        "relations_error.json"})
    io::check_writable(dir / name);
  return dir;
}

// What the run did, on stdout; what may be wrong with it, as warnings on stderr.
void print_summary(const SlamOptions& o, const io::ScanSource& source, const SlamResult& r) {
  const FrontEndStats& fe = r.front_end;
  const BackEndResult& b = r.back_end;
  const FailedChecks failed = failed_checks(r.closures);
  std::cout << std::fixed << std::setprecision(1) << source.name << ": " << fe.scans << " scans, front end "
            << r.front_end_s << " s (" << std::setprecision(0) << fe.log_seconds / std::max(r.front_end_s, 1e-9)
            << "x the log's " << fe.log_seconds << " s), " << fe.rejected << " matches rejected\n";
  if (o.config.align_to_walls)
    std::cout << "walls at " << std::setprecision(1) << r.wall_axis * kDegreesPerRadian
              << " deg to the log's axes (mapped turned onto them, written in the log's frame)\n";
  std::cout << std::setprecision(1) << r.submaps.size() << " submaps; " << r.closures.size()
            << " loop-closure hypotheses (" << failed.outside_group << " outside the consistent group, "
            << failed.at_odds_with_graph
            << " at odds with its pose graph), " << r.accepted
            << " offered (confidence >= " << std::setprecision(2)
            << o.config.min_confidence << std::setprecision(1) << "), " << r.loops_s << " s; "
            << (o.config.refinement.enabled ? "refined on the scans in " : "not refined on the scans (refinement off), ")
            << r.refine_s << " s\n"
            << "pose graph: " << b.used_count << " closures used, " << b.rejected
            << " set aside (they disagree with the solution), cost " << std::setprecision(3) << b.graph.initial_cost
            << " -> " << b.graph.final_cost << " in " << b.rounds << " solves, " << std::setprecision(1) << r.graph_s
            << " s\nneighbours: " << r.neighbours.refined << " refinements of a scan on the scans around it ("
            << o.config.neighbours.rounds << " rounds, mean move " << std::setprecision(1)
            << 1e3 * r.neighbours.mean_move << " mm, " << r.neighbours.too_far << " over "
            << o.config.neighbours.max_move << " m not taken), " << r.neighbours_s
            << " s\nmap check: " << r.map_check.crossing_beams << " of " << r.map_check.revisiting_beams
            << " beams that revisit a place cross a wall another visit saw ("
            << (r.map_check.judged ? "" : "too few to judge, ") << std::setprecision(1)
            << 100 * r.map_check.crossing_share << " %; the front end's map: " << 100 * r.front_end_map_check.crossing_share
            << " %)\nverdict: " << b.verdict << (b.reason.empty() ? "" : " (" + b.reason + ")") << "; checked: "
            << verdict_checks(r, o.config) << "\n";
  if (!b.trusted())
    std::cerr << "partslam: warning: " << o.log << ": the map written is not trusted, verdict " << b.verdict << " ("
              << b.reason << ")"
              << (b.front_end_written ? "; it is the front end's trajectory, not the closures' solution" : "")
              << "\n";
  if (fe.time_reversals > 0)
    std::cerr << "partslam: warning: " << o.log << ": " << fe.time_reversals << " scans dropped (time goes backwards)\n";
  // Measurements, not warnings: poor odometry (intel) disagrees with the scans this way too.
  std::vector<std::string> front_end;
  if (fe.heading_jumps > 0) {
    const std::vector<double> travel = travel_distances(r.scans);
    std::ostringstream jumps;
    jumps << fe.heading_jumps << " scans turned more than " << o.config.front_end.jump_turn
          << " rad away from the odometry (the scans overruled the wheels' heading: many where the odometry is poor; "
             "first at "
          << static_cast<long>(travel.at(fe.jump_scans.front())) << " m of travel)";
    front_end.push_back(jumps.str());
  }
  if (fe.degenerate > 0) {
    std::ostringstream degenerate;
    degenerate << fe.degenerate << " kept the odometry along a bare corridor (too few walls across it to match)";
    if (fe.scaled > 0)
      degenerate << std::fixed << std::setprecision(3) << ", " << fe.scaled << " of them scaled by "
                 << fe.odometry_scale << " (the odometry's scale as the matches measured it; at the log's end)";
    front_end.push_back(degenerate.str());
  }
  if (fe.half_constrained > 0)
    front_end.push_back(std::to_string(fe.half_constrained) +
                        " moved along a half-constrained corridor only as far as the odometry has lately been wrong");
  if (fe.wide_kept > 0)
    front_end.push_back(std::to_string(fe.wide_kept) +
                        " found again over every heading (the odometry's turn was far off)");
  if (fe.weak_matches > 0) {
    std::ostringstream weak;
    weak << std::fixed << std::setprecision(2) << fe.weak_matches
         << (fe.weak_matches == 1 ? " kept match scored below " : " kept matches scored below ") << kWeakMatch
         << " (the weakest " << fe.weakest_score << ", scan " << fe.weakest_scan
         << "): the trajectory rests on a poor fit there";
    front_end.push_back(weak.str());
  }
  for (std::size_t k = 0; k < front_end.size(); ++k)
    std::cout << (k == 0 ? "front end: " : ", ") << front_end[k] << (k + 1 == front_end.size() ? "\n" : "");
  if (!fe.odometry_moves)
    std::cerr << "partslam: warning: " << o.log << ": the odometry never moves (no odometry in the log?)\n";
  if (fe.mirrored) std::cerr << "partslam: warning: " << o.log << ": " << mirrored_description(fe) << "\n";
}

// DIR/loops.json: the closures offered to the back end, each with whether it was used.
nlohmann::json loops_json(const SlamOptions& o, const SlamResult& r) {
  nlohmann::json loops = nlohmann::json::array();
  for (std::size_t k = 0; k < r.offered.size(); ++k) {
    const LoopClosure& l = r.offered[k];
    loops.push_back({{"query", l.query}, {"match", l.match}, {"score", l.score}, {"confidence", l.confidence},
                     {"used", static_cast<bool>(r.back_end.used[k])},
                     {"pose", pose_json(l.T_match_query)}});
  }
  return {{"log", o.log}, {"submaps", r.submaps.size()}, {"accepted", loops}};
}

// The pose --relations judges: the robot's (ROS's trajectory of a robot is its base's), so a laser mounted off the
// robot's origin is taken off the scans' poses, unless --relations-at-laser.
Pose2 relations_mount(const SlamOptions& o, const io::ScanSource& source) {
  return o.relations_at_laser ? Pose2{} : source.T_base_laser.value_or(Pose2{});
}

// --relations: the errors of the corrected and the odometry's (`before`) trajectories, into
// DIR/relations_error.json and the summary.
void write_relations(const SlamOptions& o, const std::filesystem::path& dir, const Relations& relations,
                     const io::ScanSource& source, const SlamResult& r, const RelationsError& before,
                     nlohmann::json& summary) {
  const Pose2 mount = relations_mount(o, source);
  const RelationsError after = relations_error(r.scans, relations, mount);
  nlohmann::json after_json = io::relations_error_json(after);
  const bool offset = mount.translation().norm() > 0 || mount.theta != 0;
  if (offset) after_json["laser_mount"] = pose_json(mount);
  summary["relations"] = {{"file", o.relations}, {"slam", after_json}, {"odometry", io::relations_error_json(before)}};
  io::write_atomically(dir / "relations_error.json", [&](std::ostream& out) { out << json_text(after_json); });
  std::cout << ", relations_error.json\nrelations (" << after.relations << " of " << relations.size();
  if (offset)
    std::cout << ", between robot poses: the laser's mount " << std::setprecision(3) << mount.x << ", " << mount.y
              << " m, " << mount.theta << " rad taken off";
  std::cout << "): " << relations_text(after) << " (odometry: " << relations_text(before) << ")";
}

// The run itself, its files into dir.
void slam_into(const SlamOptions& o, const std::filesystem::path& dir) {
  const Relations relations = o.relations.empty() ? Relations{} : io::read_relations(o.relations);
  const io::ScanSource source = load_scans(o.log, o.read);
  // The relations against the log's scans before the run, not after it: matching is by timestamp. The same
  // figure is the odometry's error the summary reports.
  const RelationsError odometry =
      o.relations.empty() ? RelationsError{} : relations_error(source.scans, relations, relations_mount(o, source));
  if (!o.relations.empty() && odometry.relations == 0)
    std::cerr << "partslam: warning: " << o.relations << ": no relation names a scan of " << o.log
              << " (its timestamps are not the log's: a re-timed bag, or another run? docs/USAGE.md says how to "
                 "carry relations onto a re-timed recording); checked before the run, which goes on without "
                 "relation errors\n";
  SlamResult r;
  {
    ProgressBar bar(!o.quiet);
    r = run_slam(source.scans, o.config, [&bar](const std::string& s, std::size_t d, std::size_t n) { bar(s, d, n); });
  }
  print_summary(o, source, r);
  const BackEndResult& b = r.back_end;
  io::write_carmen_log(dir / "corrected.log", r.scans, "partslam slam " + o.log + ": corrected poses");
  const std::string title =
      source.name + (b.front_end_written ? ": the front end's map (" + std::to_string(b.used_count) +
                                               " loop closures, orange, not applied; verdict "
                                         : ": corrected map (" + std::to_string(b.used_count) +
                                               " loop closures, orange; verdict ") +
      b.verdict + (b.reason.empty() ? "" : ": " + b.reason) + (r.front_end.mirrored ? "; scans read mirrored" : "") +
      ")";
  write_maps(dir, r, source.scans, title, o.compare, o.picture_side);
  io::write_atomically(dir / "loops.json", [&](std::ostream& out) { out << json_text(loops_json(o, r)); });
  nlohmann::json summary = slam_json(o, r);
  summary["warnings"] = source.warnings;  // the reader's: a recording cut short, damage skipped
  std::cout << "wrote " << (dir / "corrected.log").string()
            << ", map.yaml, map.pgm, map.png, result.mcap, loops.json, slam.json";
  if (!o.relations.empty()) write_relations(o, dir, relations, source, r, odometry, summary);
  std::cout << "\n";
  io::write_atomically(dir / "slam.json", [&](std::ostream& out) { out << json_text(summary); });
  if (!b.trusted()) throw ExitStatus{kExitUntrusted};  // written, with the warning above: not to be trusted
}

// A run that fails leaves no empty folder of its own making behind.
void run_slam_command(const SlamOptions& o) {
  bool created = false;
  const std::filesystem::path dir = output_folder(o, created);
  try {
    slam_into(o, dir);
  } catch (...) {
    std::error_code ec;
    if (created && std::filesystem::is_empty(dir, ec)) std::filesystem::remove(dir, ec);
    throw;
  }
}

}  // namespace

void register_slam(CLI::App& app) {
  auto o = std::make_shared<SlamOptions>();
  CLI::App* cmd = app.add_subcommand("slam", "Raw log -> front end, loop closures, pose graph -> corrected log and map");
  cmd->add_option("log", o->log, "raw log (odometry poses): " + kLogInputs)
      ->required();
  add_log_read_options(*cmd, o->read);
  cmd->add_option("--out", o->out, "output folder (created when missing)")->required();
  cmd->add_option("--relations", o->relations, "Freiburg .relations file: report the relation errors");
  cmd->add_flag("--relations-at-laser", o->relations_at_laser,
                "judge the relations on the laser's poses, not the robot's (a log whose laser is mounted off the "
                "robot's origin: its mount is taken off the scans' poses by default)");
  cmd->add_option("--min-confidence", o->config.min_confidence, "loop closures at least this confident join the graph")
      ->capture_default_str();
  cmd->add_option("--threads", o->threads,
                  "threads of the front end's search and of loop closing (results do not depend on it)")
      ->capture_default_str()
      ->check(in_range(1, 1024));
  cmd->add_flag("--compare", o->compare, "map.png also shows the odometry's map beside the corrected one");
  cmd->add_option("--picture-side", o->picture_side,
                  "map.png's largest side [px]: the grid is shrunk by a whole factor to fit")
      ->capture_default_str()
      ->check(in_range(16, 20000));
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  add_config_options(*cmd, o->config_file, [] { return io::config_yaml(SlamConfig{}); });
  cmd->callback([o, cmd] {
    if (!o->config_file.empty()) {  // the file's settings, then the flags given
      SlamConfig file;
      io::read_config_file(o->config_file, file);
      if (given(*cmd, "--min-confidence")) file.min_confidence = o->config.min_confidence;
      o->config = file;
    }
    if (given(*cmd, "--threads"))
      o->config.loops.num_threads = o->config.front_end.matcher.num_threads = o->config.refinement.num_threads =
          o->config.neighbours.num_threads = o->threads;
    run_slam_command(*o);
  });
}

}  // namespace partslam::apps
