// Shared by `partslam match` and `eval` (and `demo`, through eval's options): the dMM search's parameters as
// command-line options.
#pragma once

#include <CLI/CLI.hpp>

#include "core/matching/dmm.h"

namespace partslam::apps {

/// --dmm-dilation, --dmm-angular-window (degrees on the command line, radians in `dmm`) and --dmm-turns, each
/// defaulting to what `dmm` holds (the ranking's search, ranking_dmm_config). Values are checked where the
/// config is validated.
void add_dmm_options(CLI::App& cmd, DmmConfig& dmm);

}  // namespace partslam::apps
