// Pictures of occupancy grids (core/maps/grid_map.h): free cells white, occupied black, unknown grey, north up,
// each under its title; several grids side by side at one scale (`slam --compare`: the corrected map beside the
// odometry's).
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/maps/grid_map.h"

namespace partslam::plot {

struct TitledGrid {
  const GridMap* map = nullptr;
  std::string title;
  /// The robot's way through the map (map frame), drawn as a blue line with its start green and its end red.
  Points2 path;
  /// Places to look at (map frame; e.g. where `slam`'s map check failed), circled in red.
  Points2 marks;
  /// Pairs of places joined by a loop closure (map frame), drawn as thin orange lines under the path.
  std::vector<std::pair<Vec2, Vec2>> links;
};

/// Writes the grids side by side as a PNG, atomically, shrunk by a whole factor so the picture is at most
/// max_side pixels wide and high (a block of cells is occupied when any of its cells is, else free when any is),
/// each grid's path and marks drawn over it, each title wrapped over its own grid (the picture grows a line
/// for each line the longest title takes). Throws InputError for no grid, an invalid one, or a PNG that cannot
/// be written.
void write_grid_maps_png(const std::filesystem::path& path, const std::vector<TitledGrid>& grids, int max_side = 2000);

}  // namespace partslam::plot
