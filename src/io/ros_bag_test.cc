#include "io/ros_bag.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <fstream>
#include <optional>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/maps/submap.h"
#include "io/carmen_log.h"
#include "io/ros_bag_messages.h"
#include "io/scan_source.h"
#include "io/test_files.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;

// The benchmark bags of ../shared/data/bags against the .clf.gz files made from them: the same scans, the same
// points (ranges printed to 1 mm in the .clf; the bags' beams are pi/(n-1) apart), the same odometry poses, and
// so the same submaps.
struct BagCase {
  const char* log;
  bool same_order;  ///< whether the two files list the scans in the same order (intel's do not)
};

class RosBagRealData : public ::testing::TestWithParam<BagCase> {};

TEST_P(RosBagRealData, AgreesWithTheClfMadeFromIt) {
  const std::filesystem::path data = testing::shared_data();
  const std::string log = GetParam().log;
  const std::filesystem::path bag = data / "bags" / (log + ".clf2bag.bag");
  if (!std::filesystem::exists(bag)) GTEST_SKIP() << bag << " is absent";
  const RosBagLog from_bag = read_ros_bag(bag);
  EXPECT_EQ(from_bag.scan_topic, "/scan");
  EXPECT_EQ(from_bag.odometry_topic, "/odom");
  LogReadOptions clf_options;
  clf_options.flaser_spacing = FlaserSpacing::kPiOverNMinus1;
  clf_options.min_range = 0.1;  // the bags' range_min: shorter beams are invalid in ROS
  const Scans clf = read_carmen_log(data / log / (log + ".clf.gz"), clf_options).scans;
  ASSERT_EQ(from_bag.scans.size(), clf.size());
  // The two files do not list every scan in the same order (intel: runs of scans are permuted), so each bag
  // scan is paired with the clf scan within 50 places of it whose points are the same to 1.5 mm.
  std::vector<std::optional<std::size_t>> index(clf.size());
  for (std::size_t i = 0; i < clf.size(); ++i) {
    const Points2& a = from_bag.scans[i].points_laser;
    for (std::size_t j = i > 50 ? i - 50 : 0; j < std::min(clf.size(), i + 51) && !index[i]; ++j) {
      const Points2& b = clf[j].points_laser;
      bool same = a.size() == b.size();
      for (std::size_t k = 0; same && k < a.size(); ++k) same = (a[k] - b[k]).norm() < 1.5e-3;
      if (same) index[i] = j;
    }
  }
  double worst_point = 0;
  std::vector<double> pose_error;
  for (std::size_t i = 0; i < index.size(); ++i) {
    if (!index[i]) continue;
    const Scan& a = from_bag.scans[i];
    const Scan& b = clf[*index[i]];
    ASSERT_EQ(a.num_beams, b.num_beams) << i;
    ASSERT_EQ(a.points_laser.size(), b.points_laser.size()) << i;
    for (std::size_t k = 0; k < a.points_laser.size(); ++k)
      worst_point = std::max(worst_point, (a.points_laser[k] - b.points_laser[k]).norm());
    // The bag's laser mount (base_link -> laser on /tf_static) is applied to its poses; the clf's are the base's.
    const Pose2 clf_laser = b.T_world_laser * from_bag.T_base_laser;
    pose_error.push_back((a.T_world_laser.translation() - clf_laser.translation()).norm());
  }
  std::printf("%s: laser mount %s at (%.3f m, %.3f m, %.2f deg)\n", log.c_str(),
              from_bag.laser_frame.empty() ? "(none)" : from_bag.laser_frame.c_str(), from_bag.T_base_laser.x,
              from_bag.T_base_laser.y, from_bag.T_base_laser.theta * 180 / std::numbers::pi);
  ASSERT_EQ(pose_error.size(), clf.size());  // every scan paired, one to one
  EXPECT_LT(worst_point, 1e-3);
  // The .clf interpolated the odometry at the original scan times, the bag carries it at re-timed stamps (the
  // original times are not in the bag): the poses agree to millimetres (fr079, intel) or a centimetre or two
  // (aces), with outliers where the robot moved fast between odometry messages.
  std::sort(pose_error.begin(), pose_error.end());
  std::printf("%s: %zu of %zu scans paired; pose difference bag vs clf: median %.4f m, 99th percentile %.4f m\n",
              log.c_str(), pose_error.size(), clf.size(), pose_error[pose_error.size() / 2],
              pose_error[pose_error.size() * 99 / 100]);
  EXPECT_LT(pose_error[pose_error.size() / 2], 0.02);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < index.size(); ++i) moved += *index[i] != i;
  std::printf("%s: %zu scans at another place in the clf's order\n", log.c_str(), moved);
  if (!GetParam().same_order) {
    // intel's bag lists 2591 scans at other places than its clf, each with the odometry of its own place in
    // time, so the two trajectories (and submaps, which follow the scan order) differ there by construction.
    EXPECT_GT(moved, 0u);
    return;
  }
  EXPECT_EQ(moved, 0u);
  // So the submaps agree up to those millimetres: as many within 2 %, as many points (one per occupied 0.1 m
  // cell) within 2 %.
  const Submaps sa = build_submaps(from_bag.scans), sb = build_submaps(clf);
  ASSERT_NEAR(static_cast<double>(sa.size()), static_cast<double>(sb.size()), 0.02 * static_cast<double>(sb.size()));
  double points_a = 0, points_b = 0;
  for (const Submap& m : sa) points_a += static_cast<double>(m.points.size());
  for (const Submap& m : sb) points_b += static_cast<double>(m.points.size());
  EXPECT_NEAR(points_a / points_b, 1.0, 0.02);
}

