#include "io/logs/ros2_bag.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <zstd.h>

#include <fstream>
#include <random>

#include "core/error.h"
#include "io/logs/mcap_file.h"
#include "io/logs/scan_source.h"
#include "io/files/sqlite.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;

std::filesystem::path shared_mcap() { return testing::shared_data() / "bags" / "fr079.mcap"; }
std::filesystem::path shared_bag() { return testing::shared_data() / "bags" / "fr079.clf2bag.bag"; }

// The scans of a ROS 2 bag equal those of the ROS 1 bag it holds, message for message: points to 1 mm, poses to
// 1 mm and 1e-6 rad (but for the last `unposed` scans, whose odometry may lie past a cut), the same laser mount.
void expect_same_scans(const RosBagLog& a, const RosBagLog& b, std::size_t count, std::size_t unposed = 0) {
  ASSERT_EQ(a.scans.size(), count);
  ASSERT_LE(count, b.scans.size());
  EXPECT_EQ(a.laser_frame, b.laser_frame);
  EXPECT_NEAR(a.T_base_laser.x, b.T_base_laser.x, 1e-9);
  for (std::size_t i = 0; i < count; ++i) {
    const Scan& s = a.scans[i];
    const Scan& t = b.scans[i];
    ASSERT_NEAR(s.timestamp, t.timestamp, 1e-6) << i;
    ASSERT_EQ(s.num_beams, t.num_beams) << i;
    ASSERT_EQ(s.points_laser.size(), t.points_laser.size()) << i;
    for (std::size_t k = 0; k < s.points_laser.size(); ++k)
      ASSERT_LT((s.points_laser[k] - t.points_laser[k]).norm(), 1e-3) << i;
    if (i + unposed >= count) continue;
    ASSERT_LT((s.T_world_laser.translation() - t.T_world_laser.translation()).norm(), 1e-3) << i;
    ASSERT_NEAR(wrap_angle(s.T_world_laser.theta - t.T_world_laser.theta), 0.0, 1e-6) << i;
  }
}

const RosBagLog& ros1() {
  static const RosBagLog log = read_ros_bag(shared_bag());
  return log;
}

TEST(Ros2Bag, TheSharedMcapGivesTheScansOfItsRos1Bag) {
  const RosBagLog log = read_ros2_bag(shared_mcap());
  EXPECT_EQ(log.scan_topic, "/scan");
  EXPECT_EQ(log.odometry_topic, "/odom");
  EXPECT_EQ(log.laser_frame, "laser");
  EXPECT_TRUE(log.warnings.empty());
  expect_same_scans(log, ros1(), ros1().scans.size());
}

// A message as stored: what a db3 row or an MCAP message holds.
struct Raw {
  std::string topic, type;
  std::uint64_t time;
  std::vector<std::uint8_t> data;
};

std::vector<Raw> raw_messages(const std::filesystem::path& mcap) {
  std::vector<Raw> out;
  mcap::read_messages(
      mcap,
      [&](const mcap::Channel& c, std::uint64_t t, std::span<const std::uint8_t> d) {
        out.push_back({c.topic, c.schema_name, t, {d.begin(), d.end()}});
      },
      false);
  return out;
}

