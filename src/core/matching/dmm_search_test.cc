#include "core/matching/dmm.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/testing/synthetic_maps.h"

namespace partslam {
namespace {

// Small windows so the brute-force reference stays fast.
DmmConfig small_search_config() {
  DmmConfig config;
  config.linear_window = 2.5;
  config.angular_window = 2.0 * kDegree;
  return config;
}

// A DmmSearch's poses in turn: the first scores match_dmm's optimum, each next one the brute-force maximum over
// the candidates outside the exclusion of every pose returned before (so never more than the one before), with
// and without a bar, lazy or not; at the last, nothing is left.
TEST(DmmSearch, EachNextPoseIsTheBestElsewhereThanThoseBefore) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> offset(-1.5, 1.5);
  for (int p = 0; p < 4; ++p) {
    const testing::SyntheticWorld world = testing::random_world(rng, 20.0, 20);
    const testing::SyntheticPair pair = testing::make_pair(world, rng, {offset(rng), offset(rng)},
                                                           {offset(rng), offset(rng)}, (p % 4) * std::numbers::pi / 2);
    DmmConfig config = small_search_config();
    config.linear_window = 1.2;
    config.search_depth = p % 2 == 0 ? 0 : 2;
    const PreparedQuery q = prepare_query(pair.query, config);
    const PreparedMap m = prepare_map(pair.map, config);
    const double min_distance = 0.5, min_angle = 1.5 * kDegree, r = config.resolution;
    DmmSearch search(q, m, min_distance, min_angle, /*lazy=*/p >= 2);  // both kinds of search, both depths
    std::vector<Pose2> returned;
    const auto outside = [&](double angle, int i, int j) {
      return std::all_of(returned.begin(), returned.end(), [&](const Pose2& pose) {
        return std::hypot(i * r - pose.x, j * r - pose.y) >= min_distance - 1e-9 ||
               std::abs(wrap_angle(angle - pose.theta)) > min_angle;
      });
    };
    const int w = static_cast<int>(std::floor(config.linear_window / r + 1e-9));
    int previous = std::numeric_limits<int>::max(), poses = 0, first = 0;
    for (int k = 0; k < 200; ++k) {
      int brute = -1;
      for (const RotatedQuery& rq : q.rotations) {
        for (int j = -w; j <= w; ++j) {
          for (int i = -w; i <= w; ++i) {
            if (!outside(rq.angle, i, j)) continue;
            int score = 0;
            for (std::size_t c = 0; c < rq.x.size(); ++c) score += m.grid.at(rq.x[c] + i, rq.y[c] + j);
            brute = std::max(brute, score);
          }
        }
      }
      // From the sixth pose on, a bar: poses that do not beat it are not reported.
      const int bar = k >= 5 ? first / 2 : -1;
      const DmmResult next = search.next(bar);
      if (k == 0) first = next.inliers;
      if (brute <= bar) {
        EXPECT_FALSE(next.exact) << "pair " << p;
        EXPECT_EQ(next.inliers, 0) << "pair " << p;
        break;
      }
      if (brute < 0) {  // every candidate returned or excluded
        EXPECT_EQ(next.inliers, 0) << "pair " << p;
        break;
      }
      if (k == 0) {
        EXPECT_EQ(next.inliers, match_dmm(q, m).inliers) << "pair " << p;
      }
      ASSERT_TRUE(next.exact) << "pair " << p << " pose " << k;
      ASSERT_EQ(next.inliers, brute) << "pair " << p << " pose " << k;
      EXPECT_LE(next.inliers, previous);
      EXPECT_TRUE(outside(next.T_map_query.theta, static_cast<int>(std::lround(next.T_map_query.x / r)),
                          static_cast<int>(std::lround(next.T_map_query.y / r))));
      previous = next.inliers;
      returned.push_back(next.T_map_query);
      ++poses;
    }
    EXPECT_GE(poses, 5) << "pair " << p;
  }
  DmmConfig coarse = small_search_config();
  coarse.resolution = 0.2;
  const PreparedQuery other = prepare_query({{0.0, 0.0}}, coarse);
  const PreparedMap map = prepare_map({{0.0, 0.0}}, small_search_config());
  EXPECT_THROW(DmmSearch(other, map, 1.0, 0.1), InputError);
  const PreparedQuery same = prepare_query({{0.0, 0.0}}, small_search_config());
  EXPECT_THROW(DmmSearch(same, map, -1.0, 0.1), InputError);
}

// A search spread over calls with a budget (a tracker's slices; 5000: a few nodes a call) pauses, then yields the
// same poses in the same order as one without, lazy or not, with and without a bar; every call makes progress
// (the calls for a pose end).
TEST(DmmSearch, ABudgetSpreadsTheSearchWithoutChangingItsPoses) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> offset(-1.5, 1.5);
  for (int p = 0; p < 4; ++p) {
    const testing::SyntheticWorld world = testing::random_world(rng, 20.0, 20);
    const testing::SyntheticPair pair = testing::make_pair(world, rng, {offset(rng), offset(rng)},
                                                           {offset(rng), offset(rng)}, p * std::numbers::pi / 2);
    DmmConfig config = small_search_config();
    config.search_depth = p % 2 == 0 ? 0 : 2;
    const PreparedQuery q = prepare_query(pair.query, config);
    const PreparedMap m = prepare_map(pair.map, config);
    const bool lazy = p >= 2;
    DmmSearch whole(q, m, 0.5, 1.5 * kDegree, lazy), sliced(q, m, 0.5, 1.5 * kDegree, lazy);
    int pauses = 0;
    for (int k = 0; k < 12; ++k) {
      const int bar = k >= 6 ? 10 : -1;
      const DmmResult expected = whole.next(bar);
      EXPECT_FALSE(expected.paused);
      DmmResult got;
      for (int call = 0; call < 100000; ++call) {
        got = sliced.next(bar, 5000);
        if (!got.paused) break;
        EXPECT_EQ(got.inliers, 0);
        ++pauses;
      }
      ASSERT_FALSE(got.paused) << "pair " << p << " pose " << k;
      EXPECT_EQ(got.inliers, expected.inliers) << "pair " << p << " pose " << k;
      EXPECT_EQ(got.exact, expected.exact) << "pair " << p << " pose " << k;
      EXPECT_EQ(got.T_map_query.x, expected.T_map_query.x) << "pair " << p << " pose " << k;
      EXPECT_EQ(got.T_map_query.y, expected.T_map_query.y) << "pair " << p << " pose " << k;
      EXPECT_EQ(got.T_map_query.theta, expected.T_map_query.theta) << "pair " << p << " pose " << k;
    }
    EXPECT_GT(pauses, 10) << "pair " << p << ": the budget never stopped the search";
  }
}

}  // namespace
}  // namespace partslam
