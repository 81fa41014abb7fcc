#include "core/ranking/ranking.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

#include "core/error.h"
#include "core/sim/simulator.h"
#include "core/testing/simulated_maps.h"
#include "core/maps/submap.h"

namespace partslam {
namespace {

TEST(Ranking, RegistryNamesAreUniqueAndEveryMethodParsesItsSyntax) {
  std::set<std::string_view> names;
  for (const MethodEntry& e : method_registry()) {
    EXPECT_TRUE(names.insert(e.name).second) << e.name;
    EXPECT_EQ(find_method(e.name), &e);
    EXPECT_EQ(e.syntax.substr(0, e.name.size()), e.name);
  }
  EXPECT_EQ(find_method("nope"), nullptr);
  EXPECT_NE(method_syntax_list().find("rerank:R"), std::string::npos);
  MethodSpec unknown;
  unknown.name = "nope";
  unknown.spec = "nope";
  EXPECT_THROW(make_ranker(unknown, {}), InputError);
}

TEST(Ranking, OrderIsStableBestFirst) {
  EXPECT_EQ(ranking_order(std::vector<double>{1.0, 3.0, 1.0, 2.0}), (std::vector<std::size_t>{1, 3, 0, 2}));
}

TEST(Ranking, TiersThenScoresThenFirstStageScores) {
  Ranking r;
  r.scores = {5, 9, 5, 5};
  r.tiers = {1, 0, 1, 1};
  r.shortlist_scores = {0.1, 0.9, 0.3, 0.1};
  EXPECT_EQ(ranking_order(r), (std::vector<std::size_t>{2, 0, 3, 1}));
  EXPECT_TRUE(ranks_above(r, 0, 1));   // a higher tier beats a higher score
  EXPECT_FALSE(ranks_above(r, 0, 3));  // level
  EXPECT_EQ(tied_rank(r, 0), 2.5);
  EXPECT_EQ(tied_rank(r, 1), 4.0);
}

TEST(Ranking, DmmRanksASubsetAndThreadsDoNotChangeIt) {
  const Submaps& maps = testing::simulated_maps();
  ASSERT_GT(maps.size(), 40u);
  const std::vector<MapView> views = testing::point_views(maps);
  const std::unique_ptr<Ranker> ranker = make_ranker(parse_method_spec("dmm:eq1"), {});
  ranker->prepare(views, 2);
  const std::vector<std::size_t> candidates = {3, 10, 0, 25, 40};
  const Ranking one = ranker->rank(views[0], candidates, {1, 0});
  const Ranking two = ranker->rank(views[0], candidates, {2, 0});
  ASSERT_EQ(one.scores.size(), candidates.size());
  EXPECT_EQ(one.scores, two.scores);
  // The query itself (candidate 0 at position 2) matches every one of its points.
  EXPECT_EQ(one.scores[2], static_cast<double>(maps[0].points.size()));
  ASSERT_TRUE(one.direct[2].has_value());
  EXPECT_LE(one.direct[2]->T_map_query.translation().norm(), 0.15);  // within a dilated cell
  // Top-1 pruning keeps the best candidate exact and its score.
  const Ranking top = ranker->rank(views[0], candidates, {1, 1});
  EXPECT_EQ(top.scores[2], one.scores[2]);
  EXPECT_GT(ranker->bits_per_map(), 0.0);
}

// A stored map whose canonical frame is half a quarter turn from the query's (its Manhattan alignment picked
// the other wall direction): the ranking's dMM searches eight rotation families and finds it whole; four
// families (the multiples of 90 degrees only) cannot.
TEST(Ranking, DmmFindsAMapTurnedByHalfAQuarterTurn) {
  const Submaps& maps = testing::simulated_maps();
  const Pose2 turn{0.0, 0.0, std::numbers::pi / 4};
  const Points2 turned = transform(turn, maps[5].points);
  std::vector<MapView> views = testing::point_views(maps);
  views.push_back({&turned, nullptr});
  const std::vector<std::size_t> candidates = {5};
  double share[2] = {0, 0};
  for (const int turns : {4, 8}) {
    RankingConfig config;
    EXPECT_EQ(config.dmm.canonical_turns, 8);  // the default
    config.dmm.canonical_turns = turns;
    const std::unique_ptr<Ranker> ranker = make_ranker(parse_method_spec("dmm:eq1"), config);
    ranker->prepare(views, 2);
    const Ranking r = ranker->rank(views.back(), candidates, {1, 0});
    ASSERT_TRUE(r.direct[0].has_value());
    share[turns == 8] = r.direct[0]->inlier_fraction;
    if (turns == 8) {
      // -45 degrees, or a quarter turn from it when the map is that symmetric
      const double theta = r.direct[0]->T_map_query.theta;
      EXPECT_NEAR(std::remainder(theta + std::numbers::pi / 4, std::numbers::pi / 2), 0.0, 0.03);
      EXPECT_GT(r.direct[0]->inlier_fraction, 0.95);
    }
  }
  EXPECT_LT(share[0], share[1] - 0.2) << share[0] << " vs " << share[1];
}

TEST(Ranking, VerifiedDmmGivesTheQueryItselfTheHighestProbabilityOnAnyThreads) {
  const Submaps& maps = testing::simulated_maps();
  std::vector<MapView> views = testing::point_views(maps);
  for (std::size_t i = 0; i < maps.size(); ++i) views[i].origins = &maps[i].origins;
  const MethodSpec spec = parse_method_spec("dmm");
  EXPECT_TRUE(spec.traits.calibrated);
  const std::unique_ptr<Ranker> ranker = make_ranker(spec, {});
  ranker->prepare(views, 2);
  const std::vector<std::size_t> candidates = {3, 10, 0, 25, 40};
  const Ranking one = ranker->rank(views[0], candidates, {1, 0});
  const Ranking two = ranker->rank(views[0], candidates, {2, 0});
  EXPECT_EQ(one.scores, two.scores);
  ASSERT_EQ(one.probability.size(), candidates.size());
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    ASSERT_TRUE(one.probability[j].has_value());
    EXPECT_EQ(one.scores[j], *one.probability[j]);
    EXPECT_GE(*one.probability[j], 0.0);
    EXPECT_LE(*one.probability[j], 1.0);
  }
  EXPECT_EQ(ranking_order(one).front(), 2u);
  EXPECT_GT(one.scores[2], 0.4);
  EXPECT_LE(one.direct[2]->T_map_query.translation().norm(), 0.05);  // refined below the lattice
}

TEST(Ranking, RerankPutsTheShortlistFirstOrderedByDmm) {
  const Submaps& maps = testing::simulated_maps();
  const std::vector<MapView> views = testing::point_views(maps);
  // A first stage without parts: every stored map scores 0, so the shortlist is the first R candidates.
  MethodSpec spec = parse_method_spec("rerank:3:hmm:3");
  std::vector<std::vector<Part>> parts(maps.size());
  std::vector<MapView> with_parts = views;
  for (std::size_t i = 0; i < maps.size(); ++i) with_parts[i].parts = &parts[i];
  RankingConfig config;
  const std::unique_ptr<Ranker> rerank = make_ranker(spec, config);
  rerank->prepare(with_parts, 1);
  const std::unique_ptr<Ranker> dmm = make_ranker(parse_method_spec("dmm"), config);
  dmm->prepare(with_parts, 1);
  const std::vector<std::size_t> candidates = {5, 0, 7, 9, 11};
  const Ranking r = rerank->rank(with_parts[0], candidates);
  const Ranking d = dmm->rank(with_parts[0], candidates);
  ASSERT_EQ(r.shortlist_scores.size(), candidates.size());
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    EXPECT_EQ(r.direct[j].has_value(), j < 3) << j;
    EXPECT_EQ(r.tiers[j], j < 3 ? 1 : 0) << j;
    if (j < 3) {
      EXPECT_TRUE(ranks_above(r, j, 3)) << j;
      EXPECT_EQ(r.direct[j]->inliers, d.direct[j]->inliers);
      EXPECT_EQ(r.scores[j], d.scores[j]);
      ASSERT_TRUE(r.probability[j].has_value());
      EXPECT_EQ(*r.probability[j], d.scores[j]);
    }
  }
  EXPECT_TRUE(ranks_above(r, 1, 0));  // the query itself beats every other shortlisted map
  EXPECT_EQ(ranking_order(r).front(), 1u);
  EXPECT_EQ(tied_rank(r, 1), 1.0);
  EXPECT_EQ(tied_rank(r, 3), 4.5);  // the two below the shortlist tie (their first-stage scores are all 0)
}