INSTANTIATE_TEST_SUITE_P(Bags, RosBagRealData,
                         ::testing::Values(BagCase{"fr079", true}, BagCase{"intel", false}, BagCase{"aces", true}),
                         [](const auto& info) { return std::string(info.param.log); });

TEST(RosBag, BadFilesAreNamedInTheError) {
  testing::TempDir dir;
  const auto message = [](const std::filesystem::path& p) {
    try {
      load_scan_source(p.string());
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(message(dir / "missing.bag"), HasSubstr("missing.bag: no such file"));
  EXPECT_THAT(message(dir / (std::string(5000, 'a') + ".bag")), HasSubstr("File name too long"));
  std::filesystem::create_directories(dir / "folder.bag");
  EXPECT_THAT(message(dir / "folder.bag"), HasSubstr("folder.bag: a folder without metadata.yaml"));
  {
    std::ofstream(dir / "text.bag") << "FLASER 4 1 2 3 4 0 0 0 0 0 0 1 h 1\n";
  }
  EXPECT_THAT(message(dir / "text.bag"), HasSubstr("text.bag: not a readable ROS 1 bag"));
  const std::filesystem::path real = testing::shared_data() / "bags" / "fr079.clf2bag.bag";
  if (std::filesystem::exists(real)) {  // a bag cut short
    std::ifstream in(real, std::ios::binary);
    std::string head(20000, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(dir / "cut.bag", std::ios::binary) << head;
    EXPECT_THAT(message(dir / "cut.bag"), HasSubstr("cut.bag: "));
  }
}

// A robot's bag without nav_msgs/Odometry: the scans are posed by the odom -> base_link transforms on /tf, the
// same poses as the same motion published as Odometry; without either, every scan has the identity pose.
TEST(RosBag, PosesFromTfWhenThereIsNoOdometry) {
  testing::TempDir dir;
  rosbag_messages::BagMessages m;
  for (int k = 0; k < 30; ++k) {
    const double t = 100.0 + 0.1 * k, yaw = 0.02 * k;
    m.odometry.push_back({t - 0.05, 0.1 * k, 0.05 * k, 0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)});
    rosbag_messages::LaserScanMessage scan{t, -std::numbers::pi / 2, std::numbers::pi / 180, 0.1, 30.0, {}, "laser"};
    for (int b = 0; b < 181; ++b) scan.ranges.push_back(2.0f + 0.01f * static_cast<float>(b % 17));
    m.scans.push_back(scan);
  }
  rosbag_messages::write_bag_messages((dir / "odom.bag").string(), m, /*as_tf=*/false);
  rosbag_messages::write_bag_messages((dir / "tf.bag").string(), m, /*as_tf=*/true);
  m.odometry.clear();
  rosbag_messages::write_bag_messages((dir / "bare.bag").string(), m, false);
  const RosBagLog odom = read_ros_bag(dir / "odom.bag"), tf = read_ros_bag(dir / "tf.bag"),
                  bare = read_ros_bag(dir / "bare.bag");
  EXPECT_EQ(odom.odometry_topic, "/odom");
  EXPECT_EQ(tf.odometry_topic, "/tf (odom -> base_link)");
  EXPECT_EQ(bare.odometry_topic, "");
  ASSERT_EQ(tf.scans.size(), 30u);
  ASSERT_EQ(odom.scans.size(), 30u);
  for (std::size_t i = 0; i < 30; ++i) {
    EXPECT_NEAR(tf.scans[i].T_world_laser.x, odom.scans[i].T_world_laser.x, 1e-9);
    EXPECT_NEAR(tf.scans[i].T_world_laser.y, odom.scans[i].T_world_laser.y, 1e-9);
    EXPECT_NEAR(tf.scans[i].T_world_laser.theta, odom.scans[i].T_world_laser.theta, 1e-9);
    EXPECT_EQ(tf.scans[i].points_laser, odom.scans[i].points_laser);
    EXPECT_EQ(bare.scans[i].T_world_laser.x, 0.0);
  }
  // A bag of odometry only: no laser topic, a clear error naming the file.
  rosbag_messages::BagMessages odometry_only;
  odometry_only.odometry.push_back({1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0});
  rosbag_messages::write_bag_messages((dir / "nolaser.bag").string(), odometry_only, false);
  try {
    load_scan_source((dir / "nolaser.bag").string());
    ADD_FAILURE() << "a bag without LaserScan was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("nolaser.bag: no laser scans: the ROS 1 bag holds no sensor_msgs/LaserScan messages"));
  }
  // Interpolated between odometry stamps: scan 10 at t = 101.0 lies halfway between odometry 10 and 11.
  EXPECT_NEAR(tf.scans[10].T_world_laser.x, 1.05, 1e-6);
  EXPECT_EQ(tf.scans[0].points_laser.size(), 181u);
}

// An odometry pose moved kilometres (a damaged message) is refused naming it, or left out with skip_damaged: the
// scans around it keep the poses of their neighbours.
TEST(RosBag, AnOdometryPoseThatJumpsIsDamage) {
  testing::TempDir dir;
  rosbag_messages::BagMessages m;
  for (int k = 0; k < 30; ++k) {
    const double t = 100.0 + 0.1 * k;
    m.odometry.push_back({t - 0.05, 0.1 * k, 0.0, 0.0, 0.0, 0.0, 1.0});
    rosbag_messages::LaserScanMessage scan{t, -std::numbers::pi / 2, std::numbers::pi / 180, 0.1, 30.0, {}, "laser"};
    scan.ranges.assign(181, 2.0f);
    m.scans.push_back(scan);
  }
  m.odometry[12].x = 3000.0;
  rosbag_messages::write_bag_messages((dir / "jump.bag").string(), m, false);
  try {
    read_ros_bag(dir / "jump.bag");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("jump.bag: /odom pose at stamp 101.150 s jumps 2998.9 m from the one before"));
    EXPECT_THAT(e.what(), HasSubstr("skip_damaged"));
  }
  LogReadOptions o;
  o.skip_damaged = true;
  const RosBagLog log = read_ros_bag(dir / "jump.bag", o);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("left out an odometry /odom pose at stamp 101.150 s"));
  ASSERT_EQ(log.scans.size(), 30u);
  for (const Scan& s : log.scans) EXPECT_LT(s.T_world_laser.x, 3.0);
}

