#include "apps/scan_input.h"

#include <cstdio>
#include <string_view>
#include <utility>

#include "core/error.h"

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

std::string with_flag_names(std::string text) {
  // The readers name LogReadOptions::skip_damaged as the library does: a word of its own ("(skip_damaged ...",
  // "; skip_damaged ..."), never part of a path or of another word.
  static constexpr std::string_view kField = "skip_damaged", kFlag = "--skip-damaged";
  auto delimits = [](char c) { return c == ' ' || c == '(' || c == ')' || c == ';' || c == ','; };
  for (std::size_t at = text.find(kField); at != std::string::npos; at = text.find(kField, at)) {
    const std::size_t end = at + kField.size();
    if ((at == 0 || delimits(text[at - 1])) && (end == text.size() || delimits(text[end]))) {
      text.replace(at, kField.size(), kFlag);
      at += kFlag.size();
    } else {
      at = end;
    }
  }
  return text;
}

io::ScanSource load_scans(const std::string& spec, const io::LogReadOptions& options) {
  io::ScanSource source;
  try {
    source = io::load_scan_source(spec, options);
  } catch (const InputError& e) {
    throw InputError(with_flag_names(e.what()));
  }
  for (std::string& w : source.warnings) {
    w = with_flag_names(std::move(w));
    std::fprintf(stderr, "warning: %s\n", w.c_str());
  }
  return source;
}

}  // namespace partslam::apps
