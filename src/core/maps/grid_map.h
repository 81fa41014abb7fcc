// A building map as ROS map_server holds one (docs/NOTES.md, "Locate"): a grid of cells that are
// unknown, free or occupied, its resolution, and the pose of its lower-left corner in the map frame. Built here
// from scans with known poses by ray casting (every beam frees the cells it crosses and hits its end cell), read
// and written as map.yaml + PGM by io/formats/map_server.h, and turned into points for dMM by occupied_points.
#pragma once

#include <cstdint>
#include <vector>

#include "core/maps/scan.h"

namespace partslam {

enum class CellState : std::uint8_t { kUnknown = 0, kFree = 1, kOccupied = 2 };

struct GridMap {
  double resolution = 0.05;  ///< cell side [m]
  Pose2 origin;              ///< pose of the lower-left corner of cell (0, 0) in the map frame (map_server's origin)
  int width = 0;             ///< columns
  int height = 0;            ///< rows; row 0 is the lowest y (an image's last row)
  std::vector<CellState> cells;  ///< row-major, width * height

  CellState at(int column, int row) const {
    return cells[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) + static_cast<std::size_t>(column)];
  }
  /// Centre of a cell in the map frame [m].
  Vec2 cell_centre(int column, int row) const {
    return origin * Vec2((column + 0.5) * resolution, (row + 0.5) * resolution);
  }
};

struct GridMapConfig {
  double resolution = 0.05;             ///< cell side [m] (map_server maps are usually 0.05 m)
  double max_range = kDefaultMaxRange;  ///< beam endpoints farther from the laser are not used [m]
  double occupied_ratio = 0.25;  ///< a hit cell is occupied when hits / (hits + pass-throughs) reaches this
  double margin = 0.5;           ///< unknown border around the scanned area [m]
};

/// Throws InputError naming the field.
void validate(const GridMapConfig& config);

/// Throws InputError naming the field when the map is inconsistent (size, resolution, non-finite origin).
void validate(const GridMap& map);

/// The map of scans with known poses (a corrected log) in their world frame, axis-aligned with it. Throws
/// InputError when there is no point, or the map would span more than kMaxMapExtent or 2^28 cells.
GridMap build_grid_map(const Scans& scans, const GridMapConfig& config = {});

/// Centres of the occupied cells in the map frame, row by row (dMM's and the dictionary's input).
Points2 occupied_points(const GridMap& map);

}  // namespace partslam
