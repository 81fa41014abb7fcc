#include "core/slam/log_stretch.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "core/sim/simulator.h"

namespace partslam {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// One lap of the simulated building, its scans 0.1 m of travel apart at 0.5 m/s, from time 100 s on.
const Scans& lap() {
  static const Scans scans = [] {
    SimulatorConfig config;
    config.route.laps = 1;
    config.route.room_visits = 1;
    config.route.start_time = 100.0;
    return simulate(config).scans;
  }();
  return scans;
}

std::string error_of(const StretchSpec& spec, bool every_given = false, const std::string& every = "") {
  try {
    validate(spec, every_given, every);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LogStretch, ByTravelOrByTheLogsClockTheSameScans) {
  const std::vector<double> s = travel_distances(lap());
  StretchSpec by_travel;
  by_travel.from_m = 10.0, by_travel.to_m = 12.0;
  const LogStretch a = find_log_stretch(lap(), by_travel, 2.0, std::nullopt, "lap");
  ASSERT_TRUE(a.stretch);
  EXPECT_EQ(a.log_scans, lap().size());
  EXPECT_GE(s[a.first], 10.0);
  EXPECT_LT(s[a.first - 1], 10.0);
  EXPECT_GE(s[a.end], 12.0);
  EXPECT_LT(s[a.end - 1], 12.0);
  EXPECT_DOUBLE_EQ(a.from_time, lap()[a.first].timestamp);
  // The same scans by their stamps, and one window from the first of them.
  StretchSpec by_time;
  by_time.from_time = a.from_time, by_time.to_time = lap()[a.end].timestamp;
  const LogStretch b = find_log_stretch(lap(), by_time, 2.0, std::nullopt, "lap");
  EXPECT_EQ(b.first, a.first);
  EXPECT_EQ(b.end, a.end);
  StretchSpec at;
  at.at_time = a.from_time;
  const LogStretch c = find_log_stretch(lap(), at, 2.0, std::nullopt, "lap");
  EXPECT_EQ(c.first, a.first);
  std::size_t window_end = c.first;
  while (window_end < s.size() && s[window_end] < s[a.first] + 2.0) ++window_end;
  EXPECT_EQ(c.end, window_end);
  // Its local map is the stored submap's shape, anchored within the stretch, at its travel.
  const Submap m = stretch_local_map(a, SubmapConfig{}, "lap");
  EXPECT_GE(m.anchor_scan, static_cast<std::int64_t>(a.first));
  EXPECT_LT(m.anchor_scan, static_cast<std::int64_t>(a.end));
  EXPECT_DOUBLE_EQ(m.travel, 10.0);
  EXPECT_GT(m.points.size(), 50u);
}

TEST(LogStretch, ScanMatchingRunsOverTheMarginAndTheStretchOnly) {
  StretchSpec spec;
  spec.from_m = 30.0, spec.to_m = 32.0;
  const LogStretch plain = find_log_stretch(lap(), spec, 2.0, std::nullopt, "lap");
  const LogStretch matched = find_log_stretch(lap(), spec, 2.0, FrontEndConfig{}, "lap");
  EXPECT_EQ(matched.end - matched.first, plain.end - plain.first);
  EXPECT_EQ(matched.scans.size(), matched.matched_scans);
  EXPECT_EQ(matched.scans.size(), matched.end);  // nothing after the stretch
  const std::vector<double> s = travel_distances(lap());
  const std::size_t start = plain.first - matched.first;  // the margin's first scan in the log
  EXPECT_GE(s[start], 30.0 - kScanMatchMargin);
  EXPECT_LT(s[start - 1], 30.0 - kScanMatchMargin);
  EXPECT_EQ(matched.scans[matched.first].timestamp, lap()[plain.first].timestamp);
  // No stretch: the whole log, scan-matched whole.
  const LogStretch whole = find_log_stretch(lap(), {}, 2.0, std::nullopt, "lap");
  EXPECT_FALSE(whole.stretch);
  EXPECT_EQ(whole.scans.size(), lap().size());
  EXPECT_THROW(stretch_local_map(whole, SubmapConfig{}, "lap"), InputError);
}

TEST(LogStretch, AStretchOutsideTheLogOrNotOneStretchIsRefusedByName) {
  StretchSpec past;
  past.from_m = 1e5, past.to_m = 1e5 + 2;
  EXPECT_THAT([&] { find_log_stretch(lap(), past, 2.0, std::nullopt, "lap.log"); },
              ThrowsMessage<InputError>(HasSubstr("lap.log: no scan between 100000 and 100002 m of travel")));
  StretchSpec before;
  before.at_time = 5.0;  // seconds since the first scan, not the log's clock
  EXPECT_THAT([&] { find_log_stretch(lap(), before, 2.0, std::nullopt, "lap.log"); },
              ThrowsMessage<InputError>(HasSubstr("--at 5 s lies before the log's first scan")));
  StretchSpec two;
  two.from_m = 1.0, two.to_m = 2.0, two.at_time = 100.0;
  EXPECT_THAT(error_of(two), HasSubstr("give one stretch of the log"));
  StretchSpec half;
  half.from_time = 100.0;
  EXPECT_THAT(error_of(half), HasSubstr("--from-time and --to-time go together"));
  EXPECT_THAT(error_of({}), HasSubstr("needs a stretch"));
  EXPECT_THAT(error_of({}, false, "--every M"), HasSubstr(", or --every M"));
  EXPECT_EQ(error_of({}, true), "");
}

}  // namespace
}  // namespace partslam
