// How the evaluation's work is split over processes (issue "scale": MPI ranks, apps/mpi_split.h). Each process
// takes a contiguous slice of the maps (their CPD) and of the tasks; the slices are gathered in order on every
// process, so every figure equals a single process's (timings apart). The base class is one process: its slice
// is everything and gathering copies. The library itself has no MPI.
#pragma once

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace partslam {

class WorkSplit {
 public:
  virtual ~WorkSplit() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// Every process's values, concatenated in rank order, on every process (the slices may differ in length).
  virtual std::vector<double> all_gather(std::span<const double> mine) const { return {mine.begin(), mine.end()}; }

  /// This process's [begin, end) of n items: contiguous slices, the first n % size one item longer.
  std::pair<std::size_t, std::size_t> slice(std::size_t n) const {
    const auto p = static_cast<std::size_t>(size()), r = static_cast<std::size_t>(rank());
    const std::size_t base = n / p, extra = n % p;
    const std::size_t begin = r * base + std::min(r, extra);
    return {begin, begin + base + (r < extra ? 1 : 0)};
  }
};

/// The one-process split (the default of evaluate).
inline const WorkSplit& local_work() {
  static const WorkSplit split;
  return split;
}

}  // namespace partslam
