#include "io/logs/carmen_log.h"
#include "io/logs/no_return_codes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>

#include "core/error.h"
#include "io/files/line_reader.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;
using testing::TempDir;
using testing::write_text;

constexpr double kPi = std::numbers::pi;

// FLASER: 4 beams at -90, -45, 0, 45 deg (kCarmen: pi/4); 81.91 = no return, 0 = invalid.
// ROBOTLASER1: 3 beams from -90 deg every 0.5 rad, max_range 50 (60 dropped), 2 remissions.
constexpr std::string_view kTinyLog =
    "# CARMEN Logfile\n"
    "PARAM robot_front_laser_max 81.9 nohost 0\n"
    "\n"
    "   \t \n"
    "FLASER 4 1.0 2.0 81.91 0 0.5 1.0 1.5707963267948966 0.4 0.9 1.5 100.25 host 100.3\n"
    "ODOM 0.4 0.9 1.5 0.1 0.2 0.3 100.2 host 100.2\n"
    "NEFF 10\n"
    "VERTEX2 0 1 2 3\n"
    "EDGE2 0 1 0 0 0 1 0 1 1 0 0\n"
    "SYNC 1 host 2\n"
    "UNKNOWN_MSG2 a b c\n"
    "NEFF 12\n"
    "ROBOTLASER1 0 -1.5707963267948966 3.14159 0.5 50.0 0.1 0 3 1.0 60.0 2.0 2 7 8 "
    "1 2 0.5 0.9 1.9 0.3 0 0 0 0 0 200.5 host 200.6\n";

void expect_near(const Vec2& p, double x, double y) {
  EXPECT_NEAR(p.x(), x, 1e-9);
  EXPECT_NEAR(p.y(), y, 1e-9);
}

TEST(CarmenLog, ParsesTinyLogWithKnownAnswers) {
  for (const bool gz : {false, true}) {
    TempDir dir;
    const auto path = dir / "tiny.log";
    write_text(path, kTinyLog, gz);
    const CarmenLog log = read_carmen_log(path);
    ASSERT_EQ(log.scans.size(), 2u);

    const Scan& f = log.scans[0];
    EXPECT_DOUBLE_EQ(f.timestamp, 100.25);
    EXPECT_EQ(f.num_beams, 4);
    EXPECT_DOUBLE_EQ(f.T_world_laser.x, 0.5);
    EXPECT_DOUBLE_EQ(f.T_world_laser.y, 1.0);
    EXPECT_NEAR(f.T_world_laser.theta, kPi / 2, 1e-12);
    EXPECT_DOUBLE_EQ(f.T_world_odom.x, 0.4);
    EXPECT_DOUBLE_EQ(f.T_world_odom.theta, 1.5);
    ASSERT_EQ(f.points_laser.size(), 2u);  // 81.91 and 0 dropped
    expect_near(f.points_laser[0], 0.0, -1.0);
    expect_near(f.points_laser[1], std::sqrt(2.0), -std::sqrt(2.0));
    expect_near(points_world(f)[0], 1.5, 1.0);  // (0,-1) turned by 90 deg, shifted by (0.5, 1)

    const Scan& r = log.scans[1];
    EXPECT_DOUBLE_EQ(r.timestamp, 200.5);
    EXPECT_EQ(r.num_beams, 3);
    EXPECT_DOUBLE_EQ(r.T_world_laser.x, 1.0);
    EXPECT_DOUBLE_EQ(r.T_world_laser.theta, 0.5);
    EXPECT_DOUBLE_EQ(r.T_world_odom.y, 1.9);
    ASSERT_EQ(r.points_laser.size(), 2u);  // 60 >= max_range 50
    expect_near(r.points_laser[0], 0.0, -1.0);
    expect_near(r.points_laser[1], 2.0 * std::cos(-kPi / 2 + 1.0), 2.0 * std::sin(-kPi / 2 + 1.0));

    ASSERT_EQ(log.odometry.size(), 1u);
    EXPECT_DOUBLE_EQ(log.odometry[0].timestamp, 100.2);
    EXPECT_DOUBLE_EQ(log.odometry[0].T_world_odom.y, 0.9);
    EXPECT_DOUBLE_EQ(log.odometry[0].rv, 0.2);

    const CarmenLogStats& s = log.stats;
    EXPECT_EQ(s.lines, 13u);
    EXPECT_EQ(s.flaser, 1u);
    EXPECT_EQ(s.robotlaser, 1u);
    EXPECT_EQ(s.odom, 1u);
    EXPECT_EQ(s.comments, 1u);
    EXPECT_EQ(s.blank, 2u);
    EXPECT_EQ(s.beams, 7u);
    EXPECT_EQ(s.valid_beams, 4u);
    const std::map<std::string, std::size_t, std::less<>> skipped{
        {"EDGE2", 1}, {"NEFF", 2}, {"PARAM", 1}, {"SYNC", 1}, {"UNKNOWN_MSG2", 1}, {"VERTEX2", 1}};
    EXPECT_EQ(s.skipped, skipped);
  }
}

