// Reading a command's log (CARMEN, ROS 1 or ROS 2 bag, sim[:SEED]) the one way every subcommand does: the
// --skip-damaged, --scan-topic and --odom-topic options, and the reader's warnings (a recording cut short and read up
// to its last whole record, damage skipped) printed to stderr as "warning: ..." before the command goes on. The
// readers decide what is damage (io/logs/carmen_log.h, io/logs/ros_bag.h, io/logs/ros2_bag.h); this only passes the
// options and shows what they said, naming the options by their flags where the readers name the library's fields.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "io/logs/log_read_options.h"
#include "io/logs/scan_source.h"

namespace partslam::apps {

/// --skip-damaged, --scan-topic, --odom-topic on `cmd`: set options.skip_damaged, scan_topic, odom_topic.
void add_log_read_options(CLI::App& cmd, io::LogReadOptions& options);

/// The readers' errors and warnings in the command line's words: the readers name their option as the library
/// does (LogReadOptions::skip_damaged, "skip_damaged"); a command line user sets it with --skip-damaged.
std::string with_flag_names(std::string text);

/// io::load_scan_source(spec, options), its errors and warnings worded with the flag names (with_flag_names),
/// printing each warning to stderr as "warning: ..." (the returned warnings are worded the same, for --json).
io::ScanSource load_scans(const std::string& spec, const io::LogReadOptions& options);

}  // namespace partslam::apps
