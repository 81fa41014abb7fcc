#include "io/logs/no_return_codes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"

namespace partslam::io {
namespace {

using ::testing::ElementsAre;
using ::testing::DoubleNear;

// A beam of the given range at the given bearing, in the laser frame.
Vec2 beam(double range, double bearing) { return range * Vec2(std::cos(bearing), std::sin(bearing)); }

// n scans of 180 beams: real returns spread between 2 and `far` m, and `coded` beams per scan at `code` (jittered
// by up to `jitter`), as a scanner that saw nothing writes them.
Scans scans_with_code(int n, int coded, double code, double jitter, double far = 60.0) {
  Rng rng(7, 1);
  Scans scans(static_cast<std::size_t>(n));
  for (Scan& s : scans) {
    for (int i = 0; i < 180; ++i) {
      const double bearing = (i - 90) * 0.0174533;
      s.points_laser.push_back(beam(i < coded ? code + rng.uniform(-jitter, jitter) : rng.uniform(2.0, far), bearing));
    }
    s.num_beams = 180;
  }
  return scans;
}

TEST(NoReturnCodes, AScannersCodeIsFoundAndDroppedWithItsJitterAndTheRealFarReturnsKept) {
  Scans scans = scans_with_code(300, 20, 50.0, 0.03);
  const std::vector<double> codes = find_no_return_codes(scans, LogReadOptions{});
  ASSERT_FALSE(codes.empty());
  for (double c : codes) EXPECT_THAT(c, DoubleNear(50.0, 0.035));
  std::size_t far_real = 0;  // real returns beyond 20 m outside the code's window, before
  for (const Scan& s : scans)
    for (const Vec2& p : s.points_laser)
      far_real += p.norm() > 20.0 && (p.norm() < codes.front() - kNoReturnCodeWindow ||
                                      p.norm() > codes.back() + kNoReturnCodeWindow);
  const std::size_t dropped = drop_no_return_codes(scans, codes);
  EXPECT_GE(dropped, 300u * 20u);  // every coded beam, and the few real ones within its window
  std::size_t left_far = 0;
  for (const Scan& s : scans)
    for (const Vec2& p : s.points_laser) {
      EXPECT_FALSE(std::abs(p.norm() - 50.0) < 0.03) << p.norm();
      left_far += p.norm() > 20.0;
    }
  EXPECT_EQ(left_far, far_real);  // nothing else lost
}

TEST(NoReturnCodes, RealReturnsAloneHoldNoCode) {
  const Scans scans = scans_with_code(300, 0, 0.0, 0.0);
  EXPECT_TRUE(find_no_return_codes(scans, LogReadOptions{}).empty());
}

TEST(NoReturnCodes, ACodeBelowTheMinimumRangeOrWithTheShareAtZeroIsNotLookedFor) {
  const Scans scans = scans_with_code(300, 20, 15.0, 0.0);  // a pile-up at 15 m: below the 20 m the codes start at
  EXPECT_TRUE(find_no_return_codes(scans, LogReadOptions{}).empty());
  LogReadOptions off;
  off.no_return_code_share = 0.0;
  EXPECT_TRUE(find_no_return_codes(scans_with_code(300, 20, 50.0, 0.0), off).empty());
  LogReadOptions near;
  near.no_return_code_min_range = 10.0;
  EXPECT_THAT(find_no_return_codes(scans, near), ElementsAre(DoubleNear(15.0, 0.006)));
}

TEST(NoReturnCodes, EveryCodeOfTwoIsDroppedAndTheBeamsBetweenThemKept) {
  Scans scans = scans_with_code(300, 20, 51.15, 0.0);
  for (Scan& s : scans)
    for (int i = 20; i < 30; ++i) s.points_laser[static_cast<std::size_t>(i)] = beam(32.77, 0.0);
  for (std::size_t k = 0; k < scans.size(); ++k)  // a real far return between the codes, 38 to 41 m
    scans[k].points_laser.push_back(beam(38.0 + 0.01 * static_cast<double>(k), 0.1));
  const std::vector<double> codes = find_no_return_codes(scans, LogReadOptions{});
  EXPECT_THAT(codes, ElementsAre(DoubleNear(32.77, 0.006), DoubleNear(51.15, 0.006)));
  drop_no_return_codes(scans, codes);
  for (const Scan& s : scans) {
    bool far = false;
    for (const Vec2& p : s.points_laser) {
      EXPECT_GT(std::abs(p.norm() - 32.77), kNoReturnCodeWindow);
      EXPECT_GT(std::abs(p.norm() - 51.15), kNoReturnCodeWindow);
      far = far || (p.norm() > 37.99 && p.norm() < 41.0);
    }
    EXPECT_TRUE(far);
  }
}

TEST(NoReturnCodes, AFarWallARobotFacedForLongIsNoCodeAndReturnsBeyondIt) {
  // Half of the recording parked facing a wall 25 m ahead: its beams near the perpendicular fall within a
  // centimetre of 25 m (a pile-up as large as a code's), the oblique ones spread over the bins around it.
  Scans scans = scans_with_code(300, 0, 0.0, 0.0);
  for (std::size_t k = 0; k < 150; ++k)
    for (int i = 0; i < 60; ++i) {
      const double bearing = (i - 30) * 0.0087;  // 0.5 deg beams, +-15 deg
      scans[k].points_laser[static_cast<std::size_t>(i)] = beam(25.0 / std::cos(bearing), bearing);
    }
  EXPECT_TRUE(find_no_return_codes(scans, LogReadOptions{}).empty());
}

TEST(NoReturnCodes, ReturnsBeyondAFoundCodeAreKeptWhenMoreThanStragglers) {
  Scans scans = scans_with_code(300, 20, 32.77, 0.0);  // the real returns spread to 60 m, beyond the code
  const std::vector<double> codes = find_no_return_codes(scans, LogReadOptions{});
  ASSERT_THAT(codes, ElementsAre(DoubleNear(32.77, 0.006)));
  std::size_t beyond = 0;
  for (const Scan& s : scans)
    for (const Vec2& p : s.points_laser) beyond += p.norm() > 32.77 + kNoReturnCodeWindow;
  drop_no_return_codes(scans, codes);
  std::size_t left = 0;
  for (const Scan& s : scans)
    for (const Vec2& p : s.points_laser) left += p.norm() > 32.77 + kNoReturnCodeWindow;
  EXPECT_GT(beyond, 0u);
  EXPECT_EQ(left, beyond);
}

TEST(NoReturnCodes, StragglersBeyondTheScannersMaximumGoToo) {
  Scans scans = scans_with_code(300, 20, 50.0, 0.0, 40.0);  // real returns to 40 m, the code the maximum
  for (std::size_t k = 0; k < 30; ++k) scans[k].points_laser.push_back(beam(50.2, 0.0));  // its jitter, 0.2 m above
  const std::vector<double> codes = find_no_return_codes(scans, LogReadOptions{});
  ASSERT_THAT(codes, ElementsAre(DoubleNear(50.0, 0.006)));
  EXPECT_EQ(drop_no_return_codes(scans, codes), 300u * 20u + 30u);
}

TEST(NoReturnCodes, InfiniteRangeLimitsLookOnlySoFar) {
  LogReadOptions o;
  o.max_usable_range = o.no_return_range = INFINITY;
  Scans scans = scans_with_code(300, 20, 50.0, 0.0);
  scans[0].points_laser.push_back(beam(1e6, 0.0));  // a return a thousand kilometres out
  EXPECT_THAT(find_no_return_codes(scans, o), ElementsAre(DoubleNear(50.0, 0.006)));
}

TEST(NoReturnCodes, NoScansOrNoPointsAreNoCodes) {
  Scans scans;
  EXPECT_TRUE(find_no_return_codes(scans, LogReadOptions{}).empty());
  scans.resize(3);
  EXPECT_TRUE(find_no_return_codes(scans, LogReadOptions{}).empty());
  EXPECT_EQ(drop_no_return_codes(scans, {}), 0u);
}

}  // namespace
}  // namespace partslam::io