// A gap in time (a chunk skipped as damaged, a recording paused) over which the robot moved 30 m is no
// damage: measured from the pose before the gap, every pose after it was left out and the scans after it
// posed there.
TEST(RosBag, OdometryAfterAGapInTimeIsKept) {
  testing::TempDir dir;
  rosbag_messages::BagMessages m;
  for (int k = 0; k < 40; ++k) {
    const double t = 100.0 + 0.1 * k + (k >= 20 ? 60.0 : 0.0);  // nothing for a minute after the 20th
    const double x = 0.1 * k + (k >= 20 ? 30.0 : 0.0);
    m.odometry.push_back({t - 0.05, x, 0.0, 0.0, 0.0, 0.0, 1.0});
    rosbag_messages::LaserScanMessage scan{
        t, -std::numbers::pi / 2, std::numbers::pi / 180, 0.1, 30.0, {}, "laser"};
    scan.ranges.assign(181, 2.0f);
    m.scans.push_back(scan);
  }
  rosbag_messages::write_bag_messages((dir / "gap.bag").string(), m, false);
  const RosBagLog log = read_ros_bag(dir / "gap.bag");
  EXPECT_TRUE(log.warnings.empty());
  ASSERT_EQ(log.scans.size(), 40u);
  EXPECT_NEAR(log.scans[39].T_world_laser.x, 33.9, 0.06);
  // A pose that jumps as far within a tenth of a second is still damage.
  m.odometry[30].x += 30.0;
  rosbag_messages::write_bag_messages((dir / "gap.bag").string(), m, false);
  EXPECT_THROW(read_ros_bag(dir / "gap.bag"), InputError);
  // And so is one whose stamp is damaged too, far after the others.
  m.odometry[30].x -= 30.0;
  m.odometry.push_back({1e9, 3000.0, 0.0, 0.0, 0.0, 0.0, 1.0});
  rosbag_messages::write_bag_messages((dir / "gap.bag").string(), m, false);
  EXPECT_THROW(read_ros_bag(dir / "gap.bag"), InputError);
}

// The topics can be named (LogReadOptions::scan_topic, odom_topic; --scan-topic, --odom-topic), the same for ROS 1
// and ROS 2 bags (io/bag_selection.h): the fr079 bag carries the odometry both on /odom and as /tf odom -> base_link.
TEST(RosBag, TopicsCanBeChosen) {
  const std::filesystem::path bag = testing::shared_data() / "bags" / "fr079.clf2bag.bag";
  const RosBagLog first = read_ros_bag(bag);
  EXPECT_EQ(first.odometry_topic, "/odom");
  LogReadOptions o;
  o.odom_topic = "/tf";
  const RosBagLog tf = read_ros_bag(bag, o);
  EXPECT_EQ(tf.odometry_topic, "/tf (odom -> base_link)");
  ASSERT_EQ(tf.scans.size(), first.scans.size());
  for (std::size_t i = 0; i < tf.scans.size(); i += 97)
    EXPECT_LT((tf.scans[i].T_world_laser.translation() - first.scans[i].T_world_laser.translation()).norm(), 1e-3);
  o = {};
  o.scan_topic = "/base_scan";
  try {
    read_ros_bag(bag, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("fr079.clf2bag.bag: no LaserScan message on /base_scan (the bag's topics: "));
    EXPECT_THAT(e.what(), HasSubstr("/scan (sensor_msgs/LaserScan)"));
  }
  try {
    load_scan_source("sim", o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("sim: --scan-topic and --odom-topic name a bag's topics; this is not a bag"));
  }
  o = {};
  o.odom_topic = "/wheel_odom";
  try {
    read_ros_bag(bag, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no Odometry message or odom -> base_link transform on /wheel_odom"));
  }
}

// The laser's mount on the robot, from the bag's transforms (base_link -> laser on /tf_static, here through an
// intermediate frame and once written child -> parent): every scan is posed at odometry * T_base_laser.
TEST(RosBag, AppliesTheLaserMountFromTfStatic) {
  testing::TempDir dir;
  rosbag_messages::BagMessages m;
  for (int k = 0; k < 10; ++k) {
    const double t = 50.0 + 0.1 * k, yaw = 0.1 * k;
    m.odometry.push_back({t, 0.2 * k, 0.0, 0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)});
    rosbag_messages::LaserScanMessage scan{t, -std::numbers::pi / 2, std::numbers::pi / 180, 0.1, 30.0, {}, "laser"};
    scan.ranges.assign(181, 3.0f);
    m.scans.push_back(scan);
  }
  rosbag_messages::write_bag_messages((dir / "plain.bag").string(), m, false);
  const double half = 0.05;  // the laser turned 0.1 rad on its mount
  m.transforms = {{"base_link", "mount", 0.2, 0.0, 0.0, 0.0, 0.0, 1.0},
                  {"laser", "mount", -0.02, 0.0, 0.0, 0.0, -std::sin(half), std::cos(half)}};  // mount in laser
  rosbag_messages::write_bag_messages((dir / "mounted.bag").string(), m, false);
  const RosBagLog plain = read_ros_bag(dir / "plain.bag"), mounted = read_ros_bag(dir / "mounted.bag");
  EXPECT_EQ(plain.laser_frame, "");
  EXPECT_EQ(mounted.laser_frame, "laser");
  ASSERT_EQ(mounted.scans.size(), 10u);
  const Pose2 T_mount_laser = Pose2{-0.02, 0.0, -0.1}.inverse();
  const Pose2 expected = Pose2{0.2, 0.0, 0.0} * T_mount_laser;
  EXPECT_NEAR(mounted.T_base_laser.x, expected.x, 1e-6);
  EXPECT_NEAR(mounted.T_base_laser.y, expected.y, 1e-6);
  EXPECT_NEAR(mounted.T_base_laser.theta, 0.1, 1e-6);
  for (std::size_t i = 0; i < 10; ++i) {
    const Pose2 want = plain.scans[i].T_world_laser * expected;
    EXPECT_NEAR(mounted.scans[i].T_world_laser.x, want.x, 1e-6);
    EXPECT_NEAR(mounted.scans[i].T_world_laser.y, want.y, 1e-6);
    EXPECT_NEAR(mounted.scans[i].T_world_laser.theta, want.theta, 1e-6);
  }
}

