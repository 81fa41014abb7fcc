// --config FILE.yaml and --print-config, shared by `partslam slam`, `loops` and `locate`: the file's settings
// (io/formats/config_file.h) replace the defaults, then the flags given on the command line replace the file's.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace partslam::apps {

/// Adds --config FILE (into `file`) and --print-config, which writes `defaults_yaml()` to stdout and ends the run
/// with exit code 0 before any other option is checked.
void add_config_options(CLI::App& cmd, std::string& file, std::function<std::string()> defaults_yaml);

/// True when `flag` was given on the command line (it then overrides the settings file).
inline bool given(const CLI::App& cmd, const std::string& flag) { return cmd.count(flag) > 0; }

}  // namespace partslam::apps
