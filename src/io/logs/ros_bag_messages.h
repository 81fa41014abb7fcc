// A ROS 1 bag's messages, read with librosbag by the one translation unit that includes ROS headers
// (io/logs/ros_bag_messages.cc, compiled as C++17: ROS 1's generated messages use std::allocator<void>::rebind,
// which C++20 removed), for io/logs/ros_bag.h to turn into scans. Plain standard-library types only, so this
// header compiles in both.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/logs/bag_messages.h"

namespace partslam::io::rosbag_messages {

/// Reads the messages in bag order, chosen as io/logs/bag_selection.h says (scan_topic / odom_topic: the topics asked
/// for, empty: the first); stops with BagError once more than max_ranges ranges were read. A bag that fails
/// check_bag_structure is read by walk_bag_chunks, in the order of the messages' times: one whose index is
/// missing or cut off (a recording cut short before its index, or never closed) up to its last whole chunk, with
/// a warning. Damage elsewhere (a corrupt chunk or chunk length in a bag whose file goes on to its index, a
/// message whose arrays do not fit it, a damaged index) throws BagError naming the place, or with skip_damaged is
/// skipped and counted in a warning, every other whole chunk read (found from the index when it is readable).
BagMessages read_bag_messages(const std::string& path, std::size_t max_ranges, bool skip_damaged = false,
                              const std::string& scan_topic = "", const std::string& odom_topic = "");

/// Writes the scans on /scan (frame "laser") and the odometry on /odom (nav_msgs/Odometry, frame odom ->
/// base_link) or, with as_tf, as /tf transforms odom -> base_link, and the other transforms once on /tf_static:
/// bags like a robot records them, for tests and conversions.
void write_bag_messages(const std::string& path, const BagMessages& messages, bool as_tf);

}  // namespace partslam::io::rosbag_messages
