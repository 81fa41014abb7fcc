// Test helper: the built-in simulator's submaps (default seed and configuration), built once per test binary,
// and their views for rankers (points only).
#pragma once

#include <vector>

#include "core/ranking/ranking.h"
#include "core/sim/simulator.h"
#include "core/maps/submap.h"

namespace partslam::testing {

inline const Submaps& simulated_maps() {
  static const Submaps maps = build_submaps(simulate(SimulatorConfig{}).scans);
  return maps;
}

inline std::vector<MapView> point_views(const Submaps& maps) {
  std::vector<MapView> views;
  for (const Submap& m : maps) views.push_back({&m.points, nullptr});
  return views;
}

}  // namespace partslam::testing