// A raw log of a laser mounted 0.22 m ahead of the robot's axis: the laser pose fields are the robot's odometry
// times the mount. The robot's increments are not the laser's (turning on the spot, the laser swings sideways),
// so the odometry poses are carried onto the laser; a log whose two poses differ by varying amounts (a corrected
// log) is left as it is.
TEST(CarmenLog, CarriesTheOdometryOntoALaserMountedOffTheAxis) {
  const Pose2 mount{0.22, 0.0, 0.0};
  std::string flaser, robotlaser, varying;
  char line[400];
  for (int k = 0; k < 6; ++k) {
    const Pose2 robot{1.0 + 0.1 * k, 2.0, 0.3 * k};  // driving and turning
    const Pose2 laser = robot * mount;
    std::snprintf(line, sizeof line, "FLASER 3 1.0 2.0 3.0 %.6f %.6f %.6f %.6f %.6f %.6f %.3f host %.3f\n", laser.x,
                  laser.y, laser.theta, robot.x, robot.y, robot.theta, 10.0 + k, 10.0 + k);
    flaser += line;
    std::snprintf(line, sizeof line,
                  "ROBOTLASER1 0 -1.5707963267948966 3.14159 1.5707963 50.0 0.1 0 3 1.0 2.0 3.0 0 %.6f %.6f %.6f "
                  "%.6f %.6f %.6f 0 0 0 0 0 %.3f host %.3f\n",
                  laser.x, laser.y, laser.theta, robot.x, robot.y, robot.theta, 10.0 + k, 10.0 + k);
    robotlaser += line;
    const Pose2 corrected = laser * Pose2{0.01 * k, 0.0, 0.02 * k};  // laser poses that are not the odometry's
    std::snprintf(line, sizeof line, "FLASER 3 1.0 2.0 3.0 %.6f %.6f %.6f %.6f %.6f %.6f %.3f host %.3f\n",
                  corrected.x, corrected.y, corrected.theta, robot.x, robot.y, robot.theta, 10.0 + k, 10.0 + k);
    varying += line;
  }
  TempDir dir;
  for (const std::string& text : {flaser, robotlaser}) {
    write_text(dir / "mounted.log", text, false);
    const CarmenLog log = read_carmen_log(dir / "mounted.log");
    ASSERT_TRUE(log.T_base_laser.has_value());
    EXPECT_NEAR(log.T_base_laser->x, 0.22, 1e-5);
    EXPECT_NEAR(log.T_base_laser->y, 0.0, 1e-5);
    EXPECT_NEAR(log.T_base_laser->theta, 0.0, 1e-5);
    ASSERT_EQ(log.scans.size(), 6u);
    for (std::size_t k = 1; k < 6; ++k) {
      // The odometry's increment is the laser's: 0.3 rad of turn moves it 0.22 sin(0.3) m sideways too.
      const Pose2 odometry_step = log.scans[k - 1].T_world_odom.inverse() * log.scans[k].T_world_odom;
      const Pose2 laser_step = log.scans[k - 1].T_world_laser.inverse() * log.scans[k].T_world_laser;
      EXPECT_NEAR(odometry_step.x, laser_step.x, 1e-5);
      EXPECT_NEAR(odometry_step.y, laser_step.y, 1e-5);
      EXPECT_NEAR(odometry_step.theta, laser_step.theta, 1e-5);
    }
  }
  // Too few scans, or a robot that never turned, cannot tell a mount from an offset between two frames.
  const auto first_lines = [](const std::string& text, int n) {
    std::size_t end = 0;
    for (int k = 0; k < n; ++k) end = text.find('\n', end) + 1;
    return text.substr(0, end);
  };
  write_text(dir / "short.log", first_lines(flaser, 2), false);
  EXPECT_FALSE(read_carmen_log(dir / "short.log").T_base_laser.has_value());
  std::string straight;
  for (int k = 0; k < 6; ++k) {
    const Pose2 robot{1.0 + 0.1 * k, 2.0, 0.2}, laser = robot * mount;
    std::snprintf(line, sizeof line, "FLASER 3 1.0 2.0 3.0 %.6f %.6f %.6f %.6f %.6f %.6f %.3f host %.3f\n", laser.x,
                  laser.y, laser.theta, robot.x, robot.y, robot.theta, 10.0 + k, 10.0 + k);
    straight += line;
  }
  write_text(dir / "straight.log", straight, false);
  const CarmenLog straight_log = read_carmen_log(dir / "straight.log");
  EXPECT_FALSE(straight_log.T_base_laser.has_value());
  EXPECT_NEAR(straight_log.scans[2].T_world_odom.x, 1.2, 1e-6);
  write_text(dir / "varying.log", varying, false);
  const CarmenLog log = read_carmen_log(dir / "varying.log");
  EXPECT_FALSE(log.T_base_laser.has_value());
  EXPECT_NEAR(log.scans[3].T_world_odom.x, 1.3, 1e-6);  // the robot's pose fields, as written
  EXPECT_NEAR(log.scans[3].T_world_odom.theta, 0.9, 1e-6);
}

