#include "core/ranking/scan_context_ranker.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"
#include "core/testing/simulated_maps.h"

namespace partslam {
namespace {

TEST(ScanContext, SpecsParseAndBadOnesNameTheSpec) {
  const MethodSpec native = parse_method_spec("sc");
  EXPECT_EQ(native.spec, "sc");
  EXPECT_EQ(native.label, "Scan Context");
  EXPECT_FALSE(native.traits.needs_points);
  EXPECT_FALSE(native.traits.needs_parts);
  EXPECT_TRUE(native.traits.shardable);
  const MethodSpec small = parse_method_spec("sc:128");
  EXPECT_EQ(small.spec, "sc:128");
  EXPECT_EQ(small.label, "Scan Context 128");
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
