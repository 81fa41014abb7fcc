#include "io/logs/cdr.h"

#include <bit>
#include <cstring>

namespace partslam::io::cdr {
namespace {

using rosbag_messages::bare_frame;
using rosbag_messages::BagError;


// std_msgs/msg/Header: builtin_interfaces/Time stamp (int32 sec, uint32 nanosec), string frame_id.
double header(Reader& r, std::string& frame_id) {
  const std::int32_t sec = r.int32();
  const std::uint32_t nanosec = r.uint32();
  frame_id = bare_frame(r.string());
  return static_cast<double>(sec) + 1e-9 * static_cast<double>(nanosec);
}

}  // namespace

Reader::Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {
  if (bytes.size() < 4) throw BagError("a CDR message shorter than its 4-byte encapsulation header");
  // The header's first two bytes: 0x0000 plain CDR big endian, 0x0001 little endian (parameter lists and XCDR2
  // are not used by ROS 2's default middleware for these messages).
  if (bytes[0] != 0 || bytes[1] > 1)
    throw BagError("CDR encapsulation " + std::to_string(bytes[0]) + "," + std::to_string(bytes[1]) +
                   " is not plain CDR (0,0 big endian or 0,1 little endian)");
  little_ = bytes[1] == 1;
}

void Reader::align(std::size_t n) {
  const std::size_t pad = (n - (at_ - 4) % n) % n;
  take(pad);
}

const std::uint8_t* Reader::take(std::size_t n) {
  if (n > left())
    throw BagError("a CDR message ends early: " + std::to_string(n) + " bytes wanted at byte " + std::to_string(at_) +
                   " of " + std::to_string(bytes_.size()));
  const std::uint8_t* p = bytes_.data() + at_;
  at_ += n;
  return p;
}

template <typename T>
T Reader::number() {
  align(sizeof(T));
  std::uint8_t raw[sizeof(T)];
  std::memcpy(raw, take(sizeof(T)), sizeof(T));
  if (little_ != (std::endian::native == std::endian::little)) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, raw, sizeof(T));
  return value;
}

std::int32_t Reader::int32() { return number<std::int32_t>(); }
std::uint32_t Reader::uint32() { return number<std::uint32_t>(); }
float Reader::float32() { return number<float>(); }
double Reader::float64() { return number<double>(); }

std::string Reader::string() {
  const std::uint32_t n = uint32();  // the length counts the terminating NUL
  const char* p = reinterpret_cast<const char*>(take(n));
  return std::string(p, n > 0 && p[n - 1] == '\0' ? n - 1 : n);
}

std::uint32_t Reader::sequence(std::size_t element_bytes) {
  const std::uint32_t n = uint32();
  if (element_bytes > 0 && n > left() / element_bytes)
    throw BagError("a CDR sequence of " + std::to_string(n) + " elements is longer than its message (byte " +
                   std::to_string(at_) + ")");
  return n;
}

void Reader::skip_float64s(std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) float64();
}

rosbag_messages::LaserScanMessage laser_scan(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  rosbag_messages::LaserScanMessage m;
  m.stamp = header(r, m.frame_id);
  m.angle_min = r.float32();
  r.float32();  // angle_max
  m.angle_increment = r.float32();
  r.float32();  // time_increment
  r.float32();  // scan_time
  m.range_min = r.float32();
  m.range_max = r.float32();
  m.ranges.resize(r.sequence(4));
  for (float& v : m.ranges) v = r.float32();
  return m;  // intensities are not used
}

rosbag_messages::OdometryMessage odometry(std::span<const std::uint8_t> bytes, std::string& child_frame) {
  Reader r(bytes);
  rosbag_messages::OdometryMessage m;
  std::string frame_id;
  m.stamp = header(r, frame_id);
  child_frame = bare_frame(r.string());
  m.x = r.float64();
  m.y = r.float64();
  r.float64();  // z
  m.qx = r.float64();
  m.qy = r.float64();
  m.qz = r.float64();
  m.qw = r.float64();
  return m;  // covariance and twist are not used
}

std::vector<StampedTransform> tf_message(std::span<const std::uint8_t> bytes) {
  Reader r(bytes);
  // The smallest TransformStamped: stamp 8, two empty strings 8, seven float64 56 (after alignment).
  const std::uint32_t n = r.sequence(72);
  std::vector<StampedTransform> out(n);
  for (StampedTransform& t : out) {
    t.stamp = header(r, t.transform.parent);
    t.transform.child = bare_frame(r.string());
    t.transform.x = r.float64();
    t.transform.y = r.float64();
    r.float64();  // z
    t.transform.qx = r.float64();
    t.transform.qy = r.float64();
    t.transform.qz = r.float64();
    t.transform.qw = r.float64();
  }
  return out;
}

}  // namespace partslam::io::cdr
