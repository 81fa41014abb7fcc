#include "core/parts/descriptor_matcher.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/testing/parts.h"

namespace partslam {
namespace {

using testing::part;

TEST(RegionSimilarity, KnownAnswers) {
  const Box2 a{0, 2, 0, 2};
  EXPECT_DOUBLE_EQ(region_similarity(a, a), 1.0);                         // identical
  EXPECT_DOUBLE_EQ(region_similarity(a, {5, 7, 0, 2}), 0.0);              // disjoint
  EXPECT_DOUBLE_EQ(region_similarity(a, {2, 4, 0, 2}), 0.0);              // touching edges
  EXPECT_DOUBLE_EQ(region_similarity(a, {1, 3, 0, 2}), 0.5);              // half overlap
  EXPECT_DOUBLE_EQ(region_similarity({0, 4, 0, 4}, {1, 2, 1, 2}), 0.25);  // nested: 1 / sqrt(16 * 1)
  EXPECT_DOUBLE_EQ(region_similarity(a, {1, 3, 1, 3}), 0.25);             // quarter overlap
  EXPECT_DOUBLE_EQ(region_similarity(a, {0, 2, 0, 1}), 1.0 / std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(region_similarity(a, {1, 1, 0, 2}), 0.0);                                 // empty box
  EXPECT_DOUBLE_EQ(region_similarity({1, 3, 0, 2}, a), region_similarity(a, {1, 3, 0, 2}));  // symmetric
}

// Query parts Q1..Q3, stored parts S1..S4, by hand:
//   Q1 = [0,2]^2 (AS 0.5):    f(Q1,S1) = 0.5, f(Q1,S4) = 2 / sqrt(8) = 0.7071 -> max 0.7071
//   Q2 = [10,12]x[0,2] (0.8): f(Q2,S2) = 1
//   Q3 = [20,21]x[0,1] (1.0): f(Q3,S3) = 1 / sqrt(4) = 0.5
MapDescriptor hand_query() {
  return {{part({0, 2, 0, 2}, 0.5), part({10, 12, 0, 2}, 0.8), part({20, 21, 0, 1}, 1.0)}};
}
MapDescriptor hand_stored() {
  return {{part({1, 3, 0, 2}), part({10, 12, 0, 2}), part({20, 22, 0, 2}), part({0, 2, 0, 1})}};
}

TEST(MatchScore, KnownAnswersForTheThreeMatchers) {
  const double r = 1.0 / std::sqrt(2.0);
  EXPECT_NEAR(match_score(hand_query(), hand_stored(), Matcher::kMaxMax), 1.0, 1e-12);
  EXPECT_NEAR(match_score(hand_query(), hand_stored(), Matcher::kSumMax), r + 1.0 + 0.5, 1e-12);
  EXPECT_NEAR(match_score(hand_query(), hand_stored(), Matcher::kSumMaxWeighted), 0.5 * r + 0.8 + 0.5, 1e-12);
  // Max-Max is symmetric; the sums are not (each query part takes its best stored part).
  EXPECT_NEAR(match_score(hand_stored(), hand_query(), Matcher::kMaxMax), 1.0, 1e-12);
  EXPECT_NEAR(match_score(hand_stored(), hand_query(), Matcher::kSumMax), 0.5 + 1.0 + 0.5 + r, 1e-12);
}

TEST(MatchScore, EmptyDescriptorsScoreZero) {
  for (Matcher m : {Matcher::kMaxMax, Matcher::kSumMax, Matcher::kSumMaxWeighted}) {
    EXPECT_EQ(match_score({}, hand_stored(), m), 0.0);
    EXPECT_EQ(match_score(hand_query(), {}, m), 0.0);
  }
}

TEST(MatchScore, OriginGateKeepsOnlyPartPairsThatPutTheMapsClose) {
  // Both query parts overlap the stored part's descriptor box exactly; only the first puts its map's frame
  // where the stored part puts its own (dictionary origin (10, 20) for both).
  Part stored;
  stored.keypoint_box = {-1, 1, -1, 1};
  stored.descriptor_box = {9, 11, 19, 21};
  Part near = stored;
  near.keypoint_box = {-0.5, 1.5, -1, 1};  // frame 0.5 m off
  near.descriptor_box = {9, 11, 19, 21};
  Part far = stored;
  far.keypoint_box = {3, 5, -1, 1};  // frame 4 m off
  EXPECT_NEAR((dictionary_origin(stored) - Vec2(10, 20)).norm(), 0, 1e-12);
  EXPECT_NEAR((dictionary_origin(near) - Vec2(9.5, 20)).norm(), 0, 1e-12);
  // A quarter turn carries the keypoint centre (1, 0) to (0, 1) on the dictionary.
  Part turned = stored;
  turned.keypoint_box = {0, 2, -1, 1};
  turned.rotation = 1;
  EXPECT_NEAR((dictionary_origin(turned) - Vec2(10, 19)).norm(), 0, 1e-12);
  const MapDescriptor q{{near, far}}, g{{stored}};
  EXPECT_DOUBLE_EQ(match_score(q, g, Matcher::kSumMax), 2.0);
  EXPECT_DOUBLE_EQ(match_score(q, g, Matcher::kSumMax, 2.0), 1.0);
  EXPECT_DOUBLE_EQ(match_score(q, g, Matcher::kSumMax, 0.4), 0.0);
  EXPECT_TRUE(passes_origin_gate(far, stored, 0.0));
  EXPECT_FALSE(passes_origin_gate(far, stored, 3.9));
  EXPECT_TRUE(passes_origin_gate(far, stored, 4.0));
  EXPECT_THROW(match_score(q, g, Matcher::kSumMax, -1.0), InputError);
}

TEST(MatcherNames, RoundTrip) {
  for (Matcher m : {Matcher::kMaxMax, Matcher::kSumMax, Matcher::kSumMaxWeighted}) {
    EXPECT_EQ(matcher_from_string(to_string(m)), m);
  }
  EXPECT_EQ(matcher_from_string("smw"), Matcher::kSumMaxWeighted);
  EXPECT_THROW(matcher_from_string("best"), InputError);
}

}  // namespace
}  // namespace partslam