// Writes messages as rosbag2's sqlite3 storage does (Humble's tables); zstd: per-message compression.
void write_db3(const std::filesystem::path& path, const std::vector<Raw>& messages, bool zstd = false) {
  const sqlite::Connection db = sqlite::Connection::open(path, sqlite::Connection::Access::kCreate);
  db.exec(
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, serialization_format "
      "TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data "
      "BLOB NOT NULL); BEGIN;");
  std::vector<std::string> topics;
  for (const Raw& m : messages) {
    if (std::find(topics.begin(), topics.end(), m.topic) != topics.end()) continue;
    topics.push_back(m.topic);
    sqlite::Statement(db, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')")
        .bind_int(1, static_cast<std::int64_t>(topics.size()))
        .bind_text(2, m.topic)
        .bind_text(3, m.type)
        .run();
  }
  sqlite::Statement insert(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)");
  for (const Raw& m : messages) {
    const auto id = std::find(topics.begin(), topics.end(), m.topic) - topics.begin() + 1;
    std::vector<std::uint8_t> data = m.data;
    if (zstd) {
      data.resize(ZSTD_compressBound(m.data.size()));
      data.resize(ZSTD_compress(data.data(), data.size(), m.data.data(), m.data.size(), 1));
    }
    insert.bind_int(1, id).bind_int(2, static_cast<std::int64_t>(m.time)).bind_blob(3, data).run();
    insert.reset();
  }
  db.exec("COMMIT;");
}

TEST(Ros2Bag, Db3FilesAndRosbag2FoldersGiveTheSameScans) {
  testing::TempDir dir;
  const std::vector<Raw> messages = raw_messages(shared_mcap());
  write_db3(dir / "fr079.db3", messages);
  expect_same_scans(read_ros2_bag(dir / "fr079.db3"), ros1(), ros1().scans.size());
  // A folder of two split files, with per-message zstd compression.
  std::filesystem::create_directories(dir / "bag");
  const auto half = messages.begin() + static_cast<std::ptrdiff_t>(messages.size() / 2);
  write_db3(dir / "bag" / "bag_0.db3", {messages.begin(), half}, true);
  write_db3(dir / "bag" / "bag_1.db3", {half, messages.end()}, true);
  std::ofstream(dir / "bag" / "metadata.yaml")
      << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
         "  relative_file_paths:\n    - bag_0.db3\n    - bag_1.db3\n"
         "  compression_format: zstd\n  compression_mode: message\n";  // rosbag2 takes either case
  ASSERT_TRUE(is_ros2_bag(dir / "bag"));
  expect_same_scans(read_ros2_bag(dir / "bag"), ros1(), ros1().scans.size());
  expect_same_scans(read_ros2_bag(dir / "bag" / "metadata.yaml"), ros1(), ros1().scans.size());  // the folder's
}

// A rosbag2 folder as a power loss leaves it: no metadata.yaml. Its storage files are read in split order (bag_2
// before bag_10), zstd messages found by their frames, with a warning; a metadata.yaml whose count for the scan
// topic disagrees with the files is said.
TEST(Ros2Bag, AFolderWithoutMetadataIsReadAndACountThatDisagreesIsSaid) {
  testing::TempDir dir;
  const std::vector<Raw> messages = raw_messages(shared_mcap());
  std::filesystem::create_directories(dir / "bag");
  const std::size_t third = messages.size() / 3;
  const auto at = [&](std::size_t k) { return messages.begin() + static_cast<std::ptrdiff_t>(k); };
  write_db3(dir / "bag" / "bag_2.db3", {at(0), at(third)}, true);
  write_db3(dir / "bag" / "bag_10.db3", {at(third), at(2 * third)}, true);
  write_db3(dir / "bag" / "bag_11.db3", {at(2 * third), messages.end()}, true);
  ASSERT_TRUE(is_ros2_bag(dir / "bag"));
  const RosBagLog recovered = read_ros2_bag(dir / "bag");
  expect_same_scans(recovered, ros1(), ros1().scans.size());
  ASSERT_EQ(recovered.warnings.size(), 1u);
  EXPECT_THAT(recovered.warnings[0], HasSubstr("no metadata.yaml"));
  EXPECT_THAT(recovered.warnings[0], HasSubstr("read the 3 storage files in it in split order"));
  EXPECT_EQ(load_scan_source((dir / "bag").string()).scans.size(), ros1().scans.size());
  // A metadata.yaml that states 5 scans.
  std::ofstream(dir / "bag" / "metadata.yaml")
      << "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: sqlite3\n"
         "  relative_file_paths: [bag_2.db3, bag_10.db3, bag_11.db3]\n"
         "  compression_format: zstd\n  compression_mode: message\n"
         "  topics_with_message_count:\n"
         "    - topic_metadata: {name: /scan, type: sensor_msgs/msg/LaserScan, serialization_format: cdr}\n"
         "      message_count: 5\n";
  const RosBagLog stated = read_ros2_bag(dir / "bag");
  ASSERT_EQ(stated.warnings.size(), 1u);
  EXPECT_THAT(stated.warnings[0], HasSubstr("its metadata.yaml says /scan holds 5 messages, its storage files hold " +
                                            std::to_string(ros1().scans.size())));
  // A folder with neither is no bag.
  std::filesystem::create_directories(dir / "empty");
  EXPECT_FALSE(is_ros2_bag(dir / "empty"));
}

TEST(Ros2Bag, TopicsCanBeChosen) {
  LogReadOptions o;
  o.odom_topic = "/tf";  // odom -> base_link on /tf instead of /odom: the same poses in this bag
  const RosBagLog tf = read_ros2_bag(shared_mcap(), o);
  EXPECT_EQ(tf.odometry_topic, "/tf (odom -> base_link)");
  expect_same_scans(tf, ros1(), ros1().scans.size());
  o = {};
  o.scan_topic = "/base_scan";
  try {
    read_ros2_bag(shared_mcap(), o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("fr079.mcap: no LaserScan message on /base_scan (the bag's topics: /scan "
                                    "(sensor_msgs/msg/LaserScan), "));
  }
}

// Cut at 20 random points: the scans before the cut are read, the same as the whole file's first ones, and a
// warning says where it stopped.
TEST(Ros2Bag, RecordingsCutShortAreReadUpToTheCut) {
  testing::TempDir dir;
  const std::vector<Raw> messages = raw_messages(shared_mcap());
  write_db3(dir / "whole.db3", messages);
  std::mt19937 rng(24);
  for (const std::filesystem::path& whole : {shared_mcap(), dir / "whole.db3"}) {
    std::ifstream in(whole, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), {});
    const std::string ext = whole.extension().string();
    std::size_t cuts_with_scans = 0;
    for (int k = 0; k < 20; ++k) {
      const std::size_t n = std::uniform_int_distribution<std::size_t>(bytes.size() / 20, bytes.size() - 1)(rng);
      std::ofstream(dir / ("cut" + ext), std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(n));
      const RosBagLog log = read_ros2_bag(dir / ("cut" + ext));
      // A cut past the MCAP data section (in its summary) loses nothing and needs no warning.
      if (log.scans.size() < ros1().scans.size() || log.warnings.size() == 1) {
        ASSERT_EQ(log.warnings.size(), 1u) << whole << " cut at " << n;
        EXPECT_THAT(log.warnings[0], HasSubstr("the recording is cut short")) << n;
        // Where the file ends and where reading stopped, both named.
        if (ext == ".mcap") {
          EXPECT_THAT(log.warnings[0], HasSubstr("the file (" + std::to_string(n) + " bytes) ends inside the record "
                                                 "at byte ")) << n;
        } else {
          EXPECT_THAT(log.warnings[0], HasSubstr("whole messages rows of the pages before the cut")) << n;
        }
      }
      expect_same_scans(log, ros1(), log.scans.size(), 2);
      // About the share of the scans that the share of the bytes holds (the messages are not spread evenly: within
      // a tenth of all scans).
      const double expected = static_cast<double>(n) / static_cast<double>(bytes.size()) * ros1().scans.size();
      EXPECT_GT(static_cast<double>(log.scans.size()), expected - 0.1 * ros1().scans.size()) << whole << " " << n;
      cuts_with_scans += !log.scans.empty();
    }
    EXPECT_EQ(cuts_with_scans, 20u) << whole;
  }
}