TEST(CarmenLog, StreamingReaderReportsLinesAndOdometry) {
  TempDir dir;
  write_text(dir / "tiny.log", kTinyLog, false);
  CarmenReader reader(dir / "tiny.log");
  ASSERT_TRUE(reader.next().has_value());
  EXPECT_EQ(reader.line(), 5u);
  EXPECT_TRUE(reader.odometry().empty());
  ASSERT_TRUE(reader.next().has_value());
  EXPECT_EQ(reader.line(), 13u);
  EXPECT_EQ(reader.odometry().size(), 1u);
  EXPECT_FALSE(reader.next().has_value());
  EXPECT_EQ(reader.take_odometry().size(), 1u);
  EXPECT_TRUE(reader.odometry().empty());
}

TEST(CarmenLog, SpacingConventionsAndRangeOptions) {
  EXPECT_DOUBLE_EQ(flaser_angle_increment(180, FlaserSpacing::kCarmen), kPi / 180);
  EXPECT_DOUBLE_EQ(flaser_angle_increment(181, FlaserSpacing::kCarmen), kPi / 180);
  EXPECT_DOUBLE_EQ(flaser_angle_increment(360, FlaserSpacing::kCarmen), kPi / 360);
  EXPECT_DOUBLE_EQ(flaser_angle_increment(361, FlaserSpacing::kCarmen), kPi / 360);
  EXPECT_DOUBLE_EQ(flaser_angle_increment(181, FlaserSpacing::kPiOverN), kPi / 181);
  EXPECT_DOUBLE_EQ(flaser_angle_increment(180, FlaserSpacing::kPiOverNMinus1), kPi / 179);

  TempDir dir;
  write_text(dir / "tiny.log", kTinyLog, false);
  LogReadOptions options;
  options.flaser_spacing = FlaserSpacing::kPiOverNMinus1;  // 4 beams: -90, -30, 30, 90 deg
  options.max_usable_range = 1.5;                          // drops the 2 m beams
  const CarmenLog log = read_carmen_log(dir / "tiny.log", options);
  ASSERT_EQ(log.scans[0].points_laser.size(), 1u);
  expect_near(log.scans[0].points_laser[0], 0.0, -1.0);
  options.max_usable_range = 30.0;
  options.min_range = 1.0;  // drops the 1 m beams (range <= min_range)
  const CarmenLog log2 = read_carmen_log(dir / "tiny.log", options);
  ASSERT_EQ(log2.scans[0].points_laser.size(), 1u);
  expect_near(log2.scans[0].points_laser[0], 2.0 * std::cos(-kPi / 6), 2.0 * std::sin(-kPi / 6));

  // A cap on the points of a whole log (decompression amplification), named in the message.
  options = {};
  options.max_points = 1;
  try {
    read_carmen_log(dir / "tiny.log", options);
    FAIL() << "a log over max_points was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_points"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tiny.log"), std::string::npos) << e.what();
  }
  options.max_points = 0;
  EXPECT_THROW(validate(options), InputError);
}

TEST(CarmenLog, AScannersNoReturnCodeIsDroppedOnceTheLogIsReadAndFarReturnsAreKept) {
  // 200 scans of 4 beams: two far returns (30 to 48 m, another range each scan) and two beams at 50.0 m, the
  // code aces's scanner writes when it sees nothing (its maximum: beams beyond it would be dropped too).
  std::string text;
  for (int i = 0; i < 200; ++i) {
    char line[256];
    std::snprintf(line, sizeof line, "FLASER 4 %.2f 50.00 50.00 %.2f 0 0 0 0 0 0 %d.0 host %d.0\n", 30.0 + 0.05 * i,
                  40.0 + 0.04 * i, i, i);
    text += line;
  }
  TempDir dir;
  write_text(dir / "coded.log", text, false);
  const CarmenLog log = read_carmen_log(dir / "coded.log");
  EXPECT_EQ(log.stats.no_return_code_beams, 400u);
  EXPECT_EQ(log.stats.valid_beams, 400u);
  for (const Scan& scan : log.scans) {
    ASSERT_EQ(scan.points_laser.size(), 2u);
    for (const Vec2& p : scan.points_laser) EXPECT_GT(std::abs(p.norm() - 50.0), kNoReturnCodeWindow) << p.norm();
  }
  LogReadOptions off;  // without the search, the codes are read as returns
  off.no_return_code_share = 0.0;
  EXPECT_EQ(read_carmen_log(dir / "coded.log", off).stats.valid_beams, 800u);
}

TEST(CarmenLog, ValidatesOptions) {
  LogReadOptions options;
  options.max_usable_range = 0.0;
  EXPECT_THAT([&] { validate(options); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("max_usable_range")));
  options = {};
  options.min_range = -1.0;
  EXPECT_THAT([&] { validate(options); }, ::testing::ThrowsMessage<InputError>(HasSubstr("min_range")));
  options = {};
  options.no_return_range = std::nan("");
  EXPECT_THAT([&] { validate(options); }, ::testing::ThrowsMessage<InputError>(HasSubstr("no_return_range")));
  EXPECT_THROW(CarmenReader("/nonexistent", options), InputError);
}