TEST(Ranking, RerankAskedForItsTopGivesTheSameShortlist) {
  // match --top K and loops read only the top: the first stage then ranks only its top R (through the grid
  // index on a large database; scanned here), and the shortlist and its dMM results do not change.
  const Submaps& maps = testing::simulated_maps();
  const std::vector<MapView> views = testing::point_views(maps);
  const MethodSpec spec = parse_method_spec("rerank:4:succinct");
  EXPECT_EQ(spec.traits.shortlist, 4);
  EXPECT_EQ(parse_method_spec("dmm").traits.shortlist, 0);
  const std::unique_ptr<Ranker> rerank = make_ranker(spec, {});
  rerank->prepare(views, 1);
  std::vector<std::size_t> everyone(maps.size());
  for (std::size_t i = 0; i < everyone.size(); ++i) everyone[i] = i;
  const Ranking all = rerank->rank(views[7], everyone, {1, 0});
  for (int k : {1, 4, 6}) {
    const Ranking top = rerank->rank(views[7], everyone, {1, k});
    const std::vector<std::size_t> order = ranking_order(all), top_order = ranking_order(top);
    for (std::size_t j = 0; j < 4; ++j) {
      EXPECT_EQ(top_order[j], order[j]) << "k " << k << " rank " << j;
      EXPECT_EQ(top.scores[top_order[j]], all.scores[order[j]]) << "k " << k << " rank " << j;
      EXPECT_EQ(top.tiers[top_order[j]], 1) << "k " << k << " rank " << j;
    }
  }
}

}  // namespace
}  // namespace partslam
