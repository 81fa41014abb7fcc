#include "core/slam/front_end_agreement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.h"

namespace partslam {
namespace {

// A straight drive along x, a scan every 0.2 m, stamped 0.1 s apart.
Scans straight(int n) {
  Scans s(n);
  for (int k = 0; k < n; ++k) s[k].timestamp = 0.1 * k, s[k].T_world_laser = {0.2 * k, 0, 0};
  return s;
}

// The same drive, turning by `turn` in total, spread evenly over scans [from, to), then straight again.
Scans bent(int n, int from, int to, double turn) {
  Scans s = straight(n);
  Pose2 pose;
  for (int k = 1; k < n; ++k) {
    const double dtheta = (k > from && k <= to) ? turn / (to - from) : 0.0;
    pose = pose * Pose2{0.2, 0, dtheta};
    s[k].T_world_laser = pose;
  }
  return s;
}

TEST(FrontEndAgreement, TwoFrontEndsOnOnePathAgree) {
  const Scans a = straight(500);  // 100 m
  const FrontEndAgreement r = compare_front_ends(a, a, SecondOpinionConfig{});
  EXPECT_TRUE(r.judged);
  EXPECT_TRUE(r.passed);
  EXPECT_EQ(r.paired, 500u);
  EXPECT_NEAR(static_cast<double>(r.windows), 350, 1);  // each scan with 30 m of travel after it (+- rounding)
  EXPECT_NEAR(r.max_turn, 0.0, 1e-12);
  EXPECT_NEAR(r.max_shift, 0.0, 1e-9);
}

// One path bends by 40 degrees over 10 m where the other goes straight: the two part ways, and the window shown
// holds the bend. The same paths moved or turned as a whole (another frame) still agree.
TEST(FrontEndAgreement, APathBentWhereTheOtherIsStraightPartsFromIt) {
  const Scans a = straight(500);
  const Scans b = bent(500, 200, 250, 40 * std::numbers::pi / 180);
  const FrontEndAgreement r = compare_front_ends(a, b, SecondOpinionConfig{});
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.max_turn, 40 * std::numbers::pi / 180, 1e-9);
  EXPECT_LT(r.worst_first, 250u);  // the window shown overlaps the bend
  EXPECT_GT(r.worst_last, 200u);
  EXPECT_NEAR(static_cast<double>(r.worst_last - r.worst_first), 150, 1);  // 30 m at 0.2 m a scan

  Scans moved = b;
  for (Scan& s : moved) s.T_world_laser = Pose2{5, -3, 1.0} * s.T_world_laser;
  const FrontEndAgreement same = compare_front_ends(b, moved, SecondOpinionConfig{});
  EXPECT_TRUE(same.passed);
  EXPECT_NEAR(same.max_turn, 0.0, 1e-9);
  EXPECT_NEAR(same.max_shift, 0.0, 1e-9);