// ---- malformed lines: every one must throw naming file, line 2 and the field ----

struct BadLine {
  const char* label;
  std::string line;
  const char* expected;  ///< substring of the message after "<file>:2: "
};

void PrintTo(const BadLine& b, std::ostream* os) { *os << b.label; }  // ctest's name: not the struct's bytes

class MalformedLine : public ::testing::TestWithParam<std::tuple<BadLine, bool>> {};

TEST_P(MalformedLine, ThrowsNamingFileLineAndField) {
  const auto& [bad, gz] = GetParam();
  TempDir dir;
  const auto path = dir / "bad.clf.gz";
  write_text(path, "ODOM 0 0 0 0 0 0 1.0 host 1.0\n" + bad.line + "\nODOM 0 0 0 0 0 0 2.0 host 2.0\n", gz);
  EXPECT_THAT([&] { read_carmen_log(path); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("bad.clf.gz:2: " + std::string(bad.expected))));
  // skip_damaged: the line is skipped and counted, the warning names it.
  LogReadOptions skip;
  skip.skip_damaged = true;
  const CarmenLog log = read_carmen_log(path, skip);
  EXPECT_EQ(log.scans.size(), 0u);
  EXPECT_EQ(log.odometry.size(), 2u);
  EXPECT_EQ(log.stats.damaged, 1u);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("bad.clf.gz: skipped 1 damaged line(s) (skip_damaged); the first: "));
  EXPECT_THAT(log.warnings[0], HasSubstr("bad.clf.gz:2: " + std::string(bad.expected)));
}

const std::string kRanges4 = "FLASER 4 1 2 3 4 ";
const std::string kPoses = "0 0 0 0 0 0 ";
const std::string kRobotHead = "ROBOTLASER1 0 -1.57 3.14 0.5 50 0.1 0 2 1 2 ";
const std::string kRobotTail = "0 0 0 0 0 0 0 0 0 0 0 5.0 host 5.0";

INSTANTIATE_TEST_SUITE_P(
    CarmenLog, MalformedLine,
    ::testing::Combine(
        ::testing::Values(
            BadLine{"too_few_ranges", "FLASER 4 1 2 3 " + kPoses + "1.0 h 1.0",
                    "FLASER logger_timestamp: missing (line has 14 fields, expected 15; does num_readings 4"},
            BadLine{"too_many_ranges", "FLASER 3 1 2 3 4 " + kPoses + "1.0 h 1.0",
                    "FLASER: 1 extra field(s)"},
            BadLine{"ranges_only", "FLASER 4 1 2", "FLASER range[2]: missing"},
            BadLine{"no_count", "FLASER", "FLASER num_readings: missing"},
            BadLine{"fractional_count", "FLASER 4.5 1 2 3 4",
                    "FLASER num_readings: not a whole number '4.5'"},
            BadLine{"huge_count", "FLASER 999999999 1", "FLASER num_readings: out of range '999999999'"},
            BadLine{"zero_count", "FLASER 0 " + kPoses + "1 h 1", "FLASER num_readings: no beams"},
            BadLine{"text_range", "FLASER 4 1 abc 3 4 " + kPoses + "1.0 h 1.0",
                    "FLASER range[1]: not a number 'abc'"},
            BadLine{"nan_range", "FLASER 4 1 2 nan 4 " + kPoses + "1.0 h 1.0",
                    "FLASER range[2]: not a finite number 'nan'"},
            BadLine{"inf_pose", kRanges4 + "0 inf 0 0 0 0 1.0 h 1.0", "FLASER y: not a finite number 'inf'"},
            BadLine{"absurd_pose", kRanges4 + "1e300 0 0 0 0 0 1.0 h 1.0",
                    "FLASER x: implausible coordinate 1e+300 m (beyond +-100000 m)"},
            BadLine{"absurd_odom_pose", kRanges4 + "0 0 0 0 -2e5 0 1.0 h 1.0", "FLASER odom_y: implausible coordinate"},
            BadLine{"absurd_odom", "ODOM 1e20 2 3 0 0 0 5.0 host 5.0", "ODOM x: implausible coordinate 1e+20 m"},
            BadLine{"robot_absurd_pose", kRobotHead + "0 0 0 0 3e5 0 0 0 0 0 0 0 5.0 host 5.0",
                    "ROBOTLASER1 robot_x: implausible coordinate"},
            BadLine{"suffix_garbage", kRanges4 + "0 0 1.5rad 0 0 0 1.0 h 1.0",
                    "FLASER theta: not a number '1.5rad'"},
            BadLine{"overflow", kRanges4 + kPoses + "1e999 h 1.0",
                    "FLASER ipc_timestamp: number out of range"},
            BadLine{"bad_logger_time", kRanges4 + kPoses + "1.0 h x",
                    "FLASER logger_timestamp: not a number 'x'"},
            BadLine{"odom_missing", "ODOM 1 2 3 0 0 0 5.0 host", "ODOM logger_timestamp: missing"},
            BadLine{"odom_text", "ODOM 1 2 - 0 0 0 5.0 host 5.0", "ODOM theta: not a number '-'"},
            BadLine{"odom_extra", "ODOM 1 2 3 0 0 0 5.0 host 5.0 7", "ODOM: 1 extra field(s)"},
            BadLine{"robot_short_head", "ROBOTLASER1 0 -1.57 3.14", "ROBOTLASER1 angular_res: missing"},
            BadLine{"robot_zero_res", "ROBOTLASER1 0 -1.57 3.14 0 50 0.1 0 2 1 2 0 " + kRobotTail,
                    "ROBOTLASER1 angular_res: must not be zero"},
            BadLine{"robot_missing_remissions", kRobotHead + "2 7 " + kRobotTail,
                    "ROBOTLASER1 logger_timestamp: missing"},
            BadLine{"robot_bad_remission", kRobotHead + "2 7 x " + kRobotTail,
                    "ROBOTLASER1 remission[1]: not a number 'x'"},
            BadLine{"robot_bad_pose", kRobotHead + "0 0 0 nan 0 0 0 0 0 0 0 0 5.0 host 5.0",
                    "ROBOTLASER1 laser_theta: not a finite number 'nan'"},
            BadLine{"robot_no_remission_count", "ROBOTLASER1 0 -1.57 3.14 0.5 50 0.1 0 2 1 2",
                    "ROBOTLASER1 num_remissions: missing"},
            BadLine{"not_a_message", "hello world", "not a CARMEN message: line starts with 'hello'"},
            BadLine{"numbers_only", "1216.63 1217.49 0.4 0 0 0 0 0", "not a CARMEN message"},
            BadLine{"binary", std::string("FLASER 4 \x01\x02", 11), "binary data (byte 0x01 at column 10)"},
            BadLine{"nul_byte", std::string("ODOM 1\0 2", 9), "binary data (byte 0x00 at column 7)"}),
        ::testing::Bool()),
    [](const auto& info) {
      return std::string(std::get<0>(info.param).label) + (std::get<1>(info.param) ? "_gz" : "_plain");
    });

