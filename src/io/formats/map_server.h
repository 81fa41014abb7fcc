// ROS map_server maps (http://wiki.ros.org/map_server): a YAML file (image, resolution, origin [x, y, yaw],
// occupied_thresh, free_thresh, negate, mode) beside a PGM image whose first row is the top of the map. Read as a
// building map to localise in or to use as a dictionary; written by `partslam export-map` as map_saver does
// (trinary: occupied 0, free 254, unknown 205). Only PGM images (P2 / P5, 8 or 16 bit) are read.
#pragma once

#include <filesystem>

#include "core/maps/grid_map.h"

namespace partslam::io {

/// Reads map.yaml and its image (a path relative to the YAML's folder). A cell is occupied when its occupancy
/// (255 - p) / 255 (p / 255 with negate) exceeds occupied_thresh, free below free_thresh, else unknown (mode
/// trinary and scale; mode raw reads p as a percentage, 255 unknown). Throws InputError naming the file and the
/// field or the line for a missing or bad field, a missing or unreadable image, a truncated or oversized PGM.
GridMap read_map_yaml(const std::filesystem::path& yaml_path);

/// Writes map.yaml and, beside it, the PGM named after it (map.yaml -> map.pgm), each atomically, the image
/// first. Throws InputError naming the path when a file cannot be written.
void write_map_yaml(const std::filesystem::path& yaml_path, const GridMap& map);

}  // namespace partslam::io
