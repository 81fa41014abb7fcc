// Tested by: io/logs/ros_bag_test.cc, io/logs/ros_bag_check_test.cc

#include "io/logs/ros_bag_messages.h"
#include "io/logs/bag_selection.h"
#include "io/logs/ros_bag_check.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <new>
#include <string_view>

namespace partslam::io::rosbag_messages {

namespace {


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

// The message deserialized from its bytes, after its array lengths were checked against its size.
template <typename T>
T decode(const std::vector<std::uint8_t>& bytes, const std::string& datatype, const std::string& topic,
         bool (*fits)(Cursor)) {
  if (fits != nullptr && !fits(Cursor{bytes.data(), bytes.size()}))
    throw BagError("a " + datatype + " message on " + topic + " holds an array longer than the message");
  T msg;
  ros::serialization::IStream in(const_cast<std::uint8_t*>(bytes.data()), static_cast<std::uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, msg);
  return msg;
}

template <typename T>
bool is_type(const std::string& datatype, const std::string& md5sum) {
  return datatype == ros::message_traits::DataType<T>::value() &&
         (md5sum == "*" || md5sum == ros::message_traits::MD5Sum<T>::value());
}

// Turns the bag's messages, one at a time and in bag order, into BagMessages: decoded here, chosen by the rules
// every bag shares (io/logs/bag_selection.h).
class Collector {
 public:
  Collector(std::size_t max_ranges, bool skip_damaged, const std::string& scan_topic, const std::string& odom_topic)
      : selection_(max_ranges, scan_topic, odom_topic), skip_damaged_(skip_damaged) {}