// Bags whose lengths and offsets lie, as fuzz_ros_bag made them: librosbag trusted each of them (allocating up to
// 4 GB, or reading past its buffers); they are refused as not readable bags, naming the file, before it sees them.
// Three scans of three ranges each, one odometry message before each: the small good bag the damage tests spoil.
rosbag_messages::BagMessages three_scans() {
  rosbag_messages::BagMessages m;
  for (int k = 0; k < 3; ++k) {
    m.odometry.push_back({10.0 + k, 0.1 * k, 0.0, 0.0, 0.0, 0.0, 1.0});
    m.scans.push_back({10.5 + k, -1.5, 0.5, 0.1, 30.0, {1.5f, 2.5f, 3.5f}, "laser"});
  }
  return m;
}

// Where the first entry of the first index data record (op 4) of a bag's bytes lies, found by walking the top-level
// records: an entry is a time (sec, nsec: 8 bytes) and the message's offset in its chunk (4 bytes). 0 if none.
std::size_t first_index_entry(const std::string& bag) {
  using namespace std::string_view_literals;
  for (std::size_t pos = 13; pos + 8 <= bag.size();) {
    std::uint32_t header_len = 0, data_len = 0;
    std::memcpy(&header_len, bag.data() + pos, 4);
    if (header_len > bag.size() - pos - 8) return 0;
    std::memcpy(&data_len, bag.data() + pos + 4 + header_len, 4);
    const std::size_t data = pos + 8 + header_len;
    if (std::string_view(bag.data() + pos + 4, header_len).find("op=\x04"sv) != std::string_view::npos) return data;
    pos = data + data_len;
  }
  return 0;
}

