#include "io/ros_bag_messages.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cstdint>
#include <cstring>

namespace partslam::io::rosbag_messages {

namespace {

std::string bare_frame(const std::string& frame) { return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame; }

// Walks a message's serialized bytes. ROS's deserializer sizes a vector from its length field before checking that
// the message holds that much (a 20-byte LaserScan claiming 2^29 ranges allocated 2 GB: fuzz_ros_bag), so the
// lengths of the messages with arrays are checked here first.
struct Cursor {
  const std::uint8_t* p;
  std::size_t left;
  bool skip(std::size_t n) {
    if (n > left) return false;
    p += n, left -= n;
    return true;
  }
  bool length(std::uint32_t& n) {
    if (left < 4) return false;
    std::memcpy(&n, p, 4);  // little-endian, as ROS 1 serializes
    p += 4, left -= 4;
    return true;
  }
  bool string() {
    std::uint32_t n = 0;
    return length(n) && skip(n);
  }
  /// An array of n elements of at least element_bytes each: n must fit in what is left; skips it when each element
  /// is exactly element_bytes (fixed), else only checks n.
  bool array(std::size_t element_bytes, std::uint32_t& n, bool fixed) {
    return length(n) && n <= left / element_bytes && (!fixed || skip(n * element_bytes));
  }
  bool header() { return skip(12) && string(); }  // seq, stamp, frame_id
};

bool laser_scan_fits(Cursor c) {
  std::uint32_t n = 0;
  return c.header() && c.skip(7 * 4) && c.array(4, n, true) && c.array(4, n, true);  // ranges, intensities
}

bool tf_message_fits(Cursor c) {
  std::uint32_t n = 0;
  constexpr std::size_t kMinTransform = 12 + 4 + 4 + 7 * 8;  // header without frame_id, child_frame_id, transform
  if (!c.array(kMinTransform, n, false)) return false;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (!c.header() || !c.string() || !c.skip(7 * 8)) return false;
  }
  return true;
}

// The message deserialized, after its array lengths were checked against its size; null for another message type.
template <typename T>
boost::shared_ptr<T> decode(const rosbag::MessageInstance& m, bool (*fits)(Cursor)) {
  if (!m.isType<T>()) return {};
  std::vector<std::uint8_t> bytes(m.size());
  ros::serialization::OStream out(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  m.write(out);
  if (!fits(Cursor{bytes.data(), bytes.size()}))
    throw BagError("a " + m.getDataType() + " message on " + m.getTopic() + " holds an array longer than the message");
  auto msg = boost::make_shared<T>();
  ros::serialization::IStream in(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, *msg);
  return msg;
}

}  // namespace

BagMessages read_bag_messages(const std::string& path, std::size_t max_ranges) {
  BagMessages out;
  std::string tf_topic, tf_child;
  std::vector<OdometryMessage> tf_odometry;  // used when the bag has no Odometry topic
  std::size_t ranges = 0;
  check_bag_structure(path);
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    for (const rosbag::MessageInstance& m : view) {
      if (m.getDataType() == "sensor_msgs/LaserScan") {
        if (out.scan_topic.empty()) out.scan_topic = m.getTopic();
        if (m.getTopic() != out.scan_topic) continue;
        const auto msg = decode<sensor_msgs::LaserScan>(m, laser_scan_fits);
        if (!msg) continue;
        ranges += msg->ranges.size();
        if (ranges > max_ranges)
          throw BagError("more than " + std::to_string(max_ranges) + " ranges (LogReadOptions.max_points)");
        out.scans.push_back({msg->header.stamp.toSec(), msg->angle_min, msg->angle_increment, msg->range_min,
                             msg->range_max, msg->ranges, bare_frame(msg->header.frame_id)});
      } else if (m.getDataType() == "nav_msgs/Odometry") {
        if (out.odometry_topic.empty()) out.odometry_topic = m.getTopic();
        if (m.getTopic() != out.odometry_topic) continue;
        const auto msg = m.instantiate<nav_msgs::Odometry>();
        if (!msg) continue;
        if (out.base_frame.empty()) out.base_frame = bare_frame(msg->child_frame_id);
        const auto& p = msg->pose.pose;
        out.odometry.push_back({msg->header.stamp.toSec(), p.position.x, p.position.y, p.orientation.x,
                                p.orientation.y, p.orientation.z, p.orientation.w});
      } else if (m.getDataType() == "tf2_msgs/TFMessage") {
        const auto msg = decode<tf2_msgs::TFMessage>(m, tf_message_fits);
        if (!msg) continue;
        for (const geometry_msgs::TransformStamped& t : msg->transforms) {
          const std::string child = bare_frame(t.child_frame_id), parent = bare_frame(t.header.frame_id);
          if (parent != "odom" || (child != "base_link" && child != "base_footprint")) {
            const auto same = [&](const FrameTransform& f) { return f.parent == parent && f.child == child; };
            if (std::none_of(out.transforms.begin(), out.transforms.end(), same)) {
              const auto& q = t.transform.rotation;
              out.transforms.push_back({parent, child, t.transform.translation.x, t.transform.translation.y, q.x, q.y,
                                        q.z, q.w});
            }
            continue;
          }
          if (!tf_topic.empty() && m.getTopic() != tf_topic) continue;
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
    out.base_frame = tf_child;
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
    if (!messages.transforms.empty()) {
      tf2_msgs::TFMessage msg;
      const ros::Time stamp(messages.scans.empty() ? 1.0 : messages.scans.front().stamp);
      for (const FrameTransform& f : messages.transforms) {
        geometry_msgs::TransformStamped t;
        t.header.stamp = stamp;
        t.header.frame_id = f.parent;
        t.child_frame_id = f.child;
        t.transform.translation.x = f.x, t.transform.translation.y = f.y;
        t.transform.rotation.x = f.qx, t.transform.rotation.y = f.qy, t.transform.rotation.z = f.qz;
        t.transform.rotation.w = f.qw;
        msg.transforms.push_back(t);
      }
      bag.write("/tf_static", stamp, msg);
    }
    for (const LaserScanMessage& s : messages.scans) {
      write_odometry_until(s.stamp);
      sensor_msgs::LaserScan msg;
      msg.header.stamp = ros::Time(s.stamp);
      msg.header.frame_id = s.frame_id.empty() ? "laser" : s.frame_id;
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
