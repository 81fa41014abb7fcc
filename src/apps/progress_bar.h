// A one-line progress bar on stderr for long commands (eval, describe, submaps --scan-match), redrawn in place
// and cleared when done; silent when disabled (--quiet) or when stderr is not a terminal.
//
// One bar per phase, never going backwards. A phase is a stage name with its item count; a report of the same
// phase with fewer items done than already drawn is dropped (parallel_for counts items on several threads and
// reports them in whatever order the threads reach the report: 309/772 could arrive after 310/772). A new stage name
// or count, or the same ones back in the first half after the phase completed, start a new bar.
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
  explicit ProgressBar(bool enabled = true) : out_(std::cerr), enabled_(enabled && isatty(STDERR_FILENO)) {}
  /// Draws on `out` whenever `enabled` (tests).
  ProgressBar(std::ostream& out, bool enabled) : out_(out), enabled_(enabled) {}
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  ~ProgressBar() {
    if (enabled_ && drawn_) out_ << "\r\033[K" << std::flush;
  }
  /// A core::Progress callback: stage name, items done, items in the stage.
  void operator()(const std::string& stage, std::size_t done, std::size_t total) {
    if (!enabled_ || total == 0) return;
    // The same stage and count after the phase completed: a late report of it (dropped) unless it is back in the
    // first half, which a report at most a thread count behind cannot be: then the stage runs again.
    const bool same_phase = stage == stage_ && total == total_ && (done_ < total_ || 2 * done > total);
    if (same_phase && done <= done_) return;  // late (out of order) or repeated: the bar never goes back
    if (done > total) done = total;
    const int percent = static_cast<int>(100 * done / total);
    const bool redraw = !same_phase || percent != percent_ || done == total;
    stage_ = stage, total_ = total, done_ = done;
    if (!redraw) return;
    percent_ = percent, drawn_ = true;
    const int width = 30, filled = width * percent / 100;
    out_ << "\r\033[K" << std::setw(22) << std::left << stage.substr(0, 22) << " [" << std::string(filled, '#')
         << std::string(width - filled, ' ') << "] " << std::right << std::setw(3) << percent << "% " << done << "/"
         << total << std::flush;
  }

 private:
  std::ostream& out_;
  bool enabled_;
  bool drawn_ = false;
  std::string stage_;
  std::size_t total_ = 0, done_ = 0;
  int percent_ = -1;
};

}  // namespace partslam::apps
