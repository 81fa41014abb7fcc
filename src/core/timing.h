// Wall-clock timing of the library's stages (rankers, CPD), reported in results, never used to decide.
#pragma once

#include <chrono>

namespace partslam {

using Clock = std::chrono::steady_clock;

/// Milliseconds elapsed since t0.
inline double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace partslam
