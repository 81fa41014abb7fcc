#include "core/descriptor_matcher.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace partslam {
namespace {

Part part(const Box2& descriptor_box, double as = 1.0) {
  Part p;
  p.descriptor_box = descriptor_box;
  p.keypoint_box = {0, descriptor_box.width(), 0, descriptor_box.height()};
  p.appearance_score = as;
  return p;
}

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

TEST(MatcherNames, RoundTrip) {
  for (Matcher m : {Matcher::kMaxMax, Matcher::kSumMax, Matcher::kSumMaxWeighted}) {
    EXPECT_EQ(matcher_from_string(to_string(m)), m);
  }
  EXPECT_EQ(matcher_from_string("smw"), Matcher::kSumMaxWeighted);
  EXPECT_THROW(matcher_from_string("best"), InputError);
}

}  // namespace
}  // namespace partslam
