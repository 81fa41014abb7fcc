// Registration of the CLI subcommands. Each register_* lives in its own cmd_<name>.cc and attaches a
// subcommand whose callback does the work (CLI11 runs callbacks inside App::parse).
#pragma once

#include <CLI/CLI.hpp>

namespace partslam::apps {

// One line per subcommand; keep them in this order: foundation, matching, parts, evaluation.

inline void register_all(CLI::App& app) {
  (void)app;
}

}  // namespace partslam::apps