  // A gentle bend (5 degrees over the same stretch) stays within the default limits.
  EXPECT_TRUE(compare_front_ends(a, bent(500, 200, 250, 5 * std::numbers::pi / 180), SecondOpinionConfig{}).passed);
  // A slide along the path (the second's steps 20 % longer over 20 m) fails on the shift alone.
  Scans slid = a;
  for (int k = 0; k < 500; ++k) slid[k].T_world_laser.x = 0.2 * k + 0.04 * std::clamp(k - 200, 0, 100);
  const FrontEndAgreement slide = compare_front_ends(a, slid, SecondOpinionConfig{});
  EXPECT_FALSE(slide.passed);
  EXPECT_NEAR(slide.max_turn, 0.0, 1e-12);
  EXPECT_NEAR(slide.max_shift, 4.0, 1e-9);
}

// Where a used loop closure attaches within a window, the map there does not rest on the front end alone: the
// window is pinned and not compared. Windows without a pin are compared as before.
TEST(FrontEndAgreement, WindowsThatLoopClosuresTieAreNotCompared) {
  const Scans a = straight(500);
  const Scans b = bent(500, 200, 250, 40 * std::numbers::pi / 180);
  std::vector<std::size_t> every_tenth;
  for (std::size_t k = 0; k < 500; k += 10) every_tenth.push_back(k);
  const FrontEndAgreement tied = compare_front_ends(a, b, SecondOpinionConfig{}, every_tenth);
  EXPECT_TRUE(tied.passed);
  EXPECT_FALSE(tied.judged);
  EXPECT_EQ(tied.windows, 0u);
  EXPECT_NEAR(static_cast<double>(tied.pinned), 350, 1);

  // Pins at the two ends of the log only: the windows over the bend have none, and fail as without pins.
  const FrontEndAgreement ends = compare_front_ends(a, b, SecondOpinionConfig{}, {0, 499});
  EXPECT_FALSE(ends.passed);
  EXPECT_NEAR(static_cast<double>(ends.pinned), 2, 1);  // the first window and the last
  EXPECT_NEAR(ends.max_turn, 40 * std::numbers::pi / 180, 1e-9);

  // Pins only before the bend (scans 0-190): the windows that start after the last pin and hold the whole bend
  // (scans 191-200 to 341-350) are compared; a pin out of range is ignored.
  std::vector<std::size_t> before{100000};
  for (std::size_t k = 0; k <= 190; k += 10) before.push_back(k);
  const FrontEndAgreement half = compare_front_ends(a, b, SecondOpinionConfig{}, before);
  EXPECT_FALSE(half.passed);
  EXPECT_GT(half.pinned, 0u);
  EXPECT_NEAR(half.max_turn, 40 * std::numbers::pi / 180, 1e-9);
}

// Scans are paired by timestamp: a scan only one front end kept, or a timestamp seen twice, is left out.
TEST(FrontEndAgreement, ScansArePairedByTheirTimestamps) {
  const Scans a = straight(400);
  Scans b;
  for (int k = 0; k < 400; ++k)
    if (k % 7 != 3) b.push_back(a[k]);  // the second dropped some scans
  Scans c = a;
  c[10].timestamp = c[11].timestamp;  // stamped twice: both left out (and a's scan 10 has no partner)
  EXPECT_EQ(compare_front_ends(a, b, SecondOpinionConfig{}).paired, b.size());
  EXPECT_EQ(compare_front_ends(c, a, SecondOpinionConfig{}).paired, 398u);
  EXPECT_EQ(compare_front_ends(a, c, SecondOpinionConfig{}).paired, 398u);
  EXPECT_TRUE(compare_front_ends(a, b, SecondOpinionConfig{}).passed);
}

TEST(FrontEndAgreement, ALogShorterThanAWindowIsNotJudged) {
  const Scans a = straight(100);  // 20 m
  const FrontEndAgreement r = compare_front_ends(a, bent(100, 10, 60, 1.0), SecondOpinionConfig{});
  EXPECT_FALSE(r.judged);
  EXPECT_TRUE(r.passed);
  EXPECT_EQ(r.windows, 0u);
  EXPECT_FALSE(compare_front_ends({}, {}, SecondOpinionConfig{}).judged);
}

TEST(FrontEndAgreement, ValidateNamesTheField) {
  EXPECT_NO_THROW(validate(SecondOpinionConfig{}));
  const auto message = [](const SecondOpinionConfig& c) -> std::string {
    try {
      validate(c);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  SecondOpinionConfig c;
  c.window = 0;
  EXPECT_EQ(message(c).rfind("second opinion config: window must be", 0), 0u) << message(c);
  c = {};
  c.max_turn = std::nan("");
  EXPECT_EQ(message(c).rfind("second opinion config: max_turn must be", 0), 0u) << message(c);
  c = {};
  c.fine_sigma = -1;
  EXPECT_EQ(message(c).rfind("second opinion config: fine_sigma must be", 0), 0u) << message(c);
}

}  // namespace
}  // namespace partslam
