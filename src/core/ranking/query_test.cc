#include "core/ranking/query.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/error.h"
#include "core/testing/simulated_maps.h"

namespace partslam {
namespace {

// The simulator's submaps as candidates of one dataset, with their laser origins (a database's maps).
std::vector<QueryCandidate> candidates_of(const Submaps& maps, std::size_t leave_out) {
  std::vector<QueryCandidate> out;
  for (std::size_t i = 0; i < maps.size(); ++i)
    if (i != leave_out) out.push_back({{&maps[i].points, nullptr, &maps[i].origins}, 0, maps[i].T_world_map});
  return out;
}

// The index of the map that is not a candidate, so rows' candidate indices map back to maps.
std::size_t map_of(std::size_t candidate, std::size_t left_out) { return candidate < left_out ? candidate : candidate + 1; }

TEST(RankQuery, VerifiedDmmAnswersWithACalibratedConfidence) {
  const Submaps& maps = testing::simulated_maps();
  ASSERT_GT(maps.size(), 20u);
  const std::size_t q = maps.size() / 2;
  const std::vector<QueryCandidate> candidates = candidates_of(maps, q);
  const MapView query{&maps[q].points, nullptr, &maps[q].origins};
  const QueryAnswer answer =
      rank_query(parse_method_spec("dmm"), RankingConfig{}, candidates, query, {5, 2, OtherPlace{}});
  ASSERT_EQ(answer.rows.size(), 5u);
  ASSERT_TRUE(answer.calibrated);
  ASSERT_TRUE(answer.confidence.has_value());
  for (const QueryRow& r : answer.rows) {
    ASSERT_TRUE(r.probability.has_value());
    EXPECT_GE(*r.probability, 0.0);
    EXPECT_LE(*r.probability, 1.0);
    EXPECT_DOUBLE_EQ(r.score, *r.probability);  // dmm ranks by the probability
  }
  // The confidence is the best row's probability discounted by the best one in another place; the best row
  // is a neighbour of the query (the simulator's submaps overlap their neighbours).
  const QueryRow& best = answer.rows.front();
  EXPECT_LE(*answer.confidence, *best.probability);
  EXPECT_GE(*answer.confidence, 0.0);
  const Submap& found = maps[map_of(best.candidate, q)];
  EXPECT_LT((found.T_world_map.translation() - maps[q].T_world_map.translation()).norm(), OtherPlace{}.distance);
  // Threads do not change the answer.
  const QueryAnswer serial =
      rank_query(parse_method_spec("dmm"), RankingConfig{}, candidates, query, {5, 1, OtherPlace{}});
  ASSERT_EQ(serial.rows.size(), answer.rows.size());
  for (std::size_t i = 0; i < serial.rows.size(); ++i) EXPECT_EQ(serial.rows[i].candidate, answer.rows[i].candidate);
  EXPECT_EQ(*serial.confidence, *answer.confidence);
}

TEST(RankQuery, Eq1KeepsTheInlierShareMargin) {
  const Submaps& maps = testing::simulated_maps();
  const std::size_t q = maps.size() / 2;
  const std::vector<QueryCandidate> candidates = candidates_of(maps, q);
  const QueryAnswer answer = rank_query(parse_method_spec("dmm:eq1"), RankingConfig{}, candidates,
                                        {&maps[q].points, nullptr, &maps[q].origins}, {3, 2, OtherPlace{}});
  EXPECT_FALSE(answer.calibrated);
  ASSERT_TRUE(answer.confidence.has_value());
  EXPECT_FALSE(answer.rows.front().probability.has_value());
  EXPECT_LE(*answer.confidence, answer.rows.front().pose->inlier_fraction);
}

TEST(RankQuery, RefusesNoCandidatesAndZeroRows) {
  const Submaps& maps = testing::simulated_maps();
  const MapView query{&maps[0].points, nullptr, &maps[0].origins};
  EXPECT_THROW(rank_query(parse_method_spec("dmm"), RankingConfig{}, {}, query, {}), InputError);
  const std::vector<QueryCandidate> candidates = candidates_of(maps, 0);
  EXPECT_THROW(rank_query(parse_method_spec("dmm"), RankingConfig{}, candidates, query, {0, 1, OtherPlace{}}),
               InputError);
}

// A stored query: every other map but those of its own pass within min_gap; a new local map: every stored map.
TEST(RankQuery, CandidatesAreEveryOtherMapButTheQuerysOwnPass) {
  Submaps own(5), other(3);
  for (std::size_t i = 0; i < own.size(); ++i) own[i].id = static_cast<std::int64_t>(1 + i), own[i].travel = 2.0 * i;
  for (std::size_t i = 0; i < other.size(); ++i) other[i].id = static_cast<std::int64_t>(10 + i), other[i].travel = 4.0;
  const std::vector<const Submaps*> datasets = {&own, &other};
  const CandidateChoice stored = choose_candidates(own[2], datasets, 0, 3.0);  // travel 4: 2 and 6 are too recent
  EXPECT_EQ(stored.too_recent, 2u);
  std::vector<std::pair<std::size_t, std::size_t>> maps;
  for (const ChosenMap& c : stored.maps) maps.emplace_back(c.dataset, c.map);
  EXPECT_EQ(maps, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 0}, {0, 4}, {1, 0}, {1, 1}, {1, 2}}));
  Submap fresh;
  fresh.id = -1;
  fresh.travel = 4.0;
  const CandidateChoice all = choose_candidates(fresh, datasets, std::nullopt, 3.0);
  EXPECT_EQ(all.maps.size(), own.size() + other.size());
  EXPECT_EQ(all.too_recent, 0u);
}

}  // namespace
}  // namespace partslam
