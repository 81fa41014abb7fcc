// ROS 1 bags as a scan source, read with Debian's rosbag_storage library:
// sensor_msgs/LaserScan messages become Scans (points of the beams with range_min < r < min(range_max,
// LogReadOptions::max_usable_range), less the scanner's no-return code (io/logs/no_return_codes.h); num_beams =
// ranges.size(); timestamp = header.stamp), posed by the
// nav_msgs/Odometry messages interpolated at each scan's stamp (linear in x, y, the short way in theta) in both
// pose slots, times the laser's mount on the robot when the bag's transforms give one (base_link -> the scans'
// frame, e.g. on /tf_static, composed in 3D: a laser mounted upside down has its points mirrored; the benchmark's
// .clf files, made from these bags, do not apply it). A bag without
// nav_msgs/Odometry is posed by its /tf odom -> base_link (or base_footprint) transforms instead. Scans outside the odometry's time span take the nearest odometry; a bag with neither gives
// every scan the identity pose (the front end then predicts a standing robot). A bag cut short (its index, written
// last, gone) is read up to its last whole chunk by walking its records, with a warning (RosBagLog::warnings). A
// complete bag (its index within the file) damaged in the middle is an error naming the byte, or with
// LogReadOptions::skip_damaged is read around the damage, every other whole chunk found from its index.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/maps/scan.h"
#include "io/logs/log_read_options.h"

namespace partslam::io {

/// True for a path ending in ".bag".
bool is_ros_bag(const std::filesystem::path& path);

struct RosBagLog {
  Scans scans;
  std::string scan_topic;      ///< the LaserScan topic read (the first one when there are several)
  std::string odometry_topic;  ///< the Odometry topic read, or "TOPIC (odom -> CHILD)" for /tf; empty: neither
  std::size_t odometry_messages = 0;
  /// The laser's pose on the robot, from the bag's transforms between the odometry's base frame (base_link) and
  /// the scans' frame (e.g. base_link -> laser on /tf_static); scans are posed at odometry * T_base_laser.
  /// Identity, with laser_frame empty, when the bag has no such chain.
  Pose2 T_base_laser;
  std::string laser_frame;
  /// The mount turns the laser upside down (the transforms roll or pitch it by pi): its beams, seen from above,
  /// turn clockwise, so each point's y was mirrored before T_base_laser applies (a tilted scan plane is
  /// projected onto the base's, with a warning).
  bool laser_upside_down = false;
  /// What was read past, "<file>: ..." each: a bag cut short or never closed (read up to its last whole chunk, as
  /// `rosbag reindex` would), damaged chunks or messages skipped with LogReadOptions::skip_damaged.
  std::vector<std::string> warnings;
};

namespace rosbag_messages {
struct BagMessages;
}

/// The scans of a bag's selected messages (ROS 1 or ROS 2, io/logs/bag_selection.h), posed as described above. name
/// prefixes every error. Throws InputError for a bag without scans, a scan with non-finite fields, or an
/// implausible odometry pose.
RosBagLog scans_from_bag_messages(const rosbag_messages::BagMessages& messages, const LogReadOptions& options,
                                  const std::string& name);

/// Throws InputError naming the file for a missing or foreign file, damage before the end of the file (a corrupt
/// chunk, chunk length or message, a damaged index; unless options.skip_damaged: then skipped and counted), a scan
/// with non-finite fields, or more than options.max_points valid beams. A bag cut short (its file ending before its
/// index) is read up to its last whole chunk, with a warning. A bag without LaserScan messages gives no scans
/// (load_scan_source, io/logs/scan_source.h, refuses it).
RosBagLog read_ros_bag(const std::filesystem::path& path, const LogReadOptions& options = {});

}  // namespace partslam::io
