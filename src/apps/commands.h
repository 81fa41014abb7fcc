// Registration of the CLI subcommands. Each register_* lives in its own cmd_<name>.cc and attaches a
// subcommand whose callback does the work (CLI11 runs callbacks inside App::parse).
#pragma once

#include <CLI/CLI.hpp>

namespace partslam::apps {

/// A command that wrote its results but cannot vouch for them (`slam` whose verdict is not trusted) throws this
/// after its last write: main exits with `status`, printing nothing more (the command has said why).
struct ExitStatus {
  int status = 0;
};

/// The exit status of a `slam` run whose map was written but is not trusted (README, "Exit status").
inline constexpr int kExitUntrusted = 3;

void register_submaps(CLI::App& app);  // cmd_submaps.cc
void register_dictionary(CLI::App& app);  // cmd_dictionary.cc
void register_info(CLI::App& app);     // cmd_info.cc
void register_eval(CLI::App& app);     // cmd_eval.cc
void register_demo(CLI::App& app);     // cmd_demo.cc
void register_export(CLI::App& app);   // cmd_export.cc
void register_describe(CLI::App& app);  // cmd_describe.cc
void register_match(CLI::App& app);     // cmd_match.cc
void register_render(CLI::App& app);    // cmd_render.cc
void register_loops(CLI::App& app);     // cmd_loops.cc
void register_slam(CLI::App& app);      // cmd_slam.cc
void register_locate(CLI::App& app);    // cmd_locate.cc
void register_export_map(CLI::App& app);  // cmd_export_map.cc

// One line per subcommand; keep them in this order: foundation, matching, parts, evaluation.

inline void register_all(CLI::App& app) {
  register_submaps(app);
  register_dictionary(app);
  register_info(app);
  register_export(app);
  register_export_map(app);
  register_match(app);
  register_locate(app);
  register_loops(app);
  register_slam(app);
  register_describe(app);
  register_render(app);
  register_eval(app);
  register_demo(app);
}

}  // namespace partslam::apps
