#include "io/logs/relations.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <numbers>

#include "core/error.h"
#include "io/testing/test_files.h"

namespace partslam::io {
namespace {

using ::testing::HasSubstr;
using testing::TempDir;
using ::testing::ThrowsMessage;
using testing::write_text;

TEST(Relations, ParsesKnownAnswers) {
  for (const bool gz : {false, true}) {
    TempDir dir;
    write_text(dir / "a.relations",
               "# t1 t2 x y z roll pitch yaw\n"
               "1216.630413 1217.490267 0.407950 -0.016330 0.000000 0.000000 0.000000 -0.069620\n"
               "\n"
               "  10\t20 1 2 0 0 0 4.0  \n",
               gz);
    const Relations relations = read_relations(dir / "a.relations");
    ASSERT_EQ(relations.size(), 2u);
    EXPECT_DOUBLE_EQ(relations[0].t1, 1216.630413);
    EXPECT_DOUBLE_EQ(relations[0].t2, 1217.490267);
    EXPECT_DOUBLE_EQ(relations[0].T_1_2.x, 0.407950);
    EXPECT_DOUBLE_EQ(relations[0].T_1_2.y, -0.016330);
    EXPECT_DOUBLE_EQ(relations[0].T_1_2.theta, -0.069620);
    EXPECT_DOUBLE_EQ(relations[1].t2, 20.0);
    EXPECT_NEAR(relations[1].T_1_2.theta, 4.0 - 2 * std::numbers::pi, 1e-12);  // wrapped to (-pi, pi]
  }
}

TEST(Relations, MalformedLinesThrowNamingFileLineAndField) {
  TempDir dir;
  const auto path = dir / "bad.relations";
  const std::string good = "1 2 0 0 0 0 0 0\n";
  const std::pair<std::string, std::string> cases[] = {
      {"1 2 0.1 0.2 0 0 0", "bad.relations:2: relation yaw: missing (line has 7 fields"},
      {"1 2 0.1 0.2 0 0 0 0 9", "bad.relations:2: relation: 1 extra field(s)"},
      {"1 2 0.1 abc 0 0 0 0", "bad.relations:2: relation y: not a number 'abc'"},
      {"1 nan 0.1 0 0 0 0 0", "bad.relations:2: relation t2: not a finite number 'nan'"},
      {"1 2 0.1 0 0 -inf 0 0", "bad.relations:2: relation roll: not a finite number '-inf'"},
      {std::string("1 2 \x03 0 0 0 0 0"), "bad.relations:2: binary data (byte 0x03 at column 5)"},
  };
  for (const bool gz : {false, true}) {
    for (const auto& [line, expected] : cases) {
      write_text(path, good + line + "\n" + good, gz);
      EXPECT_THAT([&] { read_relations(path); }, ThrowsMessage<InputError>(HasSubstr(expected))) << line;
    }
  }
  write_text(path, "# nothing\n\n", false);
  EXPECT_THAT([&] { read_relations(path); },
              ThrowsMessage<InputError>(HasSubstr("bad.relations: no relations")));
  EXPECT_THAT([&] { read_relations(dir / "none.relations"); },
              ThrowsMessage<InputError>(HasSubstr("none.relations: cannot open")));
  write_text(path, "FLASER 1 1.0 0 0 0 0 0 0 1 h 1\n", true);
  EXPECT_THAT([&] { read_relations(path); },
              ThrowsMessage<InputError>(HasSubstr("bad.relations:1: relation t1: not a number 'FLASER'")));
}

TEST(Relations, FindsScansByTimestamp) {
  Scans scans(4);
  scans[0].timestamp = 10.0;
  scans[1].timestamp = 12.0;
  scans[2].timestamp = 11.0;
  scans[3].timestamp = 11.0;  // duplicate: the first one wins
  EXPECT_EQ(find_scan_by_timestamp(scans, 11.00001, 1e-4), 2u);
  EXPECT_EQ(find_scan_by_timestamp(scans, 12.0), 1u);
  EXPECT_FALSE(find_scan_by_timestamp(scans, 11.5, 1e-4).has_value());
  EXPECT_FALSE(find_scan_by_timestamp({}, 11.0).has_value());
}

}  // namespace
}  // namespace partslam::io