// ---- whole-file failures ----

TEST(CarmenLog, RejectsMissingFileDirectoryAndNonLogs) {
  TempDir dir;
  EXPECT_THAT([&] { read_carmen_log(dir / "missing.clf"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("missing.clf: cannot open")));
  std::filesystem::create_directory(dir / "folder");
  EXPECT_THAT([&] { read_carmen_log(dir / "folder"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("is a directory")));
  for (const bool gz : {false, true}) {
    write_text(dir / "empty.log", "", gz);
    EXPECT_THAT([&] { read_carmen_log(dir / "empty.log"); },
                ::testing::ThrowsMessage<InputError>(HasSubstr("empty.log: not a CARMEN log")));
    write_text(dir / "comments.log", "# only\n# comments\nPARAM a b c 0\n", gz);
    EXPECT_THAT(
        [&] { read_carmen_log(dir / "comments.log"); },
        ::testing::ThrowsMessage<InputError>(HasSubstr("not a CARMEN log (no FLASER, ROBOTLASER1 or ODOM")));
  }
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
  testing::write_bytes(dir / "image.png", png);
  EXPECT_THAT([&] { read_carmen_log(dir / "image.png"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("image.png:1: not a CARMEN message")));
  testing::write_bytes(dir / "blob.bin", std::string("\x1f\x9d\x90\x00\x00\x07\n", 7));
  EXPECT_THAT(
      [&] { read_carmen_log(dir / "blob.bin"); },
      ::testing::ThrowsMessage<InputError>(HasSubstr("blob.bin:1: binary data (byte 0x1f at column 1)")));
  testing::write_bytes(dir / "long.log", std::string(LineReader::kMaxLineBytes + 10, 'A'));
  EXPECT_THAT([&] { read_carmen_log(dir / "long.log"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("long.log:1: line longer than")));
}

/// A deterministic log of n FLASER lines whose random ranges do not compress away.
std::string random_log(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> range(0.5, 20.0);
  std::ostringstream out;
  out.precision(4);
  for (int i = 0; i < n; ++i) {
    out << "FLASER 180";
    for (int b = 0; b < 180; ++b) out << ' ' << range(rng);
    out << " 0 0 0 0 0 0 " << i << " host " << i << '\n';
  }
  return out.str();
}

TEST(CarmenLog, TruncatedGzipReadsTheGoodScansWithAWarningCorruptGzipThrows) {
  TempDir dir;
  const auto path = dir / "cut.clf.gz";
  write_text(path, random_log(200), true);
  const std::string full = testing::read_bytes(path);
  EXPECT_EQ(read_carmen_log(path).scans.size(), 200u);
  EXPECT_TRUE(read_carmen_log(path).warnings.empty());
  testing::write_bytes(path, std::string_view(full).substr(0, full.size() * 6 / 10));
  const CarmenLog cut = read_carmen_log(path);
  EXPECT_GT(cut.scans.size(), 50u);
  EXPECT_LT(cut.scans.size(), 200u);
  EXPECT_TRUE(cut.stats.cut_short);
  ASSERT_EQ(cut.warnings.size(), 1u);
  EXPECT_THAT(cut.warnings[0], HasSubstr("cut.clf.gz: the gzip data is cut short: its text ends mid-record after byte "));
  EXPECT_THAT(cut.warnings[0], HasSubstr("read the " + std::to_string(cut.scans.size()) + " scans before it"));

  testing::write_bytes(path, std::string_view(full).substr(0, 2));  // magic bytes only
  EXPECT_THAT([&] { read_carmen_log(path); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("cut.clf.gz: the gzip data is cut short: its text ends "
                                                             "after byte 0 (line 0), before any whole FLASER")));

  std::string corrupt = full;
  for (std::size_t i = 20; i < 60; ++i) corrupt[i] = static_cast<char>(i * 37);
  testing::write_bytes(path, corrupt);
  EXPECT_THAT([&] { read_carmen_log(path); }, ::testing::ThrowsMessage<InputError>(HasSubstr("gzip data")));
  LogReadOptions skip;
  skip.skip_damaged = true;  // corrupt deflate data cannot be read past
  EXPECT_THAT([&] { read_carmen_log(path, skip); }, ::testing::ThrowsMessage<InputError>(HasSubstr("gzip data")));
}

TEST(CarmenLog, DetectsGzipByContentNotNameAndAcceptsCrlf) {
  TempDir dir;
  write_text(dir / "looks_plain.log", kTinyLog, true);
  EXPECT_EQ(read_carmen_log(dir / "looks_plain.log").scans.size(), 2u);
  std::string crlf;
  for (const char c : kTinyLog) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  write_text(dir / "looks_gz.clf.gz", crlf, false);
  const CarmenLog log = read_carmen_log(dir / "looks_gz.clf.gz");
  ASSERT_EQ(log.scans.size(), 2u);
  EXPECT_DOUBLE_EQ(log.scans[1].timestamp, 200.5);
}

TEST(CarmenLog, MutatedLogsParseOrThrowInputErrorNeverAnythingElse) {
  TempDir dir;
  const auto path = dir / "mutant.log";
  std::mt19937 rng(42);
  const std::string alphabet = "0123456789.-+eE naifFLASERODOM#\n\t\x01\xff";
  std::size_t parsed = 0, rejected = 0;
  for (int trial = 0; trial < 300; ++trial) {
    std::string text(kTinyLog);
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0:
          text[at] = alphabet[rng() % alphabet.size()];
          break;
        case 1:
          text.erase(at, 1 + rng() % 8);
          break;
        default:
          text.insert(at, 1, alphabet[rng() % alphabet.size()]);
          break;
      }
    }
    write_text(path, text, trial % 2 == 1);
    try {
      const CarmenLog log = read_carmen_log(path);
      for (const Scan& scan : log.scans) {
        for (const Vec2& p : scan.points_laser) ASSERT_TRUE(std::isfinite(p.x()) && std::isfinite(p.y()));
      }
      ++parsed;
    } catch (const InputError& e) {
      ASSERT_THAT(e.what(), HasSubstr("mutant.log")) << text;
      ++rejected;
    }
  }
  EXPECT_GT(parsed, 10u);
  EXPECT_GT(rejected, 75u);
}

}  // namespace
}  // namespace partslam::io