TEST(Ros2Bag, DamageInTheMiddleIsAnErrorOrSkippedAndCounted) {
  testing::TempDir dir;
  std::ifstream in(shared_mcap(), std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  for (std::size_t i = bytes.size() / 2; i < bytes.size() / 2 + 64; ++i) bytes[i] = static_cast<char>(~bytes[i]);
  std::ofstream(dir / "bad.mcap", std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  try {
    read_ros2_bag(dir / "bad.mcap");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.mcap: the chunk at byte "));
  }
  LogReadOptions o;
  o.skip_damaged = true;
  const RosBagLog log = read_ros2_bag(dir / "bad.mcap", o);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("bad.mcap: skipped 1 damaged chunks or messages (the first: the chunk at"));
  EXPECT_LT(log.scans.size(), ros1().scans.size());
  EXPECT_GT(log.scans.size(), ros1().scans.size() * 8 / 10);
}

TEST(Ros2Bag, ADamagedDb3PageIsAnErrorOrSkipped) {
  testing::TempDir dir;
  write_db3(dir / "whole.db3", raw_messages(shared_mcap()));
  std::fstream f(dir / "whole.db3", std::ios::binary | std::ios::in | std::ios::out);
  f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(dir / "whole.db3") / 2 / 4096 * 4096));
  const std::string garbage(4096, '\x5a');
  f.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  f.close();
  try {
    read_ros2_bag(dir / "whole.db3");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("whole.db3"));
    EXPECT_THAT(e.what(), HasSubstr("skip_damaged reads the rows its pages still hold"));
  }
  LogReadOptions o;
  o.skip_damaged = true;
  const RosBagLog log = read_ros2_bag(dir / "whole.db3", o);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("skipped 1 damaged pages or messages"));
  EXPECT_LT(log.scans.size(), ros1().scans.size());
  EXPECT_GT(log.scans.size(), ros1().scans.size() - 10);  // a page holds a scan or two
}

