// Tested by: apps/cli_eval_test.cc

#include "apps/eval_run.h"

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "apps/cpd_options.h"
#include "apps/dmm_options.h"
#include "apps/log_inputs.h"
#include "apps/mpi_split.h"
#include "apps/progress_bar.h"
#include "apps/scan_input.h"
#include "core/error.h"
#include "core/evaluation/trajectory_check.h"
#include "core/maps/dictionary.h"
#include "core/maps/submap.h"
#include "core/ranking/ranking.h"
#include "core/slam/front_end.h"
#include "io/store/descriptor_store.h"
#include "io/logs/ground_truth.h"
#include "io/logs/scan_source.h"

namespace partslam::apps {


void add_eval_options(CLI::App& cmd, EvalOptions& o) {
  cmd.add_option("--input", o.input, "input log with good poses (corrected; raw with --scan-match): " + kLogInputs)->required();
  cmd.add_option("--dict", o.dictionary, "dictionary log with good poses (another building): " + kLogInputs)->required();
  add_log_read_options(cmd, o.read);
  cmd.add_option("--methods", o.methods, "comma-separated: " + method_syntax_list())
      ->capture_default_str();
  cmd.add_option("--db-size", o.config.tasks.db_size, "N: maps per task database")->capture_default_str();
  cmd.add_option("--tasks", o.config.tasks.num_tasks, "tasks to sample")->capture_default_str();
  cmd.add_option("--seed", o.config.tasks.seed, "task sampling seed")
      ->capture_default_str()
      ->check(non_negative_seed());
  cmd.add_option("--max-range", o.max_range, "usable range of submaps and dictionary: farther beam endpoints are dropped [m]")
      ->capture_default_str();
  cmd.add_option("--radius", o.radii,
                 "R: relevant-pair radius [m]; several (2,4) evaluate the same maps at each, sharing the verified "
                 "dMM pairs, and write --json FILE for the first and FILE_rR for each other")
      ->delimiter(',')
      ->capture_default_str();
  cmd.add_option("--gap", o.config.tasks.min_travel_gap, "G: min travel gap of a relevant pair [m]")
      ->capture_default_str();
  cmd.add_option("--threads", o.config.num_threads, "threads (results do not depend on it)")->capture_default_str();
  cmd.add_option("--gate", o.config.ranking.parts.origin_gate,
                 "descriptor matcher: origin gate [m], part pairs must put the map frames this close; 0 = off "
                 "(the paper)")
      ->capture_default_str();
  cmd.add_option("--hmm-query-parts", o.config.ranking.parts.hmm_query_parts, "parts of an hMM query")->capture_default_str();
  add_cpd_options(cmd, o.config.cpd, "cpd-");
  add_dmm_options(cmd, o.config.ranking.dmm);
  cmd.add_flag("--scan-match", o.scan_match, "input poses from scan matching seeded by odometry (raw logs)");
  cmd.add_option("--truth", o.truth,
                 "ground truth for submaps of a raw log: its corrected twin (scans associated by content) or its "
                 ".relations file (a reference trajectory solved from them); submaps without a reference scan are "
                 "left out");
  cmd.add_flag("--quiet", o.quiet, "no progress bar");
}

std::string radius_text(double radius) {
  std::ostringstream r;
  r << radius;
  return r.str();
}

std::string radius_output(const std::string& path, std::size_t k, double radius) {
  if (k == 0 || path.empty()) return path;
  const std::filesystem::path p(path);
  return (p.parent_path() / (p.stem().string() + "_r" + radius_text(radius) + p.extension().string())).string();
}

std::vector<EvalRun> run_evaluation(const EvalOptions& o, std::ostream& log) {
  EvalRun run;
  run.options = o;
  auto t0 = std::chrono::steady_clock::now();
  const std::vector<MethodSpec> methods = parse_method_list(o.methods);
  if (o.radii.empty()) throw InputError("eval: --radius needs at least one radius");
  for (const double radius : o.radii) {  // every setting, with each radius
    EvalConfig c = o.config;
    c.tasks.radius = radius;
    validate(c);
  }
  const io::ScanSource input = load_scans(o.input, o.read);
  const io::ScanSource dict = load_scans(o.dictionary, o.read);
  run.input_name = input.name;
  run.dictionary_name = dict.name;
  SubmapConfig submap_config;
  submap_config.max_range = o.max_range;
  DictionaryConfig dictionary_config;
  dictionary_config.max_range = o.max_range;
  validate(submap_config);
  ProgressBar bar(!o.quiet && is_reporting_process());
  const Progress progress = [&bar](const std::string& s, std::size_t d, std::size_t n) { bar(s, d, n); };
  const Scans scans = o.scan_match ? scan_match_log(input.scans, FrontEndConfig{}, progress).scans : input.scans;
  Submaps maps = build_submaps(scans, submap_config);
  std::string truth_note;
  if (!o.truth.empty()) {
    const io::GroundTruth truth = io::load_ground_truth(o.truth, scans);
    const std::size_t built = maps.size();
    maps = with_reference_frames(maps, reference_frames(maps, scans, truth.reference, truth.index));
    truth_note = " (ground truth: " + truth.description + "; " + std::to_string(built - maps.size()) +
                 " submaps without a reference frame left out: no scan with a reference, or its scans disagree)";
    if (maps.empty()) throw InputError(o.truth + ": no submap of " + o.input + " has a reference frame");
  }
  const Dictionary dictionary = build_dictionary(dict.name, dict.scans, dictionary_config);
  if (!o.quiet && is_reporting_process()) {
    log << run.input_name << ": " << maps.size() << " submaps" << truth_note << "; dictionary "
        << run.dictionary_name << ": " << dictionary.points.size() << " points\n";
  }
  std::vector<EvalRun> runs;
  VerifiedPairs verified;
  for (const double radius : o.radii) {
    runs.push_back(run);
    EvalRun& r = runs.back();
    r.options.config.tasks.radius = radius;
    r.report = evaluate(maps, dictionary.points, methods, r.options.config, progress, world_split(), &verified);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t0 = std::chrono::steady_clock::now();
  }
  return runs;
}

void print_table(const EvalRun& run, std::ostream& out) {
  const EvalReport& r = run.report;
  out << "input " << run.input_name << ", dictionary " << run.dictionary_name << ": " << r.maps
      << " maps (mean " << std::fixed << std::setprecision(0) << r.mean_points << " points), "
      << r.relevant_pairs << " relevant pairs (" << std::setprecision(1) << 100 * r.low_overlap_share
      << " % under 30 % true overlap), " << r.tasks << " tasks, N = " << run.options.config.tasks.db_size
      << ", seed " << run.options.config.tasks.seed << "\n";
  const std::size_t asked = static_cast<std::size_t>(run.options.config.tasks.db_size);
  if (r.smallest_database < asked)
    out << "warning: N = " << asked << " asked, but the task databases hold " << r.smallest_database << " to "
        << r.largest_database
        << " maps (only so many lie farther than 2R from a query); each task's figures divide by "
           "its own\n";
  // R@1 % counts a rank <= max(1, 1 % of the task's N): below N = 200 that is rank 1, the R@1 column again, so it is
  // left out of the table (the JSON keeps recall_at_1pct).
  const bool r1pct = r.largest_database >= 200;
  if (!r1pct) out << "(R@1 % is left out: below N = 200 it is R@1 again)\n";
  out << std::left << std::setw(22) << "method" << std::right << std::setw(8) << "ANR %" << std::setw(8) << "R@1";
  if (r1pct) out << std::setw(8) << "R@1%";
  out << std::setw(8) << "R@5%" << std::setw(8) << "R@10%" << std::setw(12) << "us/pair" << std::setw(12)
      << "ms/query" << std::setw(10) << "bits/map" << "\n";
  for (const MethodResult& m : r.methods) {
    out << std::left << std::setw(22) << m.method.label << std::right << std::setprecision(1) << std::setw(8)
        << m.summary.anr_percent << std::setprecision(3) << std::setw(8) << m.summary.recall_at_1;
    if (r1pct) out << std::setw(8) << m.summary.recall_at_1pct;
    out << std::setw(8) << m.summary.recall_at_5pct << std::setw(8)
        << m.summary.recall_at_10pct << std::setw(12) << m.ms_per_pair * 1e3
        << std::setprecision(2)
        << std::setw(12) << m.ms_per_query << std::setprecision(0) << std::setw(10) << m.bits_per_map << "\n";
  }
  out << std::left << std::setw(22) << "oracle (true overlap)" << std::right << std::setprecision(1) << std::setw(8)
      << r.oracle.anr_percent << std::setprecision(3) << std::setw(8) << r.oracle.recall_at_1;
  if (r1pct) out << std::setw(8) << r.oracle.recall_at_1pct;
  out << std::setw(8) << r.oracle.recall_at_5pct << std::setw(8) << r.oracle.recall_at_10pct << "\n";
  for (const MethodResult& m : r.methods) {
    if (m.poses_checked == 0) continue;
    out << std::setprecision(3) << m.method.label << ": relative pose of the relevant map within "
        << run.options.config.pose_tolerance.translation << " m / " << run.options.config.pose_tolerance.rotation << " rad in "
        << m.pose_within_tolerance << " of " << m.poses_checked << " pairs; of the "
        << m.poses_checked_overlap30 << " with >= 30 % true overlap " << m.pose_within_tolerance_overlap30
        << " (within 0.1 m / 1 deg: " << m.pose_fine_overlap30 << ")\n";
  }
  for (const MethodResult& m : r.methods)
    if (m.calibration_error)
      out << std::setprecision(3) << m.method.label << ": expected calibration error " << *m.calibration_error
          << " over its probabilities\n";
  if (r.cpd_ms_per_map > 0) out << std::setprecision(1) << "CPD (offline): " << r.cpd_ms_per_map << " ms per map\n";
  out << std::setprecision(1) << "total " << run.seconds << " s\n";
}

namespace {

nlohmann::json parameters_json(const EvalRun& run) {
  const EvalConfig& c = run.options.config;
  return {{"radius", c.tasks.radius},
          {"max_range", run.options.max_range},
          {"min_travel_gap", c.tasks.min_travel_gap},
          {"origin_gate", c.ranking.parts.origin_gate},
          {"hmm_query_parts", c.ranking.parts.hmm_query_parts},
          {"cpd",
           {{"candidates", c.cpd.candidates == CandidateMode::kCorners ? "corners" : "partitions"},
            {"box_sizes", c.cpd.box_sizes},
            {"corners", c.cpd.corners},
            {"partitions", c.cpd.partitions},
            {"mc", c.cpd.maximality == MaximalityMode::kInlierShare ? "inlier" : "point"},
            {"t_size", c.cpd.t_size},
            {"gc", c.cpd.geometric_consistency},
            {"seed", c.cpd.seed},
            {"dilation", c.cpd.dmm.dilation}}},
          {"dmm",
           {{"dilation", c.ranking.dmm.dilation},
            {"angular_window_deg", c.ranking.dmm.angular_window * kDegreesPerRadian},
            {"canonical_turns", c.ranking.dmm.canonical_turns}}}};
}

nlohmann::json method_json(const MethodResult& m) {
  nlohmann::json j = {{"spec", m.method.spec},
                      {"label", m.method.label},
                      {"anr", m.summary.anr_percent},
                      {"recall_at_1", m.summary.recall_at_1},
                      {"recall_at_1pct", m.summary.recall_at_1pct},
                      {"recall_at_5pct", m.summary.recall_at_5pct},
                      {"recall_at_10pct", m.summary.recall_at_10pct},
                      {"ms_per_pair", m.ms_per_pair},
                      {"ms_per_query", m.ms_per_query},
                      {"ms_query_prep", m.ms_query_prep},
                      {"bits_per_map", m.bits_per_map},
                      {"poses_checked", m.poses_checked},
                      {"pose_within_tolerance", m.pose_within_tolerance},
                      {"poses_checked_overlap30", m.poses_checked_overlap30},
                      {"pose_within_tolerance_overlap30", m.pose_within_tolerance_overlap30},
                      {"pose_fine_overlap30", m.pose_fine_overlap30},
                      {"normalized_ranks", m.normalized_ranks}};
  if (m.calibration_error) {
    j["calibration_error"] = *m.calibration_error;
    j["reliability"] = m.reliability;
  }
  return j;
}

}  // namespace

nlohmann::json to_json(const EvalRun& run) {
  const EvalReport& r = run.report;
  nlohmann::json j = {{"input", run.options.input},
                      {"dictionary", run.options.dictionary},
                      {"db_size", run.options.config.tasks.db_size},
                      {"database_sizes", {r.smallest_database, r.largest_database}},
                      {"tasks", r.tasks},
                      {"seed", run.options.config.tasks.seed},
                      {"maps", r.maps},
                      {"mean_points", r.mean_points},
                      {"relevant_pairs", r.relevant_pairs},
                      {"low_overlap_share", r.low_overlap_share},
                      {"cpd_ms_per_map", r.cpd_ms_per_map},
                      {"seconds", run.seconds}};
  j["parameters"] = parameters_json(run);
  j["methods"] = nlohmann::json::array();
  for (const MethodResult& m : r.methods) {
    j["methods"].push_back(method_json(m));
  }
  j["oracle"] = {{"anr", r.oracle.anr_percent},
                 {"recall_at_1", r.oracle.recall_at_1},
                 {"recall_at_5pct", r.oracle.recall_at_5pct},
                 {"recall_at_10pct", r.oracle.recall_at_10pct}};
  return j;
}

}  // namespace partslam::apps