namespace partslam::io {
namespace {

TEST(CarmenLog, WrittenLogsReadBackToTheSamePointsAndPoses) {
  testing::TempDir dir;
  Scans scans(2);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    Scan& s = scans[k];
    s.timestamp = 1000.5 + static_cast<double>(k);
    s.num_beams = 181;
    s.T_world_laser = s.T_world_odom = Pose2{1.25 * static_cast<double>(k), -3.5, 0.3};
    const double inc = flaser_angle_increment(181, FlaserSpacing::kCarmen);
    for (int b = 0; b < 181; b += 3) {  // every third beam has a return
      const double a = -std::numbers::pi / 2 + b * inc, r = 2.0 + 0.01 * b;
      s.points_laser.emplace_back(r * std::cos(a), r * std::sin(a));
    }
  }
  write_carmen_log(dir / "out.log", scans);
  const CarmenLog back = read_carmen_log(dir / "out.log");
  ASSERT_EQ(back.scans.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_NEAR(back.scans[k].timestamp, scans[k].timestamp, 1e-6);
    EXPECT_NEAR(back.scans[k].T_world_laser.x, scans[k].T_world_laser.x, 1e-6);
    EXPECT_NEAR(back.scans[k].T_world_laser.theta, 0.3, 1e-6);
    ASSERT_EQ(back.scans[k].points_laser.size(), scans[k].points_laser.size());
    for (std::size_t i = 0; i < scans[k].points_laser.size(); ++i)
      EXPECT_LT((back.scans[k].points_laser[i] - scans[k].points_laser[i]).norm(), 1e-4);
  }
  Scans bad(1);
  EXPECT_THROW(write_carmen_log(dir / "bad.log", bad), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad.log"));
}

}  // namespace
}  // namespace partslam::io