TEST(RosBag, LyingLengthsAndOffsetsAreRefusedBeforeLibrosbagReadsThem) {
  testing::TempDir dir;
  const rosbag_messages::BagMessages m = three_scans();
  rosbag_messages::write_bag_messages((dir / "good.bag").string(), m, /*as_tf=*/false);
  rosbag_messages::write_bag_messages((dir / "good-tf.bag").string(), m, /*as_tf=*/true);
  ASSERT_EQ(read_ros_bag(dir / "good.bag").scans.size(), 3u);
  ASSERT_EQ(read_ros_bag(dir / "good-tf.bag").scans.size(), 3u);
  const std::string good = testing::read_bytes(dir / "good.bag"), good_tf = testing::read_bytes(dir / "good-tf.bag");
  // The bytes of the bag with the 4 bytes after the first occurrence of `after` (plus `skip`) set to value.
  const auto patched = [&](const std::string& bag, std::string_view after, std::size_t skip, std::uint32_t value) {
    const std::size_t at = bag.find(after);
    std::string out = bag;
    if (at == std::string::npos) {
      ADD_FAILURE() << "no " << after << " in the bag";
      return out;
    }
    std::memcpy(out.data() + at + after.size() + skip, &value, 4);
    return out;
  };
  const auto error = [&](const std::string& bytes) {
    testing::write_bytes(dir / "bad.bag", bytes);
    try {
      read_ros_bag(dir / "bad.bag");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  using namespace std::string_view_literals;
  const std::uint32_t many = 0xffffffff;
  // A LaserScan whose ranges claim 2^29 floats (ROS's deserializer allocated 2 GB before checking).
  const std::string_view ranges = "\x03\x00\x00\x00\x00\x00\xc0\x3f"sv;  // 3 ranges, the first 1.5f
  std::string scan = good;
  ASSERT_NE(scan.find(ranges), std::string::npos);
  const std::uint32_t floats = 0x20000000;
  std::memcpy(scan.data() + scan.find(ranges), &floats, 4);
  EXPECT_THAT(error(scan), HasSubstr("holds an array longer than the message"));
  // A TFMessage whose transform count is 2^32 - 1 (count, seq, stamp, then frame_id).
  const std::string_view frames = "\x04\x00\x00\x00odom\x09\x00\x00\x00" "base_link"sv;
  std::string tf = good_tf;
  ASSERT_NE(tf.find(frames), std::string::npos);
  std::memcpy(tf.data() + tf.find(frames) - 16, &many, 4);
  EXPECT_THAT(error(tf), HasSubstr("holds an array longer than the message"));
  // The first record of the index section with a header of 2^32 - 1 bytes (librosbag allocated 4 GB).
  std::uint64_t index_pos = 0;
  std::memcpy(&index_pos, good.data() + good.find("index_pos=") + 10, 8);
  std::string index = good;
  std::memcpy(index.data() + index_pos, &many, 4);
  // It runs past the end of the file, as when the file is cut there: the chunks before it are read, with a warning.
  const auto warnings = [&](const std::string& bytes) {
    testing::write_bytes(dir / "bad.bag", bytes);
    const RosBagLog log = read_ros_bag(dir / "bad.bag");
    EXPECT_EQ(log.scans.size(), 3u);
    std::string all;
    for (const std::string& w : log.warnings) all += w + "\n";
    return all;
  };
  EXPECT_THAT(warnings(index), HasSubstr("bad.bag: the file ends mid-record after byte " + std::to_string(index_pos)));
  // The index section past the end of the file (as in a file cut short between its chunks and its index); a chunk
  // claiming 4 GB uncompressed; an index entry past its chunk.
  EXPECT_THAT(warnings(patched(good, "index_pos=", 0, 0x7fffffff)),
              HasSubstr("bad.bag: the file ends at byte " + std::to_string(good.size()) +
                        ", before its index at byte 2147483647 (cut short); read the 3 scans of its 1 whole chunks"));
  EXPECT_THAT(error(patched(good, "size=", 0, 0xffffffff)),
              HasSubstr("bad.bag: not a readable ROS 1 bag (the record at byte " +
                                  std::to_string(good.find("compression=") - 8) + " is damaged: a chunk of more than"));
  // A chunk that claims no bytes at all (size 0, data_len 0; the fuzzer's find: an empty copy from no buffer): the
  // bytes after its header are then read as the next record, which is damaged.
  std::string empty_chunk = patched(good, "size=", 0, 0);
  {
    const std::size_t at = good.find("compression=") - 8;
    std::uint32_t header_len = 0;
    std::memcpy(&header_len, good.data() + at, 4);
    const std::uint32_t none = 0;
    std::memcpy(empty_chunk.data() + at + 4 + header_len, &none, 4);
  }
  EXPECT_THAT(error(empty_chunk), HasSubstr("bad.bag: not a readable ROS 1 bag"));
  // The first index data record's first entry: its offset.
  std::string offset = good;
  const std::size_t entry = first_index_entry(good);
  ASSERT_NE(entry, 0u);
  std::memcpy(offset.data() + entry + 8, &many, 4);  // entry 0: time (8 bytes), offset (4 bytes)
  EXPECT_THAT(error(offset), HasSubstr("message data record at 4294967295: past the end"));
  // With skip_damaged a damaged index is read past: the chunks are walked without it.
  testing::write_bytes(dir / "bad.bag", offset);
  LogReadOptions skip;
  skip.skip_damaged = true;
  const RosBagLog skipped = read_ros_bag(dir / "bad.bag", skip);
  EXPECT_EQ(skipped.scans.size(), 3u);
  ASSERT_EQ(skipped.warnings.size(), 1u);
  EXPECT_THAT(skipped.warnings[0], HasSubstr("bad.bag: the bag's index is damaged (not a readable ROS 1 bag (message "
                                             "data record at 4294967295: past the end)); read the 3 scans"));
  // A recording never closed (index_pos 0, as rosbag record leaves it until the end): read without its index.
  EXPECT_THAT(warnings(patched(good, "index_pos=", 0, 0)),
              HasSubstr("bad.bag: the bag has no index (the recording was not closed); read the 3 scans of its 1 whole "
                        "chunks without it"));
  // Another bag format version.
  EXPECT_THAT(error("#ROSBAG V1.2\n" + good.substr(13)), HasSubstr("only ROS bag format 2.0 is read"));
}

// librosbag builds a ros::Time from every time it reads, which throws a bare std::runtime_error ("Time is out of dual
// 32-bit range") when sec + nsec / 1e9 passes 2^32 - 1 (fuzz_ros_bag, ../shared/fuzz-findings): such a time is
// damage, named with where it is; skip_damaged reads the chunks without the index.
TEST(RosBag, ATimeOutOfRosRangeIsDamageNamedWhereItIs) {
  testing::TempDir dir;
  const rosbag_messages::BagMessages m = three_scans();
  rosbag_messages::write_bag_messages((dir / "good.bag").string(), m, /*as_tf=*/false);
  const std::string good = testing::read_bytes(dir / "good.bag");
  const std::uint32_t bad_time[2] = {0xfffffffeu, 4077344295u};  // the finding's: sec 2^32 - 2, nsec > 1e9
  const auto read = [&](const std::string& bytes, bool skip_damaged) {
    testing::write_bytes(dir / "bad.bag", bytes);
    LogReadOptions options;
    options.skip_damaged = skip_damaged;
    return read_ros_bag(dir / "bad.bag", options);
  };
  // In an index entry (where the finding had it), in a chunk info record and in a message record's header.
  std::string in_index = good, in_chunk_info = good, in_message = good;
  const std::size_t entry = first_index_entry(good);
  ASSERT_NE(entry, 0u);
  std::memcpy(in_index.data() + entry, bad_time, 8);
  ASSERT_NE(good.find("start_time="), std::string::npos);
  std::memcpy(in_chunk_info.data() + good.find("start_time=") + 11, bad_time, 8);
  ASSERT_NE(good.find("time="), std::string::npos);  // the first message record's (chunks are not compressed)
  std::memcpy(in_message.data() + good.find("time=") + 5, bad_time, 8);
  for (const auto& [bytes, where] : {std::pair{in_index, "index data record at "},
                                     std::pair{in_chunk_info, "chunk info record at "},
                                     std::pair{in_message, "message data record at "}}) {
    SCOPED_TRACE(where);
    try {
      read(bytes, false);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("bad.bag: not a readable ROS 1 bag (" + std::string(where)));
      EXPECT_THAT(e.what(), HasSubstr("a time out of ROS's range (sec 4294967294, nsec 4077344295)"));
    }
    const RosBagLog skipped = read(bytes, true);
    EXPECT_EQ(skipped.scans.size(), 3u);
    ASSERT_FALSE(skipped.warnings.empty());
    EXPECT_THAT(skipped.warnings[0], HasSubstr("bad.bag: the bag's index is damaged"));
  }
}

// Every input a fuzz target of ROS 1 bags ever found (fuzz/findings/fuzz_ros_bag, also the fuzzer's corpus: see
// fuzz/README.md) is read as the fuzzer reads it: scans, or an InputError naming the file; nothing else escapes.
TEST(RosBag, EveryPastFuzzFindingIsReadOrRefusedByName) {
  const std::filesystem::path findings = std::filesystem::path(PARTSLAM_SOURCE_DIR) / "fuzz/findings/fuzz_ros_bag";
  ASSERT_TRUE(std::filesystem::is_directory(findings)) << findings;
  std::size_t files = 0;
  for (const auto& f : std::filesystem::directory_iterator(findings)) {
    SCOPED_TRACE(f.path().string());
    ++files;
    for (const bool skip_damaged : {false, true}) {
      LogReadOptions options;
      options.skip_damaged = skip_damaged;
      try {
        const ScanSource source = load_scan_source(f.path().string(), options);
        EXPECT_FALSE(source.scans.empty());
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(f.path().string()));
      }
    }
  }
  EXPECT_GE(files, 1u);
}

