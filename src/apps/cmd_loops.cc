// partslam loops DB: loop closures among the submaps of one dataset (core/slam/loop_closure.h): for every submap, the
// earlier submaps beyond the travel gap that its shortlist (rerank:20 = the succinct matcher's top 20 verified by
// dMM) finds, with the dMM relative pose, score and confidence. Accepted closures (confidence >= --min-confidence) go
// to --g2o (io/formats/loop_files.h). With ground truth — the stored frames of a dataset built from a corrected log,
// or --truth TWIN|F.relations for a scan-matched one (the dataset's log is read again and scan-matched with the
// stored settings, io/logs/ground_truth.h) — it prints precision-recall, writes the curve to --plot and the figures
// to --json (precision-recall: core/evaluation/loop_evaluation.h). --config FILE.yaml sets the loop closures',
// acceptance's and truth's settings (io/formats/config_file.h, LoopsConfig; flags given override it), --print-config
// shows them all.
// Tested by: apps/cli_eval_test.cc
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/config_options.h"
#include "apps/json_text.h"
#include "apps/mpi_split.h"
#include "apps/progress_bar.h"
#include "core/error.h"
#include "core/evaluation/loop_evaluation.h"
#include "core/evaluation/trajectory_check.h"
#include "core/maps/submap.h"
#include "core/slam/front_end.h"
#include "core/slam/loop_closure.h"
#include "core/timing.h"
#include "io/files/atomic_file.h"
#include "io/formats/config_file.h"
#include "io/logs/ground_truth.h"
#include "io/formats/loop_files.h"
#include "io/store/map_database.h"
#include "io/logs/scan_source.h"
#include "apps/scan_input.h"
#include "plot/line_plot.h"

