#include "core/matching/scan_context.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "core/error.h"
#include "core/sim/simulator.h"
#include "core/testing/simulated_maps.h"
#include "core/maps/submap.h"

namespace partslam {
namespace {

/// Exact rotation by +90 deg about the origin.
Points2 rotate90(const Points2& points) {
  Points2 out;
  for (const Vec2& p : points) out.emplace_back(-p.y(), p.x());
  return out;
}

TEST(ScanContext, ConfigValidationNamesTheField) {
  EXPECT_NO_THROW(validate(ScanContextConfig{}));
  EXPECT_NO_THROW(validate(scan_context_128_config()));
  auto message = [](ScanContextConfig c) {
    try {
      validate(c);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  ScanContextConfig c;
  c.rings = 0;
  EXPECT_NE(message(c).find("rings"), std::string::npos);
  c = {};
  c.sectors = -1;
  EXPECT_NE(message(c).find("sectors"), std::string::npos);
  c = {};
  c.max_radius = 0;
  EXPECT_NE(message(c).find("max_radius"), std::string::npos);
  c = {};
  c.shortlist = -1;
  EXPECT_NE(message(c).find("shortlist"), std::string::npos);
}

TEST(ScanContext, BinsCountPointsByRingAndSectorAndDropFarOnes) {
  ScanContextConfig c;
  c.rings = 4;
  c.sectors = 4;
  c.max_radius = 4.0;
  // Ring 0 of sector 0 (twice), ring 2 of sector 1, ring 3 of sector 3; the last point is beyond L_max.
  const Points2 points = {{0.5, 0.1}, {0.3, 0.2}, {-0.1, 2.5}, {0.1, -3.9}, {5.0, 0.0}};
  const ScanContext sc = make_scan_context(points, c);
  EXPECT_EQ(sc.bin(0, 0), 2.0f);
  EXPECT_EQ(sc.bin(2, 1), 1.0f);
  EXPECT_EQ(sc.bin(3, 3), 1.0f);
  float total = 0;
  for (float v : sc.bins) total += v;
  EXPECT_EQ(total, 4.0f);
  EXPECT_EQ(sc.ring_key, (std::vector<float>{0.25f, 0.0f, 0.25f, 0.25f}));
  EXPECT_EQ(sc.bits(), 4 * 4 * 8);
  c.binary = true;
  const ScanContext b = make_scan_context(points, c);
  EXPECT_EQ(b.bin(0, 0), 1.0f);
  EXPECT_EQ(b.masks.at(0), 1u);
  EXPECT_EQ(b.bits(), 16);
}

TEST(ScanContext, ARotationBy90DegIsAQuarterShiftAtDistanceZero) {
  const Points2& points = testing::simulated_maps().at(5).points;
  for (const ScanContextConfig& c : {ScanContextConfig{}, scan_context_128_config()}) {
    const ScanContext a = make_scan_context(rotate90(points), c);
    const ScanContext b = make_scan_context(points, c);
    const ScanContextMatch m = match_scan_contexts(a, b);
    EXPECT_EQ(m.shift, c.sectors / 4) << c.sectors;
    EXPECT_NEAR(m.distance, 0.0, 1e-9) << c.sectors;
    EXPECT_NEAR(m.yaw, std::numbers::pi / 2, 1e-12);
    // Unshifted, the two differ; the ring key does not.
    EXPECT_GT(column_distance(a, b, 0), 0.1) << c.sectors;
    EXPECT_NEAR(ring_key_distance(a, b), 0.0, 1e-6);
    // And back: b is a rotated by -90 deg.
    EXPECT_EQ(match_scan_contexts(b, a).shift, 3 * c.sectors / 4);
  }
}

TEST(ScanContext, BinaryMasksGiveTheCosineOfTheGeneralFormula) {
  const ScanContextConfig c = scan_context_128_config();
  const ScanContext a = make_scan_context(testing::simulated_maps().at(3).points, c);
  const ScanContext b = make_scan_context(testing::simulated_maps().at(9).points, c);
  ScanContext a_plain = a, b_plain = b;
  a_plain.masks.clear(), b_plain.masks.clear();
  for (int s = 0; s < c.sectors; s += 3)
    EXPECT_NEAR(column_distance(a, b, s), column_distance(a_plain, b_plain, s), 1e-12) << s;
}

TEST(ScanContext, EmptyColumnsAreSkippedAndNoCommonColumnIsDistanceOne) {
  ScanContextConfig c;
  c.rings = 2;
  c.sectors = 4;
  c.max_radius = 2.0;
  // a: sectors 0 and 1; b: sector 0 only, same ring as a there. Only sector 0 is compared (distance 0).
  const ScanContext a = make_scan_context({{0.5, 0.1}, {-0.1, 0.5}}, c);
  const ScanContext b = make_scan_context({{0.5, 0.2}}, c);
  EXPECT_DOUBLE_EQ(column_distance(a, b, 0), 0.0);
  // Shifted by 2, no column is occupied in both.
  EXPECT_DOUBLE_EQ(column_distance(a, b, 2), 1.0);
  EXPECT_DOUBLE_EQ(column_distance(a, make_scan_context({}, c), 0), 1.0);
}

}  // namespace
}  // namespace partslam