// ---- bags cut short, corrupt chunks ----

// A top-level record of a bag file.
struct TopRecord {
  std::size_t pos = 0, end = 0;
  std::string header;  ///< the header's fields, each "length name=value"
};

std::vector<TopRecord> top_records(const std::string& bag) {
  std::vector<TopRecord> out;
  for (std::size_t pos = 13; pos + 8 <= bag.size();) {
    std::uint32_t header_len = 0, data_len = 0;
    std::memcpy(&header_len, bag.data() + pos, 4);
    std::memcpy(&data_len, bag.data() + pos + 4 + header_len, 4);
    const std::size_t end = pos + 8 + header_len + data_len;
    out.push_back({pos, end, bag.substr(pos + 4, header_len)});
    pos = end;
  }
  return out;
}

// The value of a header field, empty when there is none.
std::string header_field(const std::string& header, const std::string& name) {
  for (std::size_t at = 0; at + 4 <= header.size();) {
    std::uint32_t n = 0;
    std::memcpy(&n, header.data() + at, 4);
    const std::string field = header.substr(at + 4, n);
    if (field.rfind(name + "=", 0) == 0) return field.substr(name.size() + 1);
    at += 4 + n;
  }
  return {};
}

std::uint32_t u32_of(const std::string& bytes) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data(), std::min<std::size_t>(4, bytes.size()));
  return v;
}

// The chunks of a bag, from its index: where each ends and how many messages of `topic` it holds.
std::vector<std::pair<std::size_t, std::size_t>> chunks_of(const std::string& bag, const std::string& topic,
                                                           std::vector<std::size_t>* starts = nullptr) {
  const std::vector<TopRecord> records = top_records(bag);
  std::vector<std::uint32_t> connections;  // of the topic
  for (const TopRecord& r : records)
    if (header_field(r.header, "op") == "\x07" && header_field(r.header, "topic") == topic)
      connections.push_back(u32_of(header_field(r.header, "conn")));
  std::vector<std::pair<std::size_t, std::size_t>> chunks;
  for (const TopRecord& r : records) {
    const std::string op = header_field(r.header, "op");
    if (op == "\x05") {
      chunks.emplace_back(r.end, 0);
      if (starts != nullptr) starts->push_back(r.pos);
    } else if (op == "\x04" && !chunks.empty()) {
      const std::uint32_t conn = u32_of(header_field(r.header, "conn"));
      if (std::find(connections.begin(), connections.end(), conn) != connections.end())
        chunks.back().second += u32_of(header_field(r.header, "count"));
    }
  }
  return chunks;
}

void expect_same_scans(const Scans& part, const Scans& whole) {
  ASSERT_LE(part.size(), whole.size());
  for (std::size_t i = 0; i < part.size(); ++i) {
    ASSERT_EQ(part[i].timestamp, whole[i].timestamp) << i;
    ASSERT_EQ(part[i].points_laser, whole[i].points_laser) << i;
  }
}

