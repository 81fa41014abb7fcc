// ROS 2 bags written by an independent implementation (tests/ros2/convert.js: Foxglove's MCAP and CDR writers,
// sql.js for .db3) from the benchmark's ROS 1 bags: the same scans and the same submaps as the ROS 1 originals.
// Its own test binary, run after the ctest fixture Ros2Bags wrote the files into PARTSLAM_ROS2_BAGS.
#include <gtest/gtest.h>

#include <string>

#include "core/maps/submap.h"
#include "io/logs/ros2_bag.h"
#include "io/logs/ros_bag.h"
#include "io/logs/scan_source.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

struct Case {
  const char* file;  ///< in PARTSLAM_ROS2_BAGS
  const char* bag;   ///< the ROS 1 bag it was converted from
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.file; }

class Ros2Interop : public ::testing::TestWithParam<Case> {};

TEST_P(Ros2Interop, SameScansAndSubmapsAsTheRos1Bag) {
  const std::filesystem::path file = std::filesystem::path(PARTSLAM_ROS2_BAGS) / GetParam().file;
  ASSERT_TRUE(std::filesystem::exists(file)) << file << " was not written (see the Ros2Bags fixture's output)";
  ASSERT_TRUE(is_ros2_bag(file));
  const RosBagLog ros1 = read_ros_bag(testing::shared_data() / "bags" / (std::string(GetParam().bag) + ".clf2bag.bag"));
  const ScanSource ros2 = load_scan_source(file.string());
  EXPECT_TRUE(ros2.warnings.empty());
  ASSERT_EQ(ros2.scans.size(), ros1.scans.size());
  double worst_point = 0, worst_pose = 0;
  for (std::size_t i = 0; i < ros1.scans.size(); ++i) {
    const Scan& a = ros2.scans[i];
    const Scan& b = ros1.scans[i];
    ASSERT_NEAR(a.timestamp, b.timestamp, 1e-6) << i;
    ASSERT_EQ(a.points_laser.size(), b.points_laser.size()) << i;
    for (std::size_t k = 0; k < a.points_laser.size(); ++k)
      worst_point = std::max(worst_point, (a.points_laser[k] - b.points_laser[k]).norm());
    worst_pose = std::max(worst_pose, (a.T_world_laser.translation() - b.T_world_laser.translation()).norm());
  }
  EXPECT_LT(worst_point, 1e-3);
  EXPECT_LT(worst_pose, 1e-3);
  // The submaps: as many, each with its points within 1 mm.
  const Submaps sa = build_submaps(ros2.scans), sb = build_submaps(ros1.scans);
  ASSERT_EQ(sa.size(), sb.size());
  double worst_submap_point = 0;
  for (std::size_t i = 0; i < sa.size(); ++i) {
    ASSERT_EQ(sa[i].points.size(), sb[i].points.size()) << i;
    for (std::size_t k = 0; k < sa[i].points.size(); ++k)
      worst_submap_point = std::max(worst_submap_point, (sa[i].points[k] - sb[i].points[k]).norm());
  }
  EXPECT_LT(worst_submap_point, 1e-3);
  std::printf("%s: %zu scans, %zu submaps; worst point %.2e m, pose %.2e m, submap point %.2e m\n", GetParam().file,
              ros1.scans.size(), sa.size(), worst_point, worst_pose, worst_submap_point);
}

INSTANTIATE_TEST_SUITE_P(Written, Ros2Interop,
                         ::testing::Values(Case{"fr079.zstd.mcap", "fr079"}, Case{"intel.zstd.mcap", "intel"},
                                           Case{"aces.plain.mcap", "aces"}, Case{"fr079.be.db3", "fr079"},
                                           Case{"intel.rosbag2", "intel"}, Case{"aces.db3", "aces"}),
                         [](const auto& info) {
                           std::string name = info.param.file;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

}  // namespace
}  // namespace partslam::io
