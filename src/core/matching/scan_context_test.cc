#include "core/matching/scan_context.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

#include "core/error.h"
#include "core/matching/ranking.h"
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

TEST(ScanContext, SpecsParseAndBadOnesNameTheSpec) {
  const MethodSpec native = parse_method_spec("sc");
  EXPECT_EQ(native.spec, "sc");
  EXPECT_EQ(native.label(), "Scan Context");
  EXPECT_EQ(native.size, 0);
  EXPECT_FALSE(native.needs_points);
  EXPECT_FALSE(native.needs_parts);
  const MethodSpec small = parse_method_spec("sc:128");
  EXPECT_EQ(small.spec, "sc:128");
  EXPECT_EQ(small.label(), "Scan Context 128");
  EXPECT_EQ(small.size, 128);
  for (const std::string bad : {"sc:64", "sc:x", "sc:128:1", "sc:"}) {
    try {
      parse_method_spec(bad);
      ADD_FAILURE() << bad << " parsed";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
    }
  }
  // A succinct first stage for rerank.
  EXPECT_EQ(parse_method_spec("rerank:5:sc:128").spec, "rerank:5:sc:128");
}

TEST(ScanContext, BitsPerMap) {
  const std::unique_ptr<Ranker> small = make_ranker(parse_method_spec("sc:128"), {});
  EXPECT_EQ(small->bits_per_map(), 128.0);
  const std::unique_ptr<Ranker> native = make_ranker(parse_method_spec("sc"), {});
  EXPECT_EQ(native->bits_per_map(), 20.0 * 60.0 * 8.0);
}

TEST(ScanContext, AMapRanksItselfFirstAndThreadsDoNotChangeScores) {
  const Submaps& maps = testing::simulated_maps();
  ASSERT_GT(maps.size(), 40u);
  const std::vector<MapView> views = testing::point_views(maps);
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < 40; i += 2) candidates.push_back(i);  // 20 candidates, the query 12 among them
  const std::size_t query = 12, at = 6;
  for (const std::string spec : {"sc", "sc:128"}) {
    const std::unique_ptr<Ranker> one = make_ranker(parse_method_spec(spec), {});
    const std::unique_ptr<Ranker> two = make_ranker(parse_method_spec(spec), {});
    one->prepare(views, 1);
    two->prepare(views, 2);
    const Ranking r1 = one->rank(views[query], candidates, {1, 0});
    const Ranking r2 = two->rank(views[query], candidates, {2, 0});
    ASSERT_EQ(r1.scores.size(), candidates.size());
    EXPECT_EQ(r1.scores, r2.scores) << spec;
    EXPECT_NEAR(r1.scores[at], 0.0, 1e-12) << spec;  // distance 0 to itself
    EXPECT_EQ(ranking_order(r1.scores).front(), at) << spec;
    // The shortlist (10 of 20) puts the rest below it, ordered by ring-key distance.
    EXPECT_EQ(std::count_if(r1.scores.begin(), r1.scores.end(), [](double s) { return s <= kScanContextShortlistOut; }),
              10)
        << spec;
  }
}

TEST(ScanContext, ShortlistAllScoresEveryCandidate) {
  const Submaps& maps = testing::simulated_maps();
  const std::vector<MapView> views = testing::point_views(maps);
  ScanContextConfig c;
  c.shortlist = 0;
  const std::unique_ptr<Ranker> ranker = make_scan_context_ranker(c);
  ranker->prepare(views, 2);
  const std::vector<std::size_t> candidates = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  const Ranking r = ranker->rank(views[4], candidates);
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    EXPECT_GE(r.scores[j], -1.0) << j;
    EXPECT_DOUBLE_EQ(r.scores[j], -match_scan_contexts(make_scan_context(maps[4].points, c),
                                                       make_scan_context(maps[candidates[j]].points, c))
                                       .distance);
  }
  EXPECT_EQ(ranking_order(r.scores).front(), 3u);
}

}  // namespace
}  // namespace partslam
