// Shared by the two map_server targets: the invariants of a map read_map_yaml returned.
#pragma once

#include "core/maps/grid_map.h"
#include "fuzz/fuzz_common.h"

namespace partslam::fuzz {

inline void check_grid_map(const GridMap& map) {
  check(map.width >= 1 && map.height >= 1, "map size");
  check(map.cells.size() == static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height), "cells");
  check(map.resolution >= 0.001 && map.resolution <= 100.0, "resolution");
  check(finite(map.origin), "origin finite");
  for (const CellState c : map.cells) {
    check(c == CellState::kUnknown || c == CellState::kFree || c == CellState::kOccupied, "cell state");
  }
}

}  // namespace partslam::fuzz
