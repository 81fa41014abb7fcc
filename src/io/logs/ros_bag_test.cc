#include "io/logs/ros_bag.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <ostream>
#include <cstdio>
#include <fstream>
#include <optional>
#include <vector>

#include "core/error.h"
#include "core/maps/submap.h"
#include "io/logs/carmen_log.h"
#include "io/logs/ros_bag_messages.h"
#include "io/logs/scan_source.h"
#include "io/testing/test_files.h"

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

void PrintTo(const BagCase& c, std::ostream* os) { *os << c.log; }  // ctest's name: not the struct's bytes

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
  // The bags' range_max (aces's drops its 50.0 m no-return code), which the .clf does not state: its reader would
  // find the code itself and drop the few beams within centimetres below it too.
  clf_options.max_usable_range = 50.0;
  clf_options.no_return_code_share = 0.0;
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
// and ROS 2 bags (io/logs/bag_selection.h): the fr079 bag carries the odometry both on /odom and as /tf odom ->
// base_link.
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
  // The mount reaches the commands through the scan source (`slam --relations` takes it off to judge robot poses).
  EXPECT_FALSE(load_scan_source((dir / "plain.bag").string()).T_base_laser.has_value());
  const std::optional<Pose2> source_mount = load_scan_source((dir / "mounted.bag").string()).T_base_laser;
  ASSERT_TRUE(source_mount.has_value());
  EXPECT_NEAR(source_mount->x, expected.x, 1e-6);
  EXPECT_NEAR(source_mount->theta, 0.1, 1e-6);
}

// A laser mounted upside down (base_link -> laser rolled by pi, as robots that hang their scanner under a plate
// publish it): beam i looks where an upright laser's beam n - 1 - i looks, so its points, read as written, would be
// a mirror image of the room. The mount's rotation is composed in 3D and the points mirrored: the world points
// are the upright laser's. A pitch by pi (the laser turned over the other way) faces backwards instead.
TEST(RosBag, ReadsALaserMountedUpsideDown) {
  testing::TempDir dir;
  rosbag_messages::BagMessages upright;
  for (int k = 0; k < 5; ++k) {
    const double t = 10.0 + 0.1 * k, yaw = 0.3 * k;
    upright.odometry.push_back({t, 0.1 * k, 0.05 * k, 0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)});
    rosbag_messages::LaserScanMessage scan{t, -std::numbers::pi / 2, std::numbers::pi / 180, 0.1, 30.0, {}, "laser"};
    for (int i = 0; i < 181; ++i) scan.ranges.push_back(static_cast<float>(2.0 + 0.01 * i + 0.1 * k));
    upright.scans.push_back(scan);
  }
  upright.transforms = {{"base_link", "laser", 0.3, 0.1, 0.0, 0.0, 0.0, 1.0}};
  rosbag_messages::BagMessages rolled = upright, pitched = upright;
  for (rosbag_messages::LaserScanMessage& scan : rolled.scans) std::reverse(scan.ranges.begin(), scan.ranges.end());
  rolled.transforms = {{"base_link", "laser", 0.3, 0.1, 1.0, 0.0, 0.0, 0.0}};  // roll pi
  // Pitched by pi, beam i looks along base angle pi + a_i: the upright's beams, turned half round and reversed.
  pitched.transforms = {{"base_link", "laser", 0.3, 0.1, 0.0, 1.0, 0.0, 0.0}};
  rosbag_messages::write_bag_messages((dir / "upright.bag").string(), upright, false);
  rosbag_messages::write_bag_messages((dir / "rolled.bag").string(), rolled, false);
  rosbag_messages::write_bag_messages((dir / "pitched.bag").string(), pitched, false);
  const RosBagLog a = read_ros_bag(dir / "upright.bag"), b = read_ros_bag(dir / "rolled.bag"),
                  c = read_ros_bag(dir / "pitched.bag");
  EXPECT_FALSE(a.laser_upside_down);
  EXPECT_TRUE(b.laser_upside_down);
  EXPECT_TRUE(c.laser_upside_down);
  EXPECT_TRUE(b.warnings.empty());
  EXPECT_NEAR(c.T_base_laser.theta, std::numbers::pi, 1e-9);
  ASSERT_EQ(a.scans.size(), 5u);
  ASSERT_EQ(b.scans.size(), 5u);
  ASSERT_EQ(c.scans.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k) {
    const Points2 want = points_world(a.scans[k]), rolled_points = points_world(b.scans[k]);
    ASSERT_EQ(rolled_points.size(), want.size());
    for (std::size_t i = 0; i < want.size(); ++i) {
      // The rolled laser's beam i is the upright's beam n - 1 - i.
      EXPECT_NEAR((rolled_points[want.size() - 1 - i] - want[i]).norm(), 0.0, 1e-5) << k << " " << i;
    }
    // The pitched laser at the same place sees the world turned about its own position: the upright's points
    // mirrored across its y axis (its beams' angles become pi - a), each at its own range.
    const Points2 pitched_points = c.scans[k].points_laser, upright_points = a.scans[k].points_laser;
    ASSERT_EQ(pitched_points.size(), upright_points.size());
    for (std::size_t i = 0; i < upright_points.size(); ++i) {
      const Vec2 base_pitched = c.T_base_laser * pitched_points[i];
      const Vec2 base_upright(-upright_points[i].x() + 0.3, upright_points[i].y() + 0.1);
      EXPECT_NEAR((base_pitched - base_upright).norm(), 0.0, 1e-5) << k << " " << i;
    }
  }
}

// A scan plane tilted from the base's is projected onto it with a warning; a transform with a zero quaternion is
// not used (with a warning), as tf2 discards it.
TEST(RosBag, WarnsOfATiltedLaserAndSkipsAZeroQuaternion) {
  testing::TempDir dir;
  rosbag_messages::BagMessages m;
  for (int k = 0; k < 3; ++k) {
    m.odometry.push_back({1.0 + k, 0.1 * k, 0.0, 0.0, 0.0, 0.0, 1.0});
    rosbag_messages::LaserScanMessage scan{1.0 + k, -1.0, 0.01, 0.1, 30.0, {}, "laser"};
    scan.ranges.assign(201, 2.0f);
    m.scans.push_back(scan);
  }
  const double half = 0.1;  // pitched 0.2 rad (11.5 degrees) down
  m.transforms = {{"base_link", "laser", 0.2, 0.0, 0.0, std::sin(half), 0.0, std::cos(half)},
                  {"base_link", "camera", 0.1, 0.0, 0.0, 0.0, 0.0, 0.0}};
  rosbag_messages::write_bag_messages((dir / "tilted.bag").string(), m, false);
  const RosBagLog log = read_ros_bag(dir / "tilted.bag");
  EXPECT_EQ(log.laser_frame, "laser");
  EXPECT_FALSE(log.laser_upside_down);
  ASSERT_EQ(log.warnings.size(), 2u);
  EXPECT_THAT(log.warnings[0], HasSubstr("base_link -> camera has a zero quaternion"));
  EXPECT_THAT(log.warnings[1], HasSubstr("tilted.bag: the laser frame laser is tilted 11.5 degrees"));
}

}  // namespace
}  // namespace partslam::io
