// Reading ROS 2 messages from their CDR bytes (OMG CDR as rosbag2 stores them: a 4-byte encapsulation header
// naming the byte order, then the fields, each primitive aligned to its size from the end of that header). Only the
// three message types a scan source needs are decoded, into the plain records of io/logs/ros_bag_messages.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/logs/bag_messages.h"

namespace partslam::io::cdr {

/// Walks one CDR-encoded message; every read is checked against its size. Throws BagError ("... at byte N")
/// for an unknown encapsulation (only plain CDR, little and big endian) or a read past the end.
class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes);

  std::int32_t int32();
  std::uint32_t uint32();
  float float32();
  double float64();
  std::string string();
  /// A sequence length, checked to fit in what is left at element_bytes per element.
  std::uint32_t sequence(std::size_t element_bytes);
  void skip_float64s(std::size_t n);
  bool little_endian() const { return little_; }
  /// Bytes not read yet.
  std::size_t left() const { return bytes_.size() - at_; }

 private:
  void align(std::size_t n);
  const std::uint8_t* take(std::size_t n);
  template <typename T>
  T number();

  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 4;  ///< the next byte; alignment counts from 4, the end of the encapsulation header
  bool little_ = true;
};

/// sensor_msgs/msg/LaserScan. Throws BagError for a malformed message.
rosbag_messages::LaserScanMessage laser_scan(std::span<const std::uint8_t> bytes);

/// nav_msgs/msg/Odometry (the pose part) and its child_frame_id.
rosbag_messages::OdometryMessage odometry(std::span<const std::uint8_t> bytes, std::string& child_frame);

/// One geometry_msgs/msg/TransformStamped of a tf2_msgs/msg/TFMessage.
struct StampedTransform {
  double stamp = 0.0;
  rosbag_messages::FrameTransform transform;  ///< frames without a leading '/'
};

/// tf2_msgs/msg/TFMessage.
std::vector<StampedTransform> tf_message(std::span<const std::uint8_t> bytes);

}  // namespace partslam::io::cdr