namespace partslam::io {
namespace {

using ::testing::HasSubstr;

// ---- recordings cut short, damage in the middle ----

/// The FLASER / ROBOTLASER1 lines of text that end with '\n'.
std::size_t whole_scan_lines(std::string_view text) {
  std::size_t n = 0;
  for (std::size_t at = 0, end; (end = text.find('\n', at)) != std::string_view::npos; at = end + 1) {
    const std::string_view line = text.substr(at, end - at);
    if (line.starts_with("FLASER ") || line.starts_with("ROBOTLASER1 ")) ++n;
  }
  return n;
}

/// The text zlib inflates from a gzip stream, whole or cut short.
std::string inflate_prefix(std::string_view gz) {
  z_stream z{};
  EXPECT_EQ(inflateInit2(&z, 16 + MAX_WBITS), Z_OK);
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz.data()));
  z.avail_in = static_cast<uInt>(gz.size());
  std::string out;
  char buffer[1 << 16];
  int ret = Z_OK;
  while (ret == Z_OK) {
    z.next_out = reinterpret_cast<Bytef*>(buffer);
    z.avail_out = sizeof buffer;
    ret = inflate(&z, Z_NO_FLUSH);
    out.append(buffer, sizeof buffer - z.avail_out);
    if (ret == Z_BUF_ERROR && z.avail_in == 0) break;  // the input is cut short
  }
  inflateEnd(&z);
  return out;
}

void expect_prefix(const Scans& part, const Scans& whole) {
  ASSERT_LE(part.size(), whole.size());
  for (std::size_t i = 0; i < part.size(); ++i) {
    ASSERT_EQ(part[i].timestamp, whole[i].timestamp) << i;
    ASSERT_EQ(part[i].T_world_laser.x, whole[i].T_world_laser.x) << i;
    ASSERT_EQ(part[i].T_world_odom.theta, whole[i].T_world_odom.theta) << i;
    ASSERT_EQ(part[i].points_laser, whole[i].points_laser) << i;
  }
}

// Two shared logs, plain and gzip, cut at 20 random places each: every cut reads the whole lines before the cut
// (the scans a prefix of the whole log's), with a warning saying where the file stopped.
TEST(CarmenLog, RecordingsCutShortReadUpToTheirLastWholeLine) {
  std::mt19937_64 rng(24);
  for (const char* name : {"corrected/orebro-corrected.log.gz", "fr101/fr101-corrected.log.gz"}) {
    const std::filesystem::path source = testing::shared_data() / name;
    if (!std::filesystem::exists(source)) GTEST_SKIP() << source << " is absent";
    SCOPED_TRACE(name);
    const CarmenLog whole = read_carmen_log(source);
    EXPECT_TRUE(whole.warnings.empty());
    const std::string gz = testing::read_bytes(source);
    const std::string text = inflate_prefix(gz);
    ASSERT_EQ(whole_scan_lines(text), whole.scans.size());
    testing::TempDir dir;
    // Ending in a whole FLASER line without its '\n', the file is whole: no warning.
    const std::size_t last_scan = text.rfind("\nFLASER ");
    testing::write_bytes(dir / "no-newline.log", std::string_view(text).substr(0, text.find('\n', last_scan + 1)));
    const CarmenLog no_newline = read_carmen_log(dir / "no-newline.log");
    EXPECT_EQ(no_newline.scans.size(), whole.scans.size());
    EXPECT_TRUE(no_newline.warnings.empty());
    for (int k = 0; k < 20; ++k) {
      const std::size_t cut = text.size() / 10 + rng() % (text.size() * 9 / 10);
      SCOPED_TRACE("plain cut at " + std::to_string(cut));
      testing::write_bytes(dir / "cut.log", std::string_view(text).substr(0, cut));
      const CarmenLog part = read_carmen_log(dir / "cut.log");
      const std::size_t before = whole_scan_lines(std::string_view(text).substr(0, cut));
      EXPECT_GE(part.scans.size(), before);
      EXPECT_LE(part.scans.size(), before + 1);  // the last line without its '\n' may still parse
      expect_prefix(part.scans, whole.scans);
      // The cut line: its fields as far as the cut, and all of them (when they agree, it may parse whole).
      const std::size_t line_start = text.rfind('\n', cut - 1) + 1;
      const auto fields = [](std::string_view line) {
        std::istringstream in{std::string(line)};
        std::size_t n = 0;
        for (std::string f; in >> f;) ++n;
        return n;
      };
      const std::size_t have = fields(std::string_view(text).substr(line_start, cut - line_start));
      const std::size_t want = fields(std::string_view(text).substr(line_start, text.find('\n', line_start) - line_start));
      if (line_start != cut && have != want) {
        ASSERT_EQ(part.warnings.size(), 1u);
        EXPECT_THAT(part.warnings[0], HasSubstr("cut.log: the file ends mid-record after byte "));
        EXPECT_THAT(part.warnings[0], HasSubstr("; read the " + std::to_string(before) + " scans before it"));
      }

      const std::size_t gz_cut = gz.size() / 10 + rng() % (gz.size() * 9 / 10);
      SCOPED_TRACE("gzip cut at " + std::to_string(gz_cut));
      testing::write_bytes(dir / "cut.log.gz", std::string_view(gz).substr(0, gz_cut));
      const CarmenLog gz_part = read_carmen_log(dir / "cut.log.gz");
      EXPECT_EQ(gz_part.scans.size(), whole_scan_lines(inflate_prefix(std::string_view(gz).substr(0, gz_cut))));
      EXPECT_GT(gz_part.scans.size(), 0u);
      expect_prefix(gz_part.scans, whole.scans);
      ASSERT_EQ(gz_part.warnings.size(), 1u);
      EXPECT_THAT(gz_part.warnings[0], HasSubstr("cut.log.gz: the gzip data is cut short: its text ends "));
      EXPECT_THAT(gz_part.warnings[0],
                  HasSubstr("; read the " + std::to_string(gz_part.scans.size()) + " scans before it"));
    }
  }
}

