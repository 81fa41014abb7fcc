#include "io/logs/scan_source.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/error.h"
#include "io/logs/ros_bag_messages.h"
#include "io/files/sqlite.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;

// The error load_scan_source gives for `spec`, or "" when it reads it.
std::string refusal(const std::filesystem::path& spec, const LogReadOptions& options = {}) {
  try {
    load_scan_source(spec.string(), options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A rosbag2 SQLite file with a LaserScan topic and no message in it.
void write_scanless_db3(const std::filesystem::path& path) {
  const sqlite::Connection db = sqlite::Connection::open(path, sqlite::Connection::Access::kCreate);
  db.exec(
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, serialization_format "
      "TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data "
      "BLOB NOT NULL);"
      "INSERT INTO topics VALUES (1, '/scan', 'sensor_msgs/msg/LaserScan', 'cdr', '');");
}

TEST(ScanSource, EachFormatRecognisesItsSpecs) {
  testing::TempDir dir;
  std::filesystem::create_directories(dir / "rosbag2");
  testing::write_text(dir / "rosbag2" / "metadata.yaml", "rosbag2_bagfile_information: {}\n", false);
  std::filesystem::create_directories(dir / "plain");
  EXPECT_STREQ(scan_source_format("sim").name, "simulator");
  EXPECT_STREQ(scan_source_format("sim:7").name, "simulator");
  EXPECT_STREQ(scan_source_format("a/run.bag").name, "ROS 1 bag");
  EXPECT_STREQ(scan_source_format("run.mcap").name, "ROS 2 bag");
  EXPECT_STREQ(scan_source_format("run.db3").name, "ROS 2 bag");
  EXPECT_STREQ(scan_source_format((dir / "rosbag2").string()).name, "ROS 2 bag");
  EXPECT_STREQ(scan_source_format((dir / "rosbag2" / "metadata.yaml").string()).name, "ROS 2 bag");
  EXPECT_STREQ(scan_source_format("fr079.clf.gz").name, "CARMEN log");
  EXPECT_STREQ(scan_source_format("intel.log").name, "CARMEN log");
  EXPECT_THROW(scan_source_format((dir / "plain").string()), InputError);
  EXPECT_EQ(scan_source_formats().size(), 4u);
}

TEST(ScanSource, TheSimulatorGivesScansAndRefusesBagTopics) {
  const ScanSource s = load_scan_source("sim:3");
  EXPECT_EQ(s.name, "sim-3");
  EXPECT_EQ(s.source, "sim:3");
  EXPECT_FALSE(s.scans.empty());
  LogReadOptions topics;
  topics.scan_topic = "/scan";
  EXPECT_THAT(refusal("sim", topics), HasSubstr("not a bag"));
  EXPECT_THAT(refusal("sim:x"), HasSubstr("the simulator seed must be an integer"));
}

TEST(ScanSource, ACarmenLogWithoutScansIsRefusedByName) {
  testing::TempDir dir;
  const std::string text = "# a log of odometry only\nODOM 0 0 0 0 0 0 1.0 host 1.0\nPARAM robot_x 0 host 1.0\n";
  testing::write_text(dir / "odom.log", text, false);
  testing::write_text(dir / "odom.log.gz", text, true);
  testing::write_text(dir / "empty.clf", "", false);
  EXPECT_THAT(refusal(dir / "odom.log"),
              HasSubstr("odom.log: no laser scans: the CARMEN log holds no FLASER or ROBOTLASER1 messages"));
  EXPECT_THAT(refusal(dir / "odom.log.gz"), HasSubstr("odom.log.gz: no laser scans"));
  EXPECT_THAT(refusal(dir / "empty.clf"), HasSubstr("empty.clf: not a CARMEN log"));  // the reader's own refusal
}

TEST(ScanSource, ARos1BagWithoutScansIsRefusedByName) {
  testing::TempDir dir;
  rosbag_messages::BagMessages odometry_only;
  odometry_only.odometry.push_back({1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0});
  rosbag_messages::write_bag_messages((dir / "odom.bag").string(), odometry_only, false);
  EXPECT_THAT(refusal(dir / "odom.bag"),
              HasSubstr("odom.bag: no laser scans: the ROS 1 bag holds no sensor_msgs/LaserScan messages"));
  rosbag_messages::write_bag_messages((dir / "nothing.bag").string(), {}, false);
  EXPECT_THAT(refusal(dir / "nothing.bag"), HasSubstr("nothing.bag: no laser scans"));
}

TEST(ScanSource, ARos2BagWithoutScansIsRefusedByName) {
  testing::TempDir dir;
  write_scanless_db3(dir / "scanless.db3");
  EXPECT_THAT(refusal(dir / "scanless.db3"),
              HasSubstr("scanless.db3: no laser scans: the ROS 2 bag holds no sensor_msgs/LaserScan messages"));
  // The same file as a rosbag2 folder, named by the folder or by its metadata.yaml.
  std::filesystem::create_directories(dir / "run");
  write_scanless_db3(dir / "run" / "run_0.db3");
  testing::write_text(dir / "run" / "metadata.yaml",
                      "rosbag2_bagfile_information:\n  relative_file_paths: [run_0.db3]\n", false);
  EXPECT_THAT(refusal(dir / "run"), HasSubstr("run: no laser scans: the ROS 2 bag"));
  EXPECT_THAT(refusal(dir / "run" / "metadata.yaml"), HasSubstr("metadata.yaml: no laser scans"));
  // An MCAP file cut before its first message (the shared bag's first 1000 bytes): no scans, and why.
  std::string head = testing::read_bytes(testing::shared_data() / "bags" / "fr079.mcap");
  ASSERT_GT(head.size(), 1000u) << "the shared data's bags/fr079.mcap is missing";
  head.resize(1000);
  testing::write_bytes(dir / "head.mcap", head);
  const std::string error = refusal(dir / "head.mcap");
  EXPECT_THAT(error, HasSubstr("head.mcap: no laser scans: the ROS 2 bag holds no sensor_msgs/LaserScan messages"));
  EXPECT_THAT(error, HasSubstr("the recording is cut short"));
}

}  // namespace
}  // namespace partslam::io
