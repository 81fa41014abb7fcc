// partslam demo: the main job. With ../shared/data present it runs the paper's data set #1 (fr101 submaps,
// fr079 dictionary) with the Table A methods; without it, the same evaluation on the built-in simulator
// (input building seed 1, dictionary building seed 2). Prints the table and writes Fig. D and the JSON.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>
#include <memory>

#include "apps/commands.h"
#include "apps/json_text.h"
#include "apps/eval_run.h"
#include "io/files/atomic_file.h"
#include "plot/rank_plot.h"

namespace partslam::apps {
namespace {

struct DemoOptions {
  std::string data;  // empty: ../shared/data, then <source>/../shared/data
  std::string out = "out";
  int tasks = 500;
  int threads = 2;
  bool sim = false;
};

const char* kTableAMethods =
    "dmm,succinct,rerank:20,grid:11,sc,sc:128,imm:1,imm:2,imm:3,imm:4,imm:5,hmm:1,hmm:2,hmm:3,hmm:4,hmm:5,"
    "hmm:3:maxmax,hmm:3:summax,rerank:10:3,rerank:20:3";

std::filesystem::path find_data(const std::string& given) {
  if (!given.empty()) return given;
  for (const std::filesystem::path& p : {std::filesystem::path("../shared/data"),
                                        std::filesystem::path(PARTSLAM_SOURCE_DIR) / "../shared/data"}) {
    if (std::filesystem::exists(p / "fr101/fr101-corrected.log.gz") &&
        std::filesystem::exists(p / "fr079/fr079-corrected.log.gz"))
      return p;
  }
  return {};
}

void run_demo(const DemoOptions& d) {
  EvalOptions o;
  const std::filesystem::path data = d.sim ? std::filesystem::path() : find_data(d.data);
  if (data.empty()) {
    std::cout << "demo: ../shared/data not found; running on the built-in simulator "
                 "(input sim:1, dictionary sim:2)\n";
    o.input = "sim:1";
    o.dictionary = "sim:2";
  } else {
    std::cout << "demo: data set #1 of the paper (fr101 submaps, fr079 dictionary) from " << data.string() << "\n";
    o.input = (data / "fr101/fr101-corrected.log.gz").string();
    o.dictionary = (data / "fr079/fr079-corrected.log.gz").string();
  }
  o.methods = kTableAMethods;
  o.config.tasks.num_tasks = d.tasks;
  o.config.num_threads = d.threads;
  std::filesystem::create_directories(d.out);
  const EvalRun run = run_evaluation(o, std::cerr).front();  // one radius: the default
  print_table(run, std::cout);
  const std::filesystem::path json = std::filesystem::path(d.out) / "demo.json";
  const std::filesystem::path plot = std::filesystem::path(d.out) / "demo_fig_d.png";
  io::write_atomically(json, [&](std::ostream& out) { out << json_text(to_json(run)); });
  std::vector<plot::RankCurve> curves;
  for (const MethodResult& m : run.report.methods) curves.push_back({m.method.label, m.normalized_ranks});
  plot::write_rank_plot(plot, run.input_name + " / dictionary " + run.dictionary_name, curves);
  std::cout << "wrote " << json.string() << " and " << plot.string() << "\n";
}

}  // namespace

void register_demo(CLI::App& app) {
  auto d = std::make_shared<DemoOptions>();
  CLI::App* cmd = app.add_subcommand("demo", "Run the main evaluation (data set #1, or the simulator without data)");
  cmd->add_option("--data", d->data, "folder of the shared data sets (default: ../shared/data)");
  cmd->add_flag("--sim", d->sim, "use the built-in simulator even when data is present");
  cmd->add_option("--out", d->out, "output folder for the JSON and the plot")->capture_default_str();
  cmd->add_option("--tasks", d->tasks, "tasks to sample")->capture_default_str();
  cmd->add_option("--threads", d->threads, "threads")->capture_default_str();
  cmd->callback([d] { run_demo(*d); });
}

}  // namespace partslam::apps