std::string flaser_line(int i, double x) {
  return "FLASER 4 1 2 3 4 " + std::to_string(x) + " 0 0 " + std::to_string(x) + " 0 0 " + std::to_string(i) +
         " host " + std::to_string(i) + "\n";
}

TEST(CarmenLog, DamageInTheMiddleIsAnErrorOrWithSkipDamagedSkippedAndCounted) {
  for (const bool gz : {false, true}) {
    SCOPED_TRACE(gz ? "gzip" : "plain");
    std::string text;
    for (int i = 0; i < 200; ++i) {
      std::string line = flaser_line(i, 0.1 * i);
      if (i == 50) line = line.substr(0, 14) + "\n";  // a line cut short, with more lines after it
      if (i == 120) line = std::string("FLASER 4 \0\0\0\0\n", 14);  // zeros, as a crash leaves in a file
      text += line;
    }
    testing::TempDir dir;
    const auto path = dir / "mid.log";
    testing::write_text(path, text, gz);
    EXPECT_THAT([&] { read_carmen_log(path); },
                ::testing::ThrowsMessage<InputError>(HasSubstr("mid.log:51: FLASER range[3]: missing")));
    LogReadOptions skip;
    skip.skip_damaged = true;
    const CarmenLog log = read_carmen_log(path, skip);
    EXPECT_EQ(log.scans.size(), 198u);
    EXPECT_EQ(log.stats.damaged, 2u);
    EXPECT_FALSE(log.stats.cut_short);
    for (const Scan& s : log.scans) EXPECT_TRUE(s.timestamp != 50 && s.timestamp != 120);
    ASSERT_EQ(log.warnings.size(), 1u);
    EXPECT_THAT(log.warnings[0], HasSubstr("mid.log: skipped 2 damaged line(s) (skip_damaged); the first: "));
    EXPECT_THAT(log.warnings[0], HasSubstr("mid.log:51: FLASER range[3]: missing"));
    // A cut end and damage in the middle: both reported.
    testing::write_text(path, text.substr(0, text.size() - 30), gz);
    const CarmenLog both = read_carmen_log(path, skip);
    EXPECT_EQ(both.scans.size(), 197u);
    ASSERT_EQ(both.warnings.size(), 2u);
    EXPECT_THAT(both.warnings[0], HasSubstr("mid-record after byte "));
    EXPECT_THAT(both.warnings[0], HasSubstr("(line 200); read the 197 scans before it"));
  }
}

// A corrected log with one scan moved 3 km: refused naming the line, or with skip_damaged the scan skipped.
TEST(CarmenLog, AScanWhosePoseJumpsIsRefusedNamingItsLineOrSkipped) {
  std::string text = "# a corrected log\n";
  for (int i = 0; i < 200; ++i) text += flaser_line(i, i == 100 ? 3000.0 : 0.1 * i);
  testing::TempDir dir;
  const auto path = dir / "jump.log";
  testing::write_text(path, text, false);
  EXPECT_THAT([&] { read_carmen_log(path); },
              ::testing::ThrowsMessage<InputError>(HasSubstr(
                  "jump.log:102: the scan's pose (x 3000, y 0) lies 2990.1 m from the previous scan's (line 101), "
                  "beyond LogReadOptions.max_scan_jump 20 m")));
  LogReadOptions skip;
  skip.skip_damaged = true;
  const CarmenLog log = read_carmen_log(path, skip);
  EXPECT_EQ(log.scans.size(), 199u);
  EXPECT_EQ(log.stats.pose_jumps, 1u);
  EXPECT_EQ(log.stats.valid_beams, 199u * 4u);
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_THAT(log.warnings[0], HasSubstr("jump.log: skipped 1 scan(s) whose pose jumps (skip_damaged); the first: "));
  EXPECT_THAT(log.warnings[0], HasSubstr("jump.log:102: the scan's pose"));
  // A jump just within the limit is a scan like any other; the limit is an option.
  LogReadOptions wide;
  wide.max_scan_jump = 5000.0;
  EXPECT_EQ(read_carmen_log(path, wide).scans.size(), 200u);
  wide.max_scan_jump = 0.0;
  EXPECT_THROW(validate(wide), InputError);
}

}  // namespace
}  // namespace partslam::io
