#include "apps/scan_input.h"

#include <cstdio>

namespace partslam::apps {

void add_log_read_options(CLI::App& cmd, io::LogReadOptions& options) {
  cmd.add_flag("--skip-damaged", options.skip_damaged,
               "skip damaged records in the middle of a log (malformed lines, corrupt bag chunks, scans whose pose "
               "jumps) and count them in a warning, instead of stopping; a log cut short is read up to its last whole "
               "record either way");
}

io::ScanSource load_scans(const std::string& spec, const io::LogReadOptions& options) {
  io::ScanSource source = io::load_scan_source(spec, options);
  for (const std::string& w : source.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return source;
}

}  // namespace partslam::apps
