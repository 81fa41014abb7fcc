// Parallel loops over independent items (maps, tasks) with optional progress reporting. Results never depend
// on the thread count: every item writes only its own slot.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <functional>
#include <string>

namespace partslam {

/// Progress callback: stage name, items done, items in the stage. Called from one thread at a time.
using Progress = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

/// Runs body(i) for i in [0, n) on num_threads OpenMP threads (dynamic schedule), reporting progress after
/// each item from whichever thread finished it.
template <typename Body>
void parallel_for(std::size_t n, int num_threads, Body&& body, const std::string& stage = {},
                  const Progress& progress = {}) {
  std::atomic<std::size_t> done{0};
  const long count = static_cast<long>(n);
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, num_threads)) if (num_threads > 1)
  for (long i = 0; i < count; ++i) {
    body(static_cast<std::size_t>(i));
    const std::size_t d = ++done;
    if (progress) {
#pragma omp critical(partslam_parallel_progress)
      progress(stage, d, n);
    }
  }
}

}  // namespace partslam
