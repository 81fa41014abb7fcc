#include "io/logs/cdr.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cstring>

namespace partslam::io::cdr {
namespace {

using ::testing::HasSubstr;
using rosbag_messages::BagError;

// A CDR writer for the tests: encapsulation header, then fields aligned to their size from its end.
class Writer {
 public:
  explicit Writer(bool little) : little_(little) { bytes_ = {0, static_cast<std::uint8_t>(little ? 1 : 0), 0, 0}; }
  template <typename T>
  Writer& put(T v) {
    while ((bytes_.size() - 4) % sizeof(T) != 0) bytes_.push_back(0);
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    if (little_ != (std::endian::native == std::endian::little)) std::reverse(raw, raw + sizeof(T));
    bytes_.insert(bytes_.end(), raw, raw + sizeof(T));
    return *this;
  }
  Writer& string(const std::string& s) {
    put<std::uint32_t>(static_cast<std::uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
    return *this;
  }
  Writer& header(std::int32_t sec, std::uint32_t nanosec, const std::string& frame) {
    return put(sec).put(nanosec).string(frame);
  }
  std::vector<std::uint8_t> bytes_;

 private:
  bool little_;
};

std::vector<std::uint8_t> laser_scan_bytes(bool little) {
  Writer w(little);
  w.header(1000, 500000000, "/laser");
  for (float f : {-1.5f, 1.5f, 0.5f, 0.0f, 0.1f, 0.05f, 30.0f}) w.put(f);  // angle_min .. range_max
  w.put<std::uint32_t>(3).put(1.0f).put(2.0f).put(3.5f);
  w.put<std::uint32_t>(0);  // intensities
  return w.bytes_;
}

TEST(Cdr, LaserScanInEitherByteOrder) {
  for (bool little : {true, false}) {
    const rosbag_messages::LaserScanMessage m = laser_scan(laser_scan_bytes(little));
    EXPECT_DOUBLE_EQ(m.stamp, 1000.5) << little;
    EXPECT_EQ(m.frame_id, "laser");  // the leading '/' dropped
    EXPECT_FLOAT_EQ(static_cast<float>(m.angle_min), -1.5f);
    EXPECT_FLOAT_EQ(static_cast<float>(m.angle_increment), 0.5f);
    EXPECT_FLOAT_EQ(static_cast<float>(m.range_min), 0.05f);
    EXPECT_FLOAT_EQ(static_cast<float>(m.range_max), 30.0f);
    EXPECT_THAT(m.ranges, ::testing::ElementsAre(1.0f, 2.0f, 3.5f));
  }
}

TEST(Cdr, OdometryAlignsItsDoublesToEightBytes) {
  for (bool little : {true, false}) {
    Writer w(little);
    w.header(7, 0, "odom").string("base_link");  // 4+4+4+5 (odom) +3 pad, 4+10 (base_link): doubles need padding
    for (double v : {1.25, -2.5, 0.0, 0.0, 0.0, 0.38268343236508984, 0.9238795325112867}) w.put(v);
    for (int i = 0; i < 36 + 6 + 36; ++i) w.put(0.0);
    std::string child;
    const rosbag_messages::OdometryMessage m = odometry(w.bytes_, child);
    EXPECT_EQ(child, "base_link");
    EXPECT_DOUBLE_EQ(m.stamp, 7.0);
    EXPECT_DOUBLE_EQ(m.x, 1.25);
    EXPECT_DOUBLE_EQ(m.y, -2.5);
    EXPECT_DOUBLE_EQ(m.qz, 0.38268343236508984);
    EXPECT_DOUBLE_EQ(m.qw, 0.9238795325112867);
  }
}

TEST(Cdr, TfMessageHoldsEveryTransform) {
  Writer w(true);
  w.put<std::uint32_t>(2);
  w.header(3, 0, "odom").string("base_link");
  for (double v : {1.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0}) w.put(v);
  w.header(3, 0, "base_link").string("/laser");
  for (double v : {0.04, 0.0, 0.1, 0.0, 0.0, 0.0, 1.0}) w.put(v);
  const std::vector<StampedTransform> t = tf_message(w.bytes_);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].transform.parent, "odom");
  EXPECT_EQ(t[0].transform.child, "base_link");
  EXPECT_DOUBLE_EQ(t[0].transform.y, 2.0);
  EXPECT_EQ(t[1].transform.child, "laser");
  EXPECT_DOUBLE_EQ(t[1].transform.x, 0.04);
}

TEST(Cdr, EveryCutOfAMessageIsAnErrorNotACrash) {
  const std::vector<std::uint8_t> whole = laser_scan_bytes(true);
  for (std::size_t n = 0; n + 4 < whole.size(); ++n) {  // the last 4 bytes are the empty intensities' length
    const std::vector<std::uint8_t> cut(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_THROW(laser_scan(cut), BagError) << n;
  }
}

TEST(Cdr, ASequenceLongerThanItsMessageIsRefusedBeforeAllocating) {
  Writer w(true);
  w.header(1, 0, "laser");
  for (int i = 0; i < 7; ++i) w.put(0.0f);
  w.put<std::uint32_t>(0x7fffffff);  // two billion ranges in a 60-byte message
  try {
    laser_scan(w.bytes_);
    FAIL() << "no error";
  } catch (const BagError& e) {
    EXPECT_THAT(e.what(), HasSubstr("longer than its message"));
  }
  Writer tf(false);
  tf.put<std::uint32_t>(1000000);
  EXPECT_THROW(tf_message(tf.bytes_), BagError);
}

TEST(Cdr, OnlyPlainCdrIsRead) {
  std::vector<std::uint8_t> b = laser_scan_bytes(true);
  b[1] = 3;  // PL_CDR_LE
  try {
    laser_scan(b);
    FAIL() << "no error";
  } catch (const BagError& e) {
    EXPECT_THAT(e.what(), HasSubstr("is not plain CDR"));
  }
  EXPECT_THROW(laser_scan(std::vector<std::uint8_t>{0, 1}), BagError);
}

}  // namespace
}  // namespace partslam::io::cdr
