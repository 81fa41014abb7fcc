// Test helper: the association of a scan stream with itself (every scan is its own reference), for
// local_consistency / reference_frames on simulated logs whose exact poses are the reference.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace partslam::testing {

inline std::vector<std::optional<std::size_t>> identity_index(std::size_t n) {
  std::vector<std::optional<std::size_t>> index(n);
  for (std::size_t i = 0; i < n; ++i) index[i] = i;
  return index;
}

}  // namespace partslam::testing
