// ROS 2 bags (rosbag2) as a scan source: MCAP files (*.mcap, the default storage since Iron), SQLite files
// (*.db3, Humble's default), or a rosbag2 folder whose metadata.yaml lists them (split bags are read in order;
// per-message zstd compression is undone). Messages are CDR, little or big endian (io/logs/cdr.h). The scans are
// chosen and posed as for ROS 1 bags (io/logs/ros_bag.h, io/logs/bag_selection.h): sensor_msgs/msg/LaserScan posed by
// nav_msgs/msg/Odometry or tf odom -> base_link, times the laser's mount from the transforms. A recording cut
// short is read up to its last whole message with a warning; a damaged chunk or message in the middle is an
// error naming the place, or skipped and counted with LogReadOptions::skip_damaged.
#pragma once

#include <filesystem>

#include "io/logs/log_read_options.h"
#include "io/logs/ros_bag.h"

namespace partslam::io {

/// True for a path ending in ".mcap" or ".db3", a folder holding metadata.yaml, or that metadata.yaml itself.
bool is_ros2_bag(const std::filesystem::path& path);

/// Throws InputError naming the file (and byte offset or row) for a missing, foreign or damaged file, a topic asked
/// for that is not there, or more than options.max_points ranges. A bag without LaserScan messages gives no scans
/// (load_scan_source, io/logs/scan_source.h, refuses it).
RosBagLog read_ros2_bag(const std::filesystem::path& path, const LogReadOptions& options = {});

}  // namespace partslam::io