// The aces bag cut at 20 random places: each cut reads the scans of the chunks wholly before the cut (as `rosbag
// reindex` recovers them), the first scans of the whole bag, with a warning.
TEST(RosBag, BagsCutShortReadTheScansOfTheirWholeChunks) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "aces.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  EXPECT_TRUE(whole.warnings.empty());
  const std::string bytes = testing::read_bytes(source);
  const auto chunks = chunks_of(bytes, "/scan");
  ASSERT_GT(chunks.size(), 5u);
  std::size_t total = 0;
  for (const auto& c : chunks) total += c.second;
  ASSERT_EQ(total, whole.scans.size());
  testing::TempDir dir;
  std::mt19937_64 rng(24);
  for (int k = 0; k < 20; ++k) {
    const std::size_t cut = 4200 + rng() % (bytes.size() - 4200);
    SCOPED_TRACE("cut at " + std::to_string(cut));
    std::size_t before = 0;
    for (const auto& c : chunks) before += c.second * (c.first <= cut);
    testing::write_bytes(dir / "cut.bag", std::string_view(bytes).substr(0, cut));
    if (before == 0) {
      EXPECT_THAT([&] { load_scan_source((dir / "cut.bag").string()); },
                  ::testing::ThrowsMessage<InputError>(HasSubstr("no sensor_msgs/LaserScan messages; " +
                                                                 (dir / "cut.bag").string() + ": the file ends")));
      continue;
    }
    const RosBagLog part = read_ros_bag(dir / "cut.bag");
    EXPECT_EQ(part.scans.size(), before);
    expect_same_scans(part.scans, whole.scans);
    ASSERT_EQ(part.warnings.size(), 1u);
    EXPECT_THAT(part.warnings[0], HasSubstr("cut.bag: the file ends mid-record after byte "));
    EXPECT_THAT(part.warnings[0], HasSubstr("; read the " + std::to_string(before) + " scans of its "));
  }
  // Cut just after a chunk: a file of whole records without its index.
  testing::write_bytes(dir / "cut.bag", std::string_view(bytes).substr(0, chunks[3].first));
  const RosBagLog part = read_ros_bag(dir / "cut.bag");
  EXPECT_EQ(part.scans.size(), chunks[0].second + chunks[1].second + chunks[2].second + chunks[3].second);
  ASSERT_EQ(part.warnings.size(), 1u);
  EXPECT_THAT(part.warnings[0], HasSubstr("cut.bag: the file ends at byte " + std::to_string(chunks[3].first) +
                                          ", before its index at byte "));
}

TEST(RosBag, ACorruptChunkInTheMiddleIsAnErrorOrWithSkipDamagedSkippedAndCounted) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "aces.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  std::string bytes = testing::read_bytes(source);
  std::vector<std::size_t> starts;
  const auto chunks = chunks_of(bytes, "/scan", &starts);
  ASSERT_GT(chunks.size(), 5u);
  for (std::size_t i = 0; i < 64; ++i) bytes[starts[2] + 2000 + i] = static_cast<char>(i * 37);  // its bz2 data
  testing::TempDir dir;
  testing::write_bytes(dir / "corrupt.bag", bytes);
  const std::string place = "the record at byte " + std::to_string(starts[2]) + " is damaged: ";
  EXPECT_THAT([&] { read_ros_bag(dir / "corrupt.bag"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("corrupt.bag: not a readable ROS 1 bag (" + place +
                                                             "a bz2 chunk that does not decompress to its size)")));
  LogReadOptions skip;
  skip.skip_damaged = true;
  const RosBagLog log = read_ros_bag(dir / "corrupt.bag", skip);
  EXPECT_EQ(log.scans.size(), whole.scans.size() - chunks[2].second);
  expect_same_scans(Scans(log.scans.begin(), log.scans.begin() + static_cast<long>(chunks[0].second + chunks[1].second)),
                    whole.scans);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("corrupt.bag: skipped 1 damaged record(s) (skip_damaged); the first: " + place));
}


// The scans of `whole` without those of chunk `skipped` (chunks: from chunks_of), which must be `part`.
void expect_all_but_chunk(const Scans& part, const Scans& whole,
                          const std::vector<std::pair<std::size_t, std::size_t>>& chunks, std::size_t skipped) {
  std::size_t first = 0;
  for (std::size_t c = 0; c < skipped; ++c) first += chunks[c].second;
  Scans expected(whole.begin(), whole.begin() + static_cast<long>(first));
  expected.insert(expected.end(), whole.begin() + static_cast<long>(first + chunks[skipped].second), whole.end());
  ASSERT_EQ(part.size(), expected.size());
  expect_same_scans(part, expected);
}

