// The raw messages of a ROS 1 bag that io/ros_bag.h turns into scans, read by the one translation unit that
// includes ROS headers (compiled as C++17: ROS 1's generated messages use std::allocator<void>::rebind, which
// C++20 removed). Plain standard-library types only, so this header compiles in both.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace partslam::io::rosbag_messages {

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
};

/// Why a bag could not be read (the caller names the file).
struct BagError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Largest chunk of a bag read, compressed or not [bytes] (rosbag record writes 768 KB chunks).
inline constexpr std::uint32_t kMaxChunkBytes = 256u << 20;

/// Checks the structure of a ROS bag 2.0 file the way librosbag reads it (bag header, index section, chunks, index
/// entries: every length and offset within the file or its chunk, chunks of at most kMaxChunkBytes, bz2 and lz4
/// chunks decompressing to their size); throws BagError naming the first problem. read_bag_messages calls it
/// first: librosbag trusts all of these. (io/ros_bag_check.cc; no ROS headers)
void check_bag_structure(const std::string& path);

/// Reads the messages in bag order; stops with BagError once more than max_ranges ranges were read.
BagMessages read_bag_messages(const std::string& path, std::size_t max_ranges);

/// Writes the scans on /scan (frame "laser") and the odometry on /odom (nav_msgs/Odometry, frame odom ->
/// base_link) or, with as_tf, as /tf transforms odom -> base_link, and the other transforms once on /tf_static:
/// bags like a robot records them, for tests and conversions.
void write_bag_messages(const std::string& path, const BagMessages& messages, bool as_tf);

}  // namespace partslam::io::rosbag_messages
