// Point files: ASCII PLY (x y z=0) or CSV (x,y), written atomically and read back (a local map to query
// with, e.g. from another mapper).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "core/types.h"

namespace partslam::io {

enum class PointFormat { kPly, kCsv };

/// Parses "ply" or "csv"; throws InputError ("point format: expected ply or csv, got '...'") otherwise.
PointFormat parse_point_format(const std::string& name);

/// Writes the points; T_world_points, when given, is written into the header (PLY: "comment T_world_points x
/// y theta", CSV: "# T_world_points x y theta" [m, m, rad]), naming where the points' frame lies in a world
/// frame (a stored map exported in its map frame: its T_world_map). Laser origins (where the laser was when
/// it saw the points, in the points' frame), when given, follow the points: PLY a second element
/// "laser_origin" (x y), CSV one comment line "# laser_origin x y" each, which tools that skip comments
/// ignore.
void write_points(const std::filesystem::path& path, const Points2& points, PointFormat format,
                  const std::optional<Pose2>& T_world_points = std::nullopt,
                  const Points2& laser_origins = {});

/// A point file's points and, when its header names one (write_points), the pose of its frame in the world
/// frame and the laser origins (empty for a file without them: bare points).
struct PointFile {
  Points2 points;
  std::optional<Pose2> T_world_points;
  Points2 laser_origins;
};

/// Reads a point file by its extension: .ply (ASCII, the x and y vertex properties) or .csv (x,y per line; a
/// first line that is not numeric is a header; further columns are ignored). Throws InputError naming the file
/// and line for a malformed, binary, empty or oversized file (more than max_points) and for non-finite values.
Points2 read_points(const std::filesystem::path& path, std::size_t max_points = 20'000'000);

/// read_points, and the T_world_points line of the header and the laser origins when there are (a malformed
/// one is an InputError naming the line; so are more origins than max_points).
PointFile read_point_file(const std::filesystem::path& path, std::size_t max_points = 20'000'000);

}  // namespace partslam::io
