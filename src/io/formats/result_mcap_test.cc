// slam's result.mcap read back with the project's own MCAP reader: every topic with its ROS 2 type, one map
// whose grid is the map's, one transform and one point cloud per scan; the independent check (Foxglove's MCAP
// and ROS 2 message readers, from the npm registry, decoding every message by the schemas the file carries)
// is the ctest ResultMcap.ReadByFoxglove (tests/ros2/check-result-mcap.sh).
#include "io/formats/result_mcap.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <string>

#include "core/error.h"
#include "core/maps/grid_map.h"
#include "core/sim/simulator.h"
#include "io/logs/mcap_file.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

TEST(ResultMcap, HoldsTheMapThePathsTheClosuresAndEveryScan) {
  SimulatorConfig sim;
  sim.route.laps = 1;
  sim.route.room_visits = 1;
  const Scans scans = simulate(sim).scans;
  const GridMap map = build_grid_map(scans);
  testing::TempDir dir;
  write_result_mcap(dir / "result.mcap", {&map, &scans, &scans, {{Vec2(0, 0), Vec2(1, 1)}}});
  std::map<std::string, std::string> types;
  std::map<std::string, int> counts;
  std::vector<std::uint8_t> grid;
  const mcap::ReadReport report = mcap::read_messages(
      dir / "result.mcap",
      [&](const mcap::Channel& c, std::uint64_t, std::span<const std::uint8_t> data) {
        types[c.topic] = c.schema_name;
        ++counts[c.topic];
        EXPECT_EQ(c.message_encoding, "cdr");
        EXPECT_EQ(c.schema_encoding, "ros2msg");
        if (c.topic == "/map") grid.assign(data.begin(), data.end());
      },
      false);
  EXPECT_FALSE(report.truncated);
  EXPECT_EQ(types["/map"], "nav_msgs/msg/OccupancyGrid");
  EXPECT_EQ(types["/slam/path"], "nav_msgs/msg/Path");
  EXPECT_EQ(types["/odom/path"], "nav_msgs/msg/Path");
  EXPECT_EQ(types["/loop_closures"], "visualization_msgs/msg/MarkerArray");
  EXPECT_EQ(types["/tf"], "tf2_msgs/msg/TFMessage");
  EXPECT_EQ(types["/scan"], "sensor_msgs/msg/PointCloud2");
  EXPECT_EQ(counts["/map"], 1);
  EXPECT_EQ(counts["/tf"], static_cast<int>(scans.size()));
  EXPECT_EQ(counts["/scan"], static_cast<int>(scans.size()));
  // The grid's CDR: encapsulation (4), header (stamp 8, frame "map": 4 + 4), map_load_time (8), resolution
  // (4), width (4), height (4), then the origin (7 doubles, aligned to 8) and the cells' count and values.
  ASSERT_GT(grid.size(), 100u);
  const auto u32_at = [&](std::size_t at) {
    std::uint32_t v = 0;
    std::memcpy(&v, grid.data() + at, 4);
    return v;
  };
  EXPECT_EQ(grid[1], 0x01);  // CDR little endian
  float resolution = 0;
  std::memcpy(&resolution, grid.data() + 4 + 16 + 8, 4);
  EXPECT_FLOAT_EQ(resolution, static_cast<float>(map.resolution));
  EXPECT_EQ(u32_at(4 + 16 + 12), static_cast<std::uint32_t>(map.width));
  EXPECT_EQ(u32_at(4 + 16 + 16), static_cast<std::uint32_t>(map.height));
  const std::size_t cells_at = 4 + 40 + 56;  // after the origin, 8-aligned from 40
  ASSERT_EQ(u32_at(cells_at), map.cells.size());
  std::size_t occupied = 0, marked = 0;
  for (std::size_t i = 0; i < map.cells.size(); ++i) {
    occupied += map.cells[i] == CellState::kOccupied;
    marked += grid[cells_at + 4 + i] == 100;
  }
  EXPECT_EQ(marked, occupied);
  EXPECT_THROW(write_result_mcap(dir / "bad.mcap", {nullptr, &scans, nullptr, {}}), InputError);
}

TEST(ResultMcap, LocatedAnswersAreAPathAndColouredMarkers) {
  GridMap map;
  map.width = map.height = 10;
  map.cells.assign(100, CellState::kFree);
  testing::TempDir dir;
  write_located_mcap(dir / "located.mcap", map,
                     {{1.0, Pose2{1, 2, 0}, true}, {2.0, Pose2{3, 2, 0.5}, false}});
  std::map<std::string, int> counts;
  mcap::read_messages(
      dir / "located.mcap",
      [&](const mcap::Channel& c, std::uint64_t, std::span<const std::uint8_t>) { ++counts[c.topic]; },
      false);
  EXPECT_EQ(counts, (std::map<std::string, int>{{"/located", 1}, {"/located/path", 1}, {"/map", 1}}));
  EXPECT_THROW(write_located_mcap(dir / "none.mcap", map, {}), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "none.mcap"));
}

}  // namespace
}  // namespace partslam::io
