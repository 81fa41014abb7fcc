// The messages of a bag that become scans, the same for ROS 1 and ROS 2 bags: laser scans, odometry and frame
// transforms, as the readers (io/logs/ros_bag_messages.h, io/logs/ros2_bag.cc) decode them and
// io/logs/bag_selection.h chooses them. Plain standard-library types only: the one translation unit that includes
// ROS headers (compiled as C++17) includes this header too.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace partslam::io::rosbag_messages {

/// A frame id as tf2 spells it: without the leading '/' that ROS 1 allowed.
inline std::string bare_frame(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

struct LaserScanMessage {
  double stamp = 0.0;  ///< header.stamp [s]
  double angle_min = 0.0, angle_increment = 0.0, range_min = 0.0, range_max = 0.0;
  std::vector<float> ranges;
  std::string frame_id;  ///< header.frame_id, without a leading '/'
};

struct OdometryMessage {
  double stamp = 0.0;
  double x = 0.0, y = 0.0;
  double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
};

/// A transform between two frames other than odom -> base (e.g. base_link -> laser on /tf_static): the pose of
/// `child` in `parent`.
struct FrameTransform {
  std::string parent, child;  ///< without a leading '/'
  double x = 0.0, y = 0.0;
  double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
};

struct BagMessages {
  std::string scan_topic;      ///< the first sensor_msgs/LaserScan topic; only its messages are kept
  std::string odometry_topic;  ///< the first nav_msgs/Odometry topic; without one, the tf2_msgs/TFMessage topic
                               ///< (e.g. /tf) whose odom -> base_link (or base_footprint) transforms pose the
                               ///< scans, named "TOPIC (odom -> CHILD)"; empty when there is neither
  std::string base_frame;      ///< the frame the odometry poses (Odometry child_frame_id, or the /tf child)
  std::vector<LaserScanMessage> scans;
  std::vector<OdometryMessage> odometry;
  std::vector<FrameTransform> transforms;  ///< the first of every other parent -> child pair, on any tf topic
  /// What was read past: a bag cut short or without its index, damaged chunks or messages skipped (skip_damaged).
  /// Without the file's name (the caller adds it).
  std::vector<std::string> warnings;
};

/// Why a bag could not be read (the caller names the file).
struct BagError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace partslam::io::rosbag_messages
