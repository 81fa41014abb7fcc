// How the evaluation's work is split over processes (MPI ranks: apps/mpi_split.h). Each process
// takes a contiguous slice of the maps (their CPD) and of the tasks; the slices are gathered in order on every
// process, so every figure equals a single process's (timings apart). What travels are records of a trivially
// copyable type (all_gather below), as bytes; the base class is one process: its slice is everything and
// gathering copies. The library itself has no MPI.
#pragma once

#include <cstddef>
#include <cstring>
#include <span>
#include <type_traits>
#include <utility>
#include <vector>

namespace partslam {

class WorkSplit {
 public:
  virtual ~WorkSplit() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// Every process's records, concatenated in rank order, on every process (the slices may differ in length):
  /// `mine` holds whole records of record_size bytes each. Use all_gather below, which is typed.
  virtual std::vector<std::byte> all_gather_bytes(std::span<const std::byte> mine, std::size_t record_size) const {
    static_cast<void>(record_size);
    return {mine.begin(), mine.end()};
  }

  /// This process's [begin, end) of n items: contiguous slices, the first n % size one item longer.
  std::pair<std::size_t, std::size_t> slice(std::size_t n) const {
    const auto p = static_cast<std::size_t>(size()), r = static_cast<std::size_t>(rank());
    const std::size_t base = n / p, extra = n % p;
    const std::size_t begin = r * base + std::min(r, extra);
    return {begin, begin + base + (r < extra ? 1 : 0)};
  }
};

/// Every process's records, concatenated in rank order, on every process. T travels as its bytes (the
/// processes run the same build), so it must be trivially copyable: a plain record, an optional field as a flag
/// and a value.
template <typename T>
std::vector<T> all_gather(const WorkSplit& split, std::span<const T> mine) {
  static_assert(std::is_trivially_copyable_v<T>, "all_gather sends records as bytes");
  const std::vector<std::byte> bytes = split.all_gather_bytes(std::as_bytes(mine), sizeof(T));
  std::vector<T> all(bytes.size() / sizeof(T));
  if (!all.empty()) std::memcpy(all.data(), bytes.data(), all.size() * sizeof(T));
  return all;
}

/// The one-process split (the default of evaluate).
inline const WorkSplit& local_work() {
  static const WorkSplit split;
  return split;
}

}  // namespace partslam
