// Shared by `partslam eval` and `partslam demo`: options, loading the input and dictionary, running the
// evaluation with a progress bar, and printing / serialising the results.
#pragma once

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "core/evaluation/evaluation.h"
#include "core/maps/scan.h"
#include "io/logs/log_read_options.h"

namespace partslam::apps {

struct EvalOptions {
  std::string input;       ///< CARMEN log or sim[:SEED]
  std::string dictionary;  ///< CARMEN log or sim[:SEED] (another building)
  io::LogReadOptions read;  ///< reading both (--skip-damaged)
  std::string methods = "dmm,succinct,grid:11,sc:128,imm:3,hmm:3,rerank:20";
  EvalConfig config;        ///< config.tasks.radius is set from `radii` for each run
  /// R of each evaluation (--radius 2,4): the tasks of each radius on the same maps, one after the other, the
  /// verified dMM answers shared between them (core/ranking/verified_pairs.h).
  std::vector<double> radii{2.0};
  double max_range = kDefaultMaxRange;  ///< usable range of the input's submaps and the dictionary [m]
  std::string json;
  std::string plot;
  bool quiet = false;
  bool scan_match = false;  ///< input poses from the front end (raw logs)
  std::string truth;        ///< corrected twin of the input: ground truth for submaps of a raw log
};

/// Adds --input, --dict, --methods, --db-size, --tasks, --seed, --threads and the method parameters.
void add_eval_options(CLI::App& cmd, EvalOptions& options);

struct EvalRun {
  EvalOptions options;
  std::string input_name;
  std::string dictionary_name;
  EvalReport report;
  double seconds = 0;
};

/// Loads both logs, builds submaps and the dictionary, and evaluates at each of options.radii (one run each, in
/// that order; a run's seconds are its own evaluation's, the first's with the loading); progress goes to `log`
/// when it is a terminal (and not quiet).
std::vector<EvalRun> run_evaluation(const EvalOptions& options, std::ostream& log);

/// Where the run of the k-th radius writes an output given as `path`: the first radius `path` itself, each later
/// one `path` with "_r" and the radius inserted before the extension (out.json -> out_r4.json).
std::string radius_output(const std::string& path, std::size_t k, double radius);
/// A radius as --radius and radius_output write it: 4 -> "4", 2.5 -> "2.5".
std::string radius_text(double radius);

void print_table(const EvalRun& run, std::ostream& out);

/// The JSON shape of the evaluation issue (input, dictionary, db_size, tasks, seed, maps, mean_points, methods[]).
nlohmann::json to_json(const EvalRun& run);

}  // namespace partslam::apps
