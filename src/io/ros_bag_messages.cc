#include "io/ros_bag_messages.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>

namespace partslam::io::rosbag_messages {

BagMessages read_bag_messages(const std::string& path, std::size_t max_ranges) {
  BagMessages out;
  std::size_t ranges = 0;
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    for (const rosbag::MessageInstance& m : view) {
      if (m.getDataType() == "sensor_msgs/LaserScan") {
        if (out.scan_topic.empty()) out.scan_topic = m.getTopic();
        if (m.getTopic() != out.scan_topic) continue;
        const auto msg = m.instantiate<sensor_msgs::LaserScan>();
        if (!msg) continue;
        ranges += msg->ranges.size();
        if (ranges > max_ranges)
          throw BagError("more than " + std::to_string(max_ranges) + " ranges (LogReadOptions.max_points)");
        out.scans.push_back({msg->header.stamp.toSec(), msg->angle_min, msg->angle_increment, msg->range_min,
                             msg->range_max, msg->ranges});
      } else if (m.getDataType() == "nav_msgs/Odometry") {
        if (out.odometry_topic.empty()) out.odometry_topic = m.getTopic();
        if (m.getTopic() != out.odometry_topic) continue;
        const auto msg = m.instantiate<nav_msgs::Odometry>();
        if (!msg) continue;
        const auto& p = msg->pose.pose;
        out.odometry.push_back({msg->header.stamp.toSec(), p.position.x, p.position.y, p.orientation.x,
                                p.orientation.y, p.orientation.z, p.orientation.w});
      }
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(std::string("not a readable ROS 1 bag (") + e.what() + ")");
  } catch (const ros::Exception& e) {
    throw BagError(std::string("cannot decode a message (") + e.what() + ")");
  }
  return out;
}

}  // namespace partslam::io::rosbag_messages
