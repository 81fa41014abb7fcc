#include "core/matching/grid_index.h"

#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "core/error.h"
#include "core/testing/simulated_maps.h"

namespace partslam {
namespace {

// A place: points along a few random walls within +-5 m.
Points2 random_place(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-5.0, 5.0), t(0.0, 1.0);
  Points2 points;
  for (int w = 0; w < 6; ++w) {
    const Vec2 a{u(rng), u(rng)}, b{u(rng), u(rng)};
    for (int i = 0; i < 40; ++i) points.push_back(a + t(rng) * (b - a));
  }
  return points;
}

// A visit of a place: turned by a quarter turn, moved by up to half a metre, a fifth of the points missed.
Points2 visit(const Points2& place, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> offset(-0.5, 0.5);
  std::uniform_int_distribution<int> turns(0, 3);
  std::bernoulli_distribution seen(0.8);
  const int k = turns(rng);
  const Vec2 d{offset(rng), offset(rng)};
  Points2 out;
  for (Vec2 p : place) {
    if (!seen(rng)) continue;
    for (int turn = 0; turn < k; ++turn) p = Vec2{-p.y(), p.x()};
    out.push_back(p + d);
  }
  return out;
}

// A fleet's database: visits of `places` places, with mu quantised to 7 bits like the ranker's and some grids
// exactly duplicated so that scores tie.
struct Synthetic {
  std::vector<Points2> places;
  std::vector<GridBits> grids;
  std::vector<double> mu;
};

Synthetic synthetic(std::size_t n, int places, std::uint64_t seed, const GridConfig& config) {
  std::mt19937_64 rng(seed);
  Synthetic s;
  for (int p = 0; p < places; ++p) s.places.push_back(random_place(rng));
  std::uniform_int_distribution<int> place(0, places - 1), level(0, 127);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && i % 17 == 0) {
      s.grids.push_back(s.grids[i / 2]);
      s.mu.push_back(s.mu[i / 2]);
      continue;
    }
    s.grids.push_back(make_grid(visit(s.places[static_cast<std::size_t>(place(rng))], rng), config));
    s.mu.push_back(level(rng) / 127.0);
  }
  return s;
}

void expect_equal(const std::vector<GridMatch>& index, const std::vector<GridMatch>& scan, const std::string& what) {
  ASSERT_EQ(index.size(), scan.size()) << what;
  for (std::size_t r = 0; r < scan.size(); ++r) {
    EXPECT_EQ(index[r].index, scan[r].index) << what << " rank " << r;
    EXPECT_EQ(index[r].score, scan[r].score) << what << " rank " << r;  // bit for bit
  }
}

TEST(GridIndex, TopKEqualsTheScanOnSyntheticDatabases) {
  const GridConfig config = succinct_grid_config();
  std::mt19937_64 rng(11);
  for (const auto& [n, places] : {std::pair<std::size_t, int>{5000, 40}, {3000, 3000}, {50, 5}}) {
    const Synthetic db = synthetic(n, places, 7 + n, config);
    for (double hub_weight : {0.0, 1.0}) {
      for (int leaf : {1, 32}) {
        const GridIndex index(db.grids, db.mu, hub_weight, {.leaf_size = leaf});
        EXPECT_EQ(index.size(), n);
        for (int t = 0; t < 3; ++t) {
          const GridQuery q(make_query_grids(visit(db.places[rng() % db.places.size()], rng), config), config);
          for (std::size_t k : {std::size_t{1}, std::size_t{7}, std::size_t{100}, n + 3}) {
            GridSearchStats stats;
            const std::string what = "n " + std::to_string(n) + " hub " + std::to_string(hub_weight) + " leaf " +
                                     std::to_string(leaf) + " k " + std::to_string(k);
            expect_equal(index.top_k(q, k, &stats), scan_top_k(q, db.grids, db.mu, hub_weight, k), what);
            if (k == 1 && n == 5000) {  // the bounds spare most of the scan's per-pose work
              EXPECT_LT(stats.poses_scored, n * q.grids().size() / 4) << what;
            }
          }
        }
      }
    }
  }
}

TEST(GridIndex, EmptyDatabasesAndEmptyGrids) {
  const GridConfig config = succinct_grid_config();
  std::mt19937_64 rng(2);
  const GridQuery q(make_query_grids(random_place(rng), config), config);
  EXPECT_TRUE(GridIndex({}, {}, 1.0).top_k(q, 5).empty());
  const std::vector<GridBits> empty_grids(40);  // every stored grid empty: all score 0, ties by index
  const std::vector<GridMatch> top = GridIndex(empty_grids, {}, 0.0).top_k(q, 3);
  expect_equal(top, scan_top_k(q, empty_grids, {}, 0.0, 3), "empty grids");
  ASSERT_EQ(top.size(), 3u);
  EXPECT_EQ(top[0].index, 0u);
  EXPECT_EQ(top[2].index, 2u);
  EXPECT_TRUE(GridIndex(empty_grids, {}, 0.0).top_k(q, 0).empty());
}

TEST(GridIndex, RefusesBadInputNamingIt) {
  const GridConfig config = succinct_grid_config();
  EXPECT_THROW(GridQuery(std::vector<GridBits>(10), config), InputError);  // not the config's poses
  EXPECT_THROW(GridIndex(std::vector<GridBits>(3), std::vector<double>(2), 1.0), InputError);
  EXPECT_THROW(GridIndex(std::vector<GridBits>(3), {}, 1.0, {.leaf_size = 0}), InputError);
  try {
    GridIndex(std::vector<GridBits>(2), {0.5, std::nan("")}, 1.0);
    FAIL() << "a NaN hubness value was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hubness"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace partslam
