// Results as robotics viewers read them: an MCAP file (https://mcap.dev) of ROS 2 Humble messages in CDR,
// which Foxglove opens and `ros2 bag play` replays. `slam` writes DIR/result.mcap with
//   /map            nav_msgs/msg/OccupancyGrid      the corrected map (as map.yaml + map.pgm hold it)
//   /slam/path      nav_msgs/msg/Path               the corrected trajectory of the laser
//   /odom/path      nav_msgs/msg/Path               the odometry's
//   /loop_closures  visualization_msgs/msg/MarkerArray   the used closures, a LINE_LIST between submap
//   centres /tf             tf2_msgs/msg/TFMessage          map -> laser at every scan (the corrected pose)
//   /scan           sensor_msgs/msg/PointCloud2     every scan's points in the laser frame, at its time
// Each schema is the message's full definition with its dependencies (ros2msg), so a reader needs no ROS
// install. Unchunked and without a summary section (readers stream it); written atomically. `locate` writes
// its answers likewise (write_located_mcap).
#pragma once

#include <filesystem>
#include <utility>
#include <vector>

#include "core/maps/grid_map.h"
#include "core/maps/scan.h"

namespace partslam::io {

struct SlamResultLayers {
  const GridMap* map = nullptr;      ///< the corrected map (required)
  const Scans* corrected = nullptr;  ///< scans at their corrected poses (required): the path, /tf and /scan
  const Scans* odometry = nullptr;   ///< the log's own poses for the odometry's path (optional)
  std::vector<std::pair<Vec2, Vec2>> closures;  ///< the used closures, map frame
};

/// Writes the layers to `path` (see above). Throws InputError for a missing map or scans, an empty scan list
/// or a file that cannot be written.
void write_result_mcap(const std::filesystem::path& path, const SlamResultLayers& layers);

/// One answer of `locate`: when (the stretch's first scan), where the robot is in the map, and whether
/// confident.
struct LocatedPose {
  double stamp = 0;
  Pose2 robot;
  bool confident = false;
};

/// `locate --every --mcap`: /map (the building map), /located/path (nav_msgs/msg/Path of the answers in
/// travel order) and /located (a MarkerArray SPHERE_LIST, green confident, orange low, as --plot draws them).
/// Throws InputError for no answer or a file that cannot be written.
void write_located_mcap(const std::filesystem::path& path, const GridMap& map,
                        const std::vector<LocatedPose>& located);

}  // namespace partslam::io