TEST(Ros2Bag, ForeignAndBrokenInputsAreRefusedByName) {
  testing::TempDir dir;
  std::ofstream(dir / "a.mcap") << "not a bag";
  std::ofstream(dir / "a.db3") << "not a database either, but long enough to hold a header of a hundred bytes "
                                  "............................................";
  std::filesystem::create_directories(dir / "f");
  std::ofstream(dir / "f" / "metadata.yaml") << "rosbag2_bagfile_information:\n  relative_file_paths: []\n";
  std::filesystem::create_directories(dir / "g");
  std::ofstream(dir / "g" / "metadata.yaml") << "rosbag2_bagfile_information:\n  compression_mode: FILE\n"
                                                "  compression_format: zstd\n";
  const std::vector<std::pair<std::filesystem::path, std::string>> cases = {
      {dir / "a.mcap", "a.mcap: not an MCAP file"},
      {dir / "a.db3", "a.db3: not a rosbag2 SQLite file"},
      {dir / "f", "metadata.yaml: relative_file_paths: missing or empty"},
      {dir / "g", "metadata.yaml: compression_mode FILE with format ZSTD is not read"},
      {dir / "absent.mcap", "absent.mcap: no such file"},
  };
  for (const auto& [path, message] : cases) {
    try {
      read_ros2_bag(path);
      ADD_FAILURE() << path << ": no error";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(message));
    }
  }
  // A folder without metadata.yaml is not a rosbag2 folder, and no log either.
  std::filesystem::create_directories(dir / "plain");
  try {
    load_scan_source((dir / "plain").string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plain: a folder without metadata.yaml"));
  }
  // Cut before its first whole message: the error says so.
  {
    std::ifstream in(shared_mcap(), std::ios::binary);
    std::string head(1000, '\0');
    in.read(head.data(), 1000);
    std::ofstream(dir / "head.mcap", std::ios::binary) << head;
  }
  try {
    load_scan_source((dir / "head.mcap").string());
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("head.mcap: no laser scans: the ROS 2 bag holds no sensor_msgs/LaserScan messages; "));
    EXPECT_THAT(e.what(), HasSubstr("the recording is cut short"));
  }
  // A db3 whose only topic is not a scan.
  write_db3(dir / "odom.db3", {{"/odom", "nav_msgs/msg/Odometry", 1, {0, 1, 0, 0}}});
  try {
    read_ros2_bag(dir / "odom.db3");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("odom.db3: messages row 1 (/odom, nav_msgs/msg/Odometry): a CDR message ends"));
  }
}

}  // namespace
}  // namespace partslam::io
