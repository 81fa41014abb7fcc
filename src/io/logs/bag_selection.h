// Which of a bag's messages pose the scans, the same for ROS 1 and ROS 2 bags: the scans are the first
// LaserScan topic's messages (or those of the topic asked for), posed by the first Odometry topic (or the one
// asked for) or, without one, by a tf topic's odom -> base_link (or base_footprint) transforms; every other
// transform is kept once per parent -> child pair for the laser's mount. A reader decodes messages in time order
// and hands them to a BagSelection, which fills the BagMessages of io/logs/ros_bag_messages.h.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/logs/bag_messages.h"

namespace partslam::io::rosbag_messages {

class BagSelection {
 public:
  /// scan_topic / odom_topic: the topics asked for (empty: the first of their type). Throws BagError once more
  /// than max_ranges ranges were added.
  BagSelection(std::size_t max_ranges, std::string scan_topic, std::string odom_topic);

  /// True when a LaserScan message on this topic is kept (the reader may skip decoding the others).
  bool wants_scan(const std::string& topic);
  void add_scan(const std::string& topic, LaserScanMessage message);
  /// True when an Odometry message on this topic is kept.
  bool wants_odometry(const std::string& topic);
  void add_odometry(const std::string& topic, const std::string& child_frame, const OdometryMessage& message);
  /// One transform of a TFMessage on topic, stamped.
  void add_transform(const std::string& topic, double stamp, const FrameTransform& transform);
  /// Notes a topic of any type (for the error that names the bag's topics).
  void note_topic(const std::string& topic, const std::string& type);

  /// The selection; throws BagError when a topic asked for holds no message of its type.
  BagMessages finish() &&;

 private:
  std::size_t max_ranges_, ranges_ = 0;
  std::string scan_topic_, odom_topic_;
  bool scan_asked_, odom_asked_;
  BagMessages out_;
  std::string tf_topic_, tf_child_;
  std::vector<OdometryMessage> tf_odometry_;  // used when the bag has no Odometry topic
  std::vector<std::string> topics_;           // "topic (type)", in order of appearance
};

}  // namespace partslam::io::rosbag_messages
