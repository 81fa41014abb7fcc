// A one-line progress bar on stderr for long commands (eval, describe, submaps --scan-match), redrawn in place
// and cleared when done; silent when disabled (--quiet) or when stderr is not a terminal.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <iomanip>
#include <iostream>
#include <string>

namespace partslam::apps {

class ProgressBar {
 public:
  /// Draws only when `enabled` and stderr is a terminal.
  explicit ProgressBar(bool enabled = true) : enabled_(enabled && isatty(STDERR_FILENO)) {}
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  ~ProgressBar() {
    if (enabled_ && drawn_) std::cerr << "\r\033[K" << std::flush;
  }
  /// A core::Progress callback: stage name, items done, items in the stage.
  void operator()(const std::string& stage, std::size_t done, std::size_t total) {
    if (!enabled_ || total == 0) return;
    const int percent = static_cast<int>(100 * done / total);
    if (stage == stage_ && percent == percent_ && done != total) return;
    stage_ = stage, percent_ = percent, drawn_ = true;
    const int width = 30, filled = width * percent / 100;
    std::cerr << "\r\033[K" << std::setw(22) << std::left << stage.substr(0, 22) << " ["
              << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << std::right << std::setw(3)
              << percent << "% " << done << "/" << total << std::flush;
  }

 private:
  bool enabled_;
  bool drawn_ = false;
  std::string stage_;
  int percent_ = -1;
};

}  // namespace partslam::apps
