// partslam eval --input LOG --dict LOG --methods LIST: the paper's evaluation (Table A, Fig. D, time, space).
// Builds the submaps of the input and the dictionary map, samples ground-truth tasks, runs every method on the
// same tasks and prints the table; --json and --plot write the figures (atomically). Under `mpirun -n P` the CPD
// and the tasks are split over the ranks (apps/mpi_split.h) and rank 0 reports the same figures.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/json_text.h"
#include "apps/eval_run.h"
#include "apps/mpi_split.h"
#include "core/error.h"
#include "io/files/atomic_file.h"
#include "plot/rank_plot.h"

namespace partslam::apps {
namespace {

void run_eval(const EvalOptions& o) {
  // Fail before hours of work, not after: output paths and parameters are checked first.
  std::vector<io::NamedPath> outputs = {{"--plot", o.plot}};
  for (std::size_t k = 0; k < o.radii.size(); ++k) outputs.push_back({"--json", radius_output(o.json, k, o.radii[k])});
  io::check_outputs(outputs, {{"--input", o.input}, {"--dict", o.dictionary}, {"--truth", o.truth}});
  const std::vector<EvalRun> runs = run_evaluation(o, std::cerr);
  if (!is_reporting_process()) return;  // rank > 0 of mpirun: its slices are in rank 0's report
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const EvalRun& run = runs[k];
    if (runs.size() > 1) std::cout << (k > 0 ? "\n" : "") << "== R = " << radius_text(o.radii[k]) << " m\n";
    print_table(run, std::cout);
    const std::string json = radius_output(o.json, k, o.radii[k]);
    if (!json.empty()) {
      const nlohmann::json j = to_json(run);
      io::write_atomically(json, [&](std::ostream& out) { out << json_text(j); });
      std::cout << "wrote " << json << "\n";
    }
  }
  if (!o.plot.empty()) {  // the first radius's
    const EvalRun& run = runs.front();
    std::vector<plot::RankCurve> curves;
    for (const MethodResult& m : run.report.methods) curves.push_back({m.method.label, m.normalized_ranks});
    plot::write_rank_plot(o.plot, run.input_name + " / dictionary " + run.dictionary_name, curves);
    std::cout << "wrote " << o.plot << "\n";
  }
}

}  // namespace

void register_eval(CLI::App& app) {
  auto o = std::make_shared<EvalOptions>();
  CLI::App* cmd = app.add_subcommand("eval", "Evaluate matching methods on ground-truth tasks (ANR, time, bits)");
  add_eval_options(*cmd, *o);
  cmd->add_option("--json", o->json, "write the results as JSON");
  cmd->add_option("--plot", o->plot, "write the cumulative normalised-rank plot (Fig. D) as PNG (the first radius's)");
  cmd->callback([o] { run_eval(*o); });
}

}  // namespace partslam::apps
