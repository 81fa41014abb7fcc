// Parallel loops over independent items (maps, tasks) with optional progress reporting. Results never depend
// on the thread count: every item writes only its own slot.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <limits>
#include <string>

namespace partslam {

/// Progress callback: stage name, items done, items in the stage. Called from one thread at a time.
using Progress = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

/// Runs body(i) for i in [0, n) on num_threads OpenMP threads (dynamic schedule), reporting progress after
/// each item from whichever thread finished it. An exception from a body (which must not leave an OpenMP region:
/// that would end the process) is rethrown here, after the loop; items above the lowest failing one so far are
/// skipped, those below always run, so the exception rethrown is the lowest failing item's for any thread count.
template <typename Body>
void parallel_for(std::size_t n, int num_threads, Body&& body, const std::string& stage = {},
                  const Progress& progress = {}) {
  std::atomic<std::size_t> done{0};
  std::atomic<long> lowest_failed{std::numeric_limits<long>::max()};  // items above it are skipped
  std::exception_ptr error;
  const long count = static_cast<long>(n);
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, num_threads)) if (num_threads > 1)
  for (long i = 0; i < count; ++i) {
    if (i > lowest_failed.load()) continue;
    try {
      body(static_cast<std::size_t>(i));
    } catch (...) {
#pragma omp critical(partslam_parallel_error)
      if (i < lowest_failed.load()) error = std::current_exception(), lowest_failed = i;
      continue;
    }
    const std::size_t d = ++done;
    if (progress) {
#pragma omp critical(partslam_parallel_progress)
      progress(stage, d, n);
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace partslam