  /// One message; a damaged one throws BagError, or with skip_damaged is counted.
  void add(const std::string& topic, const std::string& datatype, const std::string& md5sum,
           const std::vector<std::uint8_t>& bytes) {
    selection_.note_topic(topic, datatype);
    try {
      add_message(topic, datatype, md5sum, bytes);
    } catch (const ros::Exception& e) {
      damaged(std::string("cannot decode a message (") + e.what() + ")");
    } catch (const BagError& e) {
      if (std::string(e.what()).rfind("more than ", 0) == 0) throw;  // the max_ranges limit
      damaged(e.what());
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {  // ROS's time arithmetic throws a bare std::runtime_error
      damaged(std::string("cannot decode a message (") + e.what() + ")");
    }
  }

  BagMessages finish() {
    BagMessages out = std::move(selection_).finish();
    if (damaged_ > 0)
      out.warnings.push_back("skipped " + std::to_string(damaged_) + " damaged message(s) (skip_damaged); the first: " +
                             first_damage_);
    return out;
  }

 private:
  void damaged(const std::string& what) {
    if (!skip_damaged_) throw BagError(what);
    if (damaged_++ == 0) first_damage_ = what;
  }

  void add_message(const std::string& topic, const std::string& datatype, const std::string& md5sum,
                   const std::vector<std::uint8_t>& bytes) {
    if (is_type<sensor_msgs::LaserScan>(datatype, md5sum)) {
      if (!selection_.wants_scan(topic)) return;
      const auto msg = decode<sensor_msgs::LaserScan>(bytes, datatype, topic, laser_scan_fits);
      selection_.add_scan(topic, {msg.header.stamp.toSec(), msg.angle_min, msg.angle_increment, msg.range_min,
                                  msg.range_max, msg.ranges, bare_frame(msg.header.frame_id)});
    } else if (is_type<nav_msgs::Odometry>(datatype, md5sum)) {
      if (!selection_.wants_odometry(topic)) return;
      const auto msg = decode<nav_msgs::Odometry>(bytes, datatype, topic, nullptr);
      const auto& p = msg.pose.pose;
      selection_.add_odometry(topic, bare_frame(msg.child_frame_id),
                              {msg.header.stamp.toSec(), p.position.x, p.position.y, p.orientation.x,
                               p.orientation.y, p.orientation.z, p.orientation.w});
    } else if (is_type<tf2_msgs::TFMessage>(datatype, md5sum)) {
      const auto msg = decode<tf2_msgs::TFMessage>(bytes, datatype, topic, tf_message_fits);
      for (const geometry_msgs::TransformStamped& t : msg.transforms) {
        const auto& q = t.transform.rotation;
        selection_.add_transform(topic, t.header.stamp.toSec(),
                                 {bare_frame(t.header.frame_id), bare_frame(t.child_frame_id),
                                  t.transform.translation.x, t.transform.translation.y, q.x, q.y, q.z, q.w});
      }
    }
  }

  BagSelection selection_;
  const bool skip_damaged_;
  std::size_t damaged_ = 0;
  std::string first_damage_;
};

const std::vector<std::string>& kept_types() {
  static const std::vector<std::string> types{ros::message_traits::DataType<sensor_msgs::LaserScan>::value(),
                                              ros::message_traits::DataType<nav_msgs::Odometry>::value(),
                                              ros::message_traits::DataType<tf2_msgs::TFMessage>::value()};
  return types;
}

// A bag whose structure check failed (structure_error): its chunks walked record by record (walk_bag_chunks). A
// bag cut short before its index or never closed is read up to its last whole record, with a warning; one whose
// index alone is damaged, or damaged before its index, only with skip_damaged (the other whole chunks read).
BagMessages read_without_index(const std::string& path, std::size_t max_ranges, bool skip_damaged,
                               const std::string& scan_topic, const std::string& odom_topic,
                               const std::string& structure_error) {
  // Serialized LaserScans take about 4 bytes a range (8 allows for their headers and intensities); 256 MB more for
  // the odometry and transforms of a long recording (and a bound on a hostile file's millions of tiny messages).
  const std::size_t max_bytes = max_ranges * 8 + (std::size_t{256} << 20);
  ChunkWalk walk = walk_bag_chunks(path, kept_types(), skip_damaged, max_bytes);
  const bool index_gone = walk.index_pos == 0 || walk.index_pos >= walk.file_size;
  if (walk.cut_at == 0 && walk.damaged == 0 && !index_gone && !skip_damaged) throw BagError(structure_error);
  // In the order librosbag's View gives: by time, file order among equal times.
  std::stable_sort(walk.messages.begin(), walk.messages.end(),
                   [](const RawMessage& a, const RawMessage& b) { return a.time < b.time; });
  Collector collector(max_ranges, skip_damaged, scan_topic, odom_topic);
  for (const RawMessage& m : walk.messages) {
    const BagConnection& c = walk.connections[m.connection];
    collector.add(c.topic, c.datatype, c.md5sum, m.data);
  }
  BagMessages out = collector.finish();
  std::vector<std::string> warnings;
  const std::string read = "read the " + std::to_string(out.scans.size()) + " scans of its " +
                           std::to_string(walk.chunks) + " whole chunks";
  if (walk.cut_at != 0) {
    warnings.push_back("the file ends mid-record after byte " + std::to_string(walk.cut_at) +
                       " (the record starting there runs past the end at byte " + std::to_string(walk.file_size) +
                       "); " + read + " before it, as 'rosbag reindex' would");
  } else if (walk.index_pos == 0) {
    warnings.push_back("the bag has no index (the recording was not closed); " + read + " without it");
  } else if (index_gone) {
    warnings.push_back("the file ends at byte " + std::to_string(walk.file_size) + ", before its index at byte " +
                       std::to_string(walk.index_pos) + " (cut short); " + read + " before it");
  } else if (walk.damaged == 0) {
    warnings.push_back("the bag's index is damaged (" + structure_error + "); " + read + " without it (skip_damaged)");
  }
  if (walk.damaged > 0) {
    std::string w = "skipped " + std::to_string(walk.damaged) + " damaged record(s) (skip_damaged); the first: " +
                    walk.first_damage;
    if (warnings.empty()) {  // a bag closed with its index: say what was read around the damage
      w += "; " + read;
      if (walk.indexed_chunks > 0) w += " (of the " + std::to_string(walk.indexed_chunks) + " its index lists)";
    }
    warnings.push_back(w);
  }
  if (walk.lost_at != 0)
    warnings.push_back("no chunk record was found after the damaged record at byte " + std::to_string(walk.lost_at) +
                       ": the rest of the file, to byte " + std::to_string(walk.file_size) + ", could not be read");
  out.warnings.insert(out.warnings.begin(), warnings.begin(), warnings.end());
  return out;
}

}  // namespace

BagMessages read_bag_messages(const std::string& path, std::size_t max_ranges, bool skip_damaged,
                              const std::string& scan_topic, const std::string& odom_topic) {
  try {
    check_bag_structure(path);
  } catch (const BagError& e) {
    return read_without_index(path, max_ranges, skip_damaged, scan_topic, odom_topic, e.what());
  }
  Collector collector(max_ranges, skip_damaged, scan_topic, odom_topic);
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    std::vector<std::uint8_t> bytes;
    for (const rosbag::MessageInstance& m : view) {
      const std::string& datatype = m.getDataType();
      if (std::find(kept_types().begin(), kept_types().end(), datatype) == kept_types().end()) continue;
      bytes.resize(m.size());
      ros::serialization::OStream out(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
      m.write(out);
      collector.add(m.getTopic(), datatype, m.getMD5Sum(), bytes);
    }
  } catch (const rosbag::BagException& e) {
    throw BagError(std::string("not a readable ROS 1 bag (") + e.what() + ")");
  } catch (const ros::Exception& e) {
    throw BagError(std::string("cannot decode a message (") + e.what() + ")");
  } catch (const BagError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    // Anything else librosbag lets out (its time arithmetic throws a bare std::runtime_error) is damage the
    // structure check did not foresee: the bag is read without librosbag, as a bag with a damaged index is.
    return read_without_index(path, max_ranges, skip_damaged, scan_topic, odom_topic,
                              std::string("not a readable ROS 1 bag (librosbag: ") + e.what() + ")");
  }
  return collector.finish();
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
