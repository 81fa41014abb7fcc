// Point files: ASCII PLY (x y z=0) or CSV (x,y), written atomically and read back (a local map to query
// with, e.g. from another mapper).
#pragma once

#include <filesystem>
#include <string>

#include "core/types.h"

namespace partslam::io {

enum class PointFormat { kPly, kCsv };

/// Parses "ply" or "csv"; throws InputError otherwise.
PointFormat parse_point_format(const std::string& name);

void write_points(const std::filesystem::path& path, const Points2& points, PointFormat format);

/// Reads a point file by its extension: .ply (ASCII, the x and y vertex properties) or .csv (x,y per line; a
/// first line that is not numeric is a header; further columns are ignored). Throws InputError naming the file
/// and line for a malformed, binary, empty or oversized file (more than max_points) and for non-finite values.
Points2 read_points(const std::filesystem::path& path, std::size_t max_points = 20'000'000);

}  // namespace partslam::io
