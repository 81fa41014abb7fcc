// Reading a command's log (CARMEN, ROS 1 bag, sim[:SEED]) the one way every subcommand does: the --skip-damaged flag,
// and the reader's warnings (a recording cut short and read up to its last whole record, damage skipped) printed to
// stderr as "warning: ..." before the command goes on. The readers decide what is damage (io/carmen_log.h,
// io/ros_bag.h); this only passes the option and shows what they said.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "io/carmen_log.h"
#include "io/scan_source.h"

namespace partslam::apps {

/// --skip-damaged on `cmd`: sets options.skip_damaged.
void add_log_read_options(CLI::App& cmd, io::LogReadOptions& options);

/// io::load_scan_source(spec, options), printing each of its warnings to stderr as "warning: ...".
io::ScanSource load_scans(const std::string& spec, const io::LogReadOptions& options);

}  // namespace partslam::apps
