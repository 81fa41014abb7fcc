// Point-set export: ASCII PLY (x y z=0) or CSV (x,y), written atomically.
#pragma once

#include <filesystem>
#include <string>

#include "core/types.h"

namespace partslam::io {

enum class PointFormat { kPly, kCsv };

/// Parses "ply" or "csv"; throws InputError otherwise.
PointFormat parse_point_format(const std::string& name);

void write_points(const std::filesystem::path& path, const Points2& points, PointFormat format);

}  // namespace partslam::io