// A complete bag (its index, at the header's index_pos, within the file and intact) whose 7th chunk record has a
// length running past the end of the file is damaged, not cut short there (not just the scans of its first 6
// chunks, exit 0): an error naming the byte; with skip_damaged every other chunk is read, found from the index
// (the chunks after the damaged one too).
TEST(RosBag, ADamagedChunkLengthInACompleteBagIsDamageNotACut) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "fr079.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  const std::string good = testing::read_bytes(source);
  std::vector<std::size_t> starts;
  const auto chunks = chunks_of(good, "/scan", &starts);
  ASSERT_GT(chunks.size(), 7u);
  const std::size_t at = starts[6];
  std::uint32_t header_len = 0, data_len = 0;
  std::memcpy(&header_len, good.data() + at, 4);
  std::memcpy(&data_len, good.data() + at + 4 + header_len, 4);
  testing::TempDir dir;
  LogReadOptions skip;
  skip.skip_damaged = true;
  const std::string place = "the record at byte " + std::to_string(at) + " is damaged: ";
  struct Patch {
    const char* what;
    std::size_t offset;  ///< from the record's start
    std::uint32_t value;
    std::string problem;
  };
  const std::vector<Patch> patches{
      {"data_len past the end", 4 + header_len, 0xfffffff0u, "its length runs past the end of the file at byte "},
      {"header_len past the end", 0, static_cast<std::uint32_t>(good.size()), "its length runs past the end"},
      {"data_len shortened", 4 + header_len, data_len - 1000, "a bz2 chunk that does not decompress to its size"},
      {"data_len lengthened over the next chunk", 4 + header_len,
       static_cast<std::uint32_t>(starts[7] + 100 - (at + 8 + header_len)),
       "its length runs over the chunk at byte " + std::to_string(starts[7])}};
  for (const Patch& p : patches) {
    SCOPED_TRACE(p.what);
    std::string bytes = good;
    std::memcpy(bytes.data() + at + p.offset, &p.value, 4);
    testing::write_bytes(dir / "damaged.bag", bytes);
    EXPECT_THAT([&] { read_ros_bag(dir / "damaged.bag"); },
                ::testing::ThrowsMessage<InputError>(::testing::AllOf(
                    HasSubstr("damaged.bag: not a readable ROS 1 bag (" + place + p.problem), HasSubstr("skip_damaged"))));
    const RosBagLog log = read_ros_bag(dir / "damaged.bag", skip);
    expect_all_but_chunk(log.scans, whole.scans, chunks, 6);
    ASSERT_EQ(log.warnings.size(), 1u);
    EXPECT_THAT(log.warnings[0], HasSubstr("damaged.bag: skipped 1 damaged record(s) (skip_damaged); the first: " +
                                           place + p.problem));
    EXPECT_THAT(log.warnings[0], HasSubstr("; read the " + std::to_string(log.scans.size()) + " scans of its " +
                                           std::to_string(chunks.size() - 1) + " whole chunks (of the " +
                                           std::to_string(chunks.size()) + " its index lists)"));
  }
  // Two damaged chunks, one of them the last: both skipped and counted, the others read.
  std::string bytes = good;
  const std::uint32_t past = 0xfffffff0u;
  std::memcpy(bytes.data() + starts[2], &past, 4);
  std::memcpy(bytes.data() + starts.back(), &past, 4);
  testing::write_bytes(dir / "damaged.bag", bytes);
  const RosBagLog log = read_ros_bag(dir / "damaged.bag", skip);
  EXPECT_EQ(log.scans.size(), whole.scans.size() - chunks[2].second - chunks.back().second);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("skipped 2 damaged record(s) (skip_damaged); the first: the record at byte " +
                                         std::to_string(starts[2]) + " is damaged"));
}

// Without a readable index (here a recording never closed: index_pos 0), a chunk whose header cannot be read
// (so neither where it ends) does not end the walk with skip_damaged: the walker finds the next chunk record by its
// header and reads on; after the last chunk there is none to find, which a warning says.
TEST(RosBag, WithoutAnIndexSkipDamagedFindsTheNextChunkAfterOneWithBadLengths) {
  const std::filesystem::path source = testing::shared_data() / "bags" / "aces.clf2bag.bag";
  if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
  const RosBagLog whole = read_ros_bag(source);
  std::string good = testing::read_bytes(source);
  std::vector<std::size_t> starts;
  const auto chunks = chunks_of(good, "/scan", &starts);
  ASSERT_GT(chunks.size(), 5u);
  const std::size_t index_pos_at = good.find("index_pos=") + 10;
  std::memset(good.data() + index_pos_at, 0, 8);  // never closed
  testing::TempDir dir;
  LogReadOptions skip;
  skip.skip_damaged = true;
  std::string bytes = good;
  // The length of its header's first field too long: the header cannot be read, nor so where the chunk ends.
  const std::uint32_t field_len = 0x7fffffff;
  std::memcpy(bytes.data() + starts[2] + 4, &field_len, 4);
  testing::write_bytes(dir / "damaged.bag", bytes);
  const std::string place = "the record at byte " + std::to_string(starts[2]) + " is damaged: ";
  EXPECT_THAT([&] { read_ros_bag(dir / "damaged.bag"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("damaged.bag: not a readable ROS 1 bag (" + place)));
  RosBagLog log = read_ros_bag(dir / "damaged.bag", skip);
  expect_all_but_chunk(log.scans, whole.scans, chunks, 2);
  ASSERT_EQ(log.warnings.size(), 2u);
  EXPECT_THAT(log.warnings[0], HasSubstr("damaged.bag: the bag has no index (the recording was not closed)"));
  EXPECT_THAT(log.warnings[1], HasSubstr("damaged.bag: skipped 1 damaged record(s) (skip_damaged); the first: " + place));
  // The last chunk damaged so: nothing after it is found (its index data records and the index are read past).
  bytes = good;
  std::memcpy(bytes.data() + starts.back() + 4, &field_len, 4);
  testing::write_bytes(dir / "damaged.bag", bytes);
  log = read_ros_bag(dir / "damaged.bag", skip);
  EXPECT_EQ(log.scans.size(), whole.scans.size() - chunks.back().second);
  ASSERT_EQ(log.warnings.size(), 3u);
  EXPECT_THAT(log.warnings[2], HasSubstr("damaged.bag: no chunk record was found after the damaged record at byte " +
                                         std::to_string(starts.back()) + ": the rest of the file"));
}

}  // namespace
}  // namespace partslam::io
