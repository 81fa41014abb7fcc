#include "io/ros_bag_messages.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

namespace partslam::io::rosbag_messages {

namespace {

std::string bare_frame(const std::string& frame) { return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame; }

}  // namespace

BagMessages read_bag_messages(const std::string& path, std::size_t max_ranges) {
  BagMessages out;
  std::string tf_topic, tf_child;
  std::vector<OdometryMessage> tf_odometry;  // used when the bag has no Odometry topic
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
      } else if (m.getDataType() == "tf2_msgs/TFMessage" && (tf_topic.empty() || m.getTopic() == tf_topic)) {
        const auto msg = m.instantiate<tf2_msgs::TFMessage>();
        if (!msg) continue;
        for (const geometry_msgs::TransformStamped& t : msg->transforms) {
          const std::string child = bare_frame(t.child_frame_id);
          if (bare_frame(t.header.frame_id) != "odom" || (child != "base_link" && child != "base_footprint")) continue;
          if (tf_child.empty()) tf_topic = m.getTopic(), tf_child = child;
          if (child != tf_child) continue;
          const auto& q = t.transform.rotation;
          tf_odometry.push_back({t.header.stamp.toSec(), t.transform.translation.x, t.transform.translation.y, q.x,
                                 q.y, q.z, q.w});
        }
      }
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(std::string("not a readable ROS 1 bag (") + e.what() + ")");
  } catch (const ros::Exception& e) {
    throw BagError(std::string("cannot decode a message (") + e.what() + ")");
  }
  if (out.odometry_topic.empty() && !tf_odometry.empty()) {
    out.odometry_topic = tf_topic + " (odom -> " + tf_child + ")";
    out.odometry = std::move(tf_odometry);
  }
  return out;
}

void write_bag_messages(const std::string& path, const BagMessages& messages, bool as_tf) {
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    std::size_t o = 0;
    const auto write_odometry_until = [&](double t) {
      for (; o < messages.odometry.size() && messages.odometry[o].stamp <= t; ++o) {
        const OdometryMessage& m = messages.odometry[o];
        const ros::Time stamp(m.stamp);
        if (as_tf) {
          tf2_msgs::TFMessage msg;
          geometry_msgs::TransformStamped t;
          t.header.stamp = stamp;
          t.header.frame_id = "odom";
          t.child_frame_id = "base_link";
          t.transform.translation.x = m.x, t.transform.translation.y = m.y;
          t.transform.rotation.x = m.qx, t.transform.rotation.y = m.qy, t.transform.rotation.z = m.qz;
          t.transform.rotation.w = m.qw;
          msg.transforms.push_back(t);
          bag.write("/tf", stamp, msg);
        } else {
          nav_msgs::Odometry msg;
          msg.header.stamp = stamp;
          msg.header.frame_id = "odom";
          msg.child_frame_id = "base_link";
          msg.pose.pose.position.x = m.x, msg.pose.pose.position.y = m.y;
          msg.pose.pose.orientation.x = m.qx, msg.pose.pose.orientation.y = m.qy;
          msg.pose.pose.orientation.z = m.qz, msg.pose.pose.orientation.w = m.qw;
          bag.write("/odom", stamp, msg);
        }
      }
    };
    for (const LaserScanMessage& s : messages.scans) {
      write_odometry_until(s.stamp);
      sensor_msgs::LaserScan msg;
      msg.header.stamp = ros::Time(s.stamp);
      msg.header.frame_id = "laser";
      msg.angle_min = static_cast<float>(s.angle_min);
      msg.angle_increment = static_cast<float>(s.angle_increment);
      msg.angle_max = static_cast<float>(s.angle_min + s.angle_increment * (s.ranges.size() - 1));
      msg.range_min = static_cast<float>(s.range_min);
      msg.range_max = static_cast<float>(s.range_max);
      msg.ranges = s.ranges;
      bag.write("/scan", msg.header.stamp, msg);
    }
    write_odometry_until(1e300);
    bag.close();
  } catch (const rosbag::BagException& e) {
    throw BagError(std::string("cannot write the bag (") + e.what() + ")");
  }
}

}  // namespace partslam::io::rosbag_messages
