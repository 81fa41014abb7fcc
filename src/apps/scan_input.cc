#include "apps/scan_input.h"

#include <cstdio>

namespace partslam::apps {

void add_log_read_options(CLI::App& cmd, io::LogReadOptions& options) {
  cmd.add_flag("--skip-damaged", options.skip_damaged,
               "skip damaged records in the middle of a log (malformed lines, corrupt bag chunks, scans whose pose "
               "jumps) and count them in a warning, instead of stopping; a log cut short is read up to its last whole "
               "record either way");
  cmd.add_option("--scan-topic", options.scan_topic,
                 "bags (ROS 1 and 2): the LaserScan topic to read (default: the first one)");
  cmd.add_option("--odom-topic", options.odom_topic,
                 "bags: the Odometry topic that poses the scans, or a tf topic (e.g. /tf) whose odom -> base_link "
                 "transforms do (default: the first Odometry topic, else /tf)");
}

io::ScanSource load_scans(const std::string& spec, const io::LogReadOptions& options) {
  io::ScanSource source = io::load_scan_source(spec, options);
  for (const std::string& w : source.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return source;
}

}  // namespace partslam::apps