namespace partslam::apps {
namespace {

struct LoopsOptions {
  std::string db;
  std::string config_file;  ///< --config
  io::LogReadOptions read;  ///< reading the dataset's log (--truth)
  std::string dataset;
  LoopClosureConfig config = io::loops_command_defaults();
  LoopTruthConfig truth_config;
  double min_confidence = 0.2;
  std::string truth;
  std::string json;
  std::string g2o;
  std::string plot;
  bool quiet = false;
};

io::DatasetInfo choose_dataset(const io::MapDatabase& db, const std::string& name) {
  if (!name.empty()) {
    auto d = db.find_dataset(name);
    if (!d) throw InputError(db.path().string() + ": no dataset named '" + name + "'");
    return *d;
  }
  std::vector<io::DatasetInfo> maps;
  for (const io::DatasetInfo& d : db.datasets())
    if (d.spec.kind == io::DatasetKind::kSubmaps) maps.push_back(d);
  if (maps.size() != 1)
    throw InputError(db.path().string() + ": " + std::to_string(maps.size()) +
                     " datasets of submaps: choose one with --dataset");
  return maps.front();
}

// True frames of the stored submaps: the stored ones for a dataset of a corrected log; with a twin, through the
// dataset's log rebuilt as it was stored. Empty when there is no ground truth.
std::vector<std::optional<Pose2>> true_frames(const io::DatasetInfo& d, const Submaps& maps, const LoopsOptions& o,
                                              std::string& note) {
  if (o.truth.empty()) {
    if (d.spec.scan_matched) {
      note = "no ground truth (scan-matched dataset: give --truth with its corrected twin)";
      return {};
    }
    note = "ground truth: the stored frames (the log's poses)";
    std::vector<std::optional<Pose2>> frames;
    for (const Submap& m : maps) frames.emplace_back(m.T_world_map);
    return frames;
  }
  Scans scans = load_scans(d.spec.source, o.read).scans;
  if (d.spec.scan_matched) scans = scan_match_log(scans, d.spec.front_end).scans;
  const Submaps rebuilt = build_submaps(scans, d.spec.config);
  bool same = rebuilt.size() == maps.size();
  for (std::size_t i = 0; same && i < maps.size(); ++i) same = rebuilt[i].anchor_scan == maps[i].anchor_scan;
  if (!same)
    throw InputError(d.spec.source + ": rebuilding dataset '" + d.spec.name + "' from it gives other submaps (" +
                     std::to_string(rebuilt.size()) + ", stored " + std::to_string(maps.size()) +
                     "): the log changed since it was stored");
  const io::GroundTruth truth = io::load_ground_truth(o.truth, scans);
  std::vector<std::optional<Pose2>> frames = reference_frames(maps, scans, truth.reference, truth.index);
  std::size_t known = 0;
  for (const auto& f : frames) known += f.has_value();
  note = "ground truth: " + truth.description + " (" + std::to_string(known) + " of " + std::to_string(maps.size()) +
         " submaps have a reference frame)";
  return frames;
}

// --config: the file's settings, then the flags given on the command line.
void apply_config_file(const CLI::App& cmd, LoopsOptions& o) {
  io::LoopsConfig f;
  io::read_config_file(o.config_file, f);
  if (given(cmd, "--method")) f.loops.method = o.config.method;
  if (given(cmd, "--gap")) f.loops.min_travel_gap = o.config.min_travel_gap;
  if (given(cmd, "--min-score")) f.loops.min_score = o.config.min_score;
  if (given(cmd, "--context")) f.loops.context = o.config.context;
  if (given(cmd, "--drift")) f.loops.drift_rate = o.config.drift_rate;
  if (given(cmd, "--threads")) f.loops.num_threads = o.config.num_threads;
  if (given(cmd, "--no-graph-check")) f.loops.graph_check = false;
  if (given(cmd, "--no-consistency-check")) f.loops.consistency.enabled = false;
  if (given(cmd, "--measured-poses")) f.loops.graph_pose = false;
  if (given(cmd, "--min-confidence")) f.min_confidence = o.min_confidence;
  if (given(cmd, "--radius")) f.truth.radius = o.truth_config.radius;
  o.config = f.loops;
  o.min_confidence = f.min_confidence;
  o.truth_config = f.truth;
}

void run_loops(const LoopsOptions& o) {
  io::validate(io::LoopsConfig{o.config, o.min_confidence, o.truth_config});  // before any work
  io::check_outputs({{"--json", o.json}, {"--g2o", o.g2o}, {"--plot", o.plot}}, {{"DB", o.db}});
  const auto db = io::MapDatabase::open(o.db, io::MapDatabase::Mode::kReadOnly);
  const io::DatasetInfo dataset = choose_dataset(db, o.dataset);
  const Submaps maps = db.load_submaps(dataset.id);
  std::string note;
  const std::vector<std::optional<Pose2>> truth = true_frames(dataset, maps, o, note);
  if (!o.plot.empty() && truth.empty()) throw InputError("--plot: " + note);

  const auto t0 = Clock::now();
  std::vector<LoopClosure> closures;
  {
    ProgressBar bar(!o.quiet && is_reporting_process());
    // Under mpirun the queries are split over the ranks (apps/mpi_split.h); rank 0 reports.
    closures = find_loop_closures(
        maps, o.config, [&bar](const std::string& s, std::size_t d, std::size_t n) { bar(s, d, n); }, world_split());
  }
  if (!is_reporting_process()) return;
  const double seconds = ms_since(t0) / 1e3;
  std::vector<LoopClosure> accepted;
  for (const LoopClosure& c : closures)
    if (c.confidence >= o.min_confidence) accepted.push_back(c);
  const FailedChecks failed = failed_checks(closures);
  std::cout << std::fixed << std::setprecision(1) << dataset.spec.name << ": " << maps.size() << " submaps, "
            << closures.size() << " verified hypotheses (" << o.config.method << ", G " << o.config.min_travel_gap
            << " m; " << failed.outside_group << " outside the consistent group, " << failed.at_odds_with_graph
            << " at odds with its pose graph), " << accepted.size()
            << " accepted at confidence >= " << std::setprecision(2) << o.min_confidence << std::setprecision(1)
            << ", " << seconds << " s\n"
            << note << "\n";
  nlohmann::json j = {{"dataset", dataset.spec.name},
                      {"method", o.config.method},
                      {"min_travel_gap", o.config.min_travel_gap},
                      {"min_confidence", o.min_confidence},
                      {"seconds", seconds},
                      {"closures", io::closures_json(maps, closures, o.min_confidence)}};
  if (!truth.empty()) {
    const LoopEvaluation e = evaluate_loop_closures(closures, maps, truth, o.truth_config);
    std::cout << std::setprecision(3) << "relevant pairs (R " << o.truth_config.radius << " m): " << e.relevant_pairs
              << "; correct hypotheses " << e.correct << " of " << e.hypotheses << "; max F1 " << e.max_f1
              << "; recall at 100 % precision " << e.recall_at_full_precision << " (confidence >= "
              << e.confidence_at_full_precision << "); places: " << e.relevant_queries
              << " submaps with a relevant earlier one, " << e.query_recall_at_full_precision
              << " of them closed at 100 % precision\n";
    j["evaluation"] = io::loop_evaluation_json(e);
    for (std::size_t i = 0; i < closures.size(); ++i) {
      if (e.verdicts[i] < 0) continue;
      const Pose2 T = truth[closures[i].match]->inverse() * *truth[closures[i].query];
      j["closures"][i]["correct"] = e.verdicts[i] == 1;
      j["closures"][i]["true_pose"] = pose_json(T);
    }
    if (!o.plot.empty()) {
      plot::Curve curve{dataset.spec.name + " " + o.config.method, {}};
      for (const PrecisionRecall& p : e.curve) curve.points.emplace_back(p.recall, p.precision);
      plot::write_line_plot(o.plot, {"loop closures: " + dataset.spec.name, "recall", "precision", 1.0, 1}, {curve});
    }
  }
  if (!o.json.empty()) io::write_atomically(o.json, [&](std::ostream& out) { out << json_text(j); });
  if (!o.g2o.empty()) io::write_atomically(o.g2o, [&](std::ostream& out) { io::write_g2o(out, maps, accepted); });
}

}  // namespace

void register_loops(CLI::App& app) {
  auto o = std::make_shared<LoopsOptions>();
  CLI::App* cmd = app.add_subcommand("loops", "Find loop closures among the submaps of a dataset (shortlist, dMM verification)");
  cmd->add_option("db", o->db, "map database")->required();
  cmd->add_option("--dataset", o->dataset, "dataset of submaps (default: the only one)");
  add_log_read_options(*cmd, o->read);
  cmd->add_option("--method", o->config.method, "shortlist and verification: rerank:R[:SPEC] or dmm")->capture_default_str();
  cmd->add_option("--gap", o->config.min_travel_gap, "G: min travel between a submap and its matches [m]")
      ->capture_default_str();
  cmd->add_option("--min-score", o->config.min_score, "hypotheses with a lower dMM inlier fraction are dropped")
      ->capture_default_str();
  cmd->add_option("--context", o->config.context,
                  "verification in context: submaps within this travel of query and match are joined [m]; 0 = off")
      ->capture_default_str();
  cmd->add_option("--drift", o->config.drift_rate,
                  "drift gate: matches farther than 2 m + DRIFT x travel gap (and 0.3 rad + 0.2 DRIFT rad/m) from "
                  "the stored relative pose are dropped; 0 = off")
      ->capture_default_str();
  cmd->add_option("--min-confidence", o->min_confidence, "closures at least this confident are accepted (g2o)")
      ->capture_default_str();
  cmd->add_option("--threads", o->config.num_threads, "threads (results do not depend on it)")->capture_default_str();
  cmd->add_option("--truth", o->truth,
                  "ground truth for a scan-matched dataset: the corrected twin of its log, or its .relations file");
  cmd->add_option("--radius", o->truth_config.radius, "R: true frames this close are the same place [m]")
      ->capture_default_str();
  cmd->add_option("--json", o->json, "write closures (and precision-recall) as JSON");
  cmd->add_option("--g2o", o->g2o, "write the pose graph: submap vertices, consecutive and accepted loop edges");
  cmd->add_option("--plot", o->plot, "write the precision-recall curve as PNG (needs ground truth)");
  cmd->add_flag("--no-graph-check", [o](std::int64_t) { o->config.graph_check = false; },
                "keep hypotheses that disagree with a robust pose graph of all of them at full confidence");
  cmd->add_flag("--no-consistency-check", [o](std::int64_t) { o->config.consistency.enabled = false; },
                "keep hypotheses outside the largest group that agrees pairwise through the front end's chain at "
                "full confidence");
  cmd->add_flag("--measured-poses", [o](std::int64_t) { o->config.graph_pose = false; },
                "report each closure's own match pose, not the pose graph's for the consistent ones");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  add_config_options(*cmd, o->config_file, [] { return io::config_yaml(io::LoopsConfig{}); });
  cmd->callback([o, cmd] {
    if (!o->config_file.empty()) apply_config_file(*cmd, *o);
    o->truth_config.min_travel_gap = o->config.min_travel_gap;
    if (given(*cmd, "--drift")) {
      if (o->config.drift_rate == 0) o->config.drift_offset = 0;  // --drift 0: off
      o->config.drift_turn_rate = 0.2 * o->config.drift_rate;
    }
    run_loops(*o);
  });
}

}  // namespace partslam::apps
