#include "core/matching/grid_cascade.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
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

void expect_equal(const std::vector<GridMatch>& got, const std::vector<GridMatch>& scan,
                  const std::string& what) {
  ASSERT_EQ(got.size(), scan.size()) << what;
  for (std::size_t r = 0; r < scan.size(); ++r) {
    EXPECT_EQ(got[r].index, scan[r].index) << what << " rank " << r;
    EXPECT_EQ(got[r].score, scan[r].score) << what << " rank " << r;  // bit for bit
  }
}

// Every stage forced to prune on a small database.
GridCascadeConfig pruning() {
  return {.turns_keep = 0.3, .turns_min = 1, .coarse_keep = 0.05, .coarse_min = 1};
}

TEST(GridCascade, EqualsTheScanWhenTheShortListsCoverTheDatabase) {
  const GridConfig config = succinct_grid_config();
  std::mt19937_64 rng(11);
  for (const auto& [n, places] : {std::pair<std::size_t, int>{1500, 40}, {50, 5}, {13, 13}}) {
    const Synthetic db = synthetic(n, places, 7 + n, config);
    for (double hub_weight : {0.0, 1.0}) {
      GridConfig c = config;
      c.hub_weight = hub_weight;
      for (bool simd : {false, true}) {
        const GridCascade cascade(db.grids, db.mu, c, {.use_simd = simd});
        EXPECT_EQ(cascade.size(), n);
        for (int t = 0; t < 3; ++t) {
          const std::vector<GridBits> q =
              make_query_grids(visit(db.places[rng() % db.places.size()], rng), config);
          for (std::size_t k : {std::size_t{1}, std::size_t{7}, std::size_t{100}, n + 3}) {
            GridCascadeStats stats;
            const std::string what = "n " + std::to_string(n) + " hub " + std::to_string(hub_weight) +
                                     " simd " + std::to_string(simd) + " k " + std::to_string(k);
            expect_equal(cascade.top_k(q, k, &stats), scan_top_k(q, db.grids, db.mu, hub_weight, k), what);
            EXPECT_EQ(stats.coarse_kept, n) << what;  // nothing pruned below coarse_min maps
            const std::size_t first = (n + 1) / 2;    // the first maps only
            expect_equal(
                cascade.top_k(q, k, &stats, first),
                scan_top_k(q, std::span(db.grids).first(first), std::span(db.mu).first(first), hub_weight, k),
                what + " first " + std::to_string(first));
            EXPECT_EQ(stats.coarse_kept, first) << what;
          }
        }
      }
    }
  }
}

TEST(GridCascade, ScoresEveryStoredMapAsTheScanDoes) {
  const GridConfig config = succinct_grid_config();
  const Synthetic db = synthetic(300, 20, 17, config);
  std::mt19937_64 rng(8);
  const std::vector<GridBits> q = make_query_grids(visit(db.places[3], rng), config);
  const std::vector<GridMatch> scan = scan_top_k(q, db.grids, db.mu, config.hub_weight, db.grids.size());
  for (bool simd : {false, true}) {
    const std::vector<double> scores = GridCascade(db.grids, db.mu, config, {.use_simd = simd}).scores(q);
    ASSERT_EQ(scores.size(), db.grids.size());
    for (const GridMatch& m : scan)
      EXPECT_EQ(scores[m.index], m.score) << "map " << m.index << " simd " << simd;
  }
  EXPECT_THROW(GridCascade(db.grids, db.mu, config).scores(std::vector<GridBits>(5)), InputError);
}

TEST(GridCascade, StagesKeepTheirShareAndScoreExactly) {
  const GridConfig config = succinct_grid_config();
  const Synthetic db = synthetic(4000, 60, 3, config);
  std::mt19937_64 rng(5);
  const GridCascade portable(
      db.grids, db.mu, config,
      {.turns_keep = 0.3, .turns_min = 1, .coarse_keep = 0.05, .coarse_min = 1, .use_simd = false});
  const GridCascade simd(
      db.grids, db.mu, config,
      {.turns_keep = 0.3, .turns_min = 1, .coarse_keep = 0.05, .coarse_min = 1, .use_simd = true});
  for (int t = 0; t < 5; ++t) {
    const Points2 place = db.places[rng() % db.places.size()];
    const std::vector<GridBits> q = make_query_grids(visit(place, rng), config);
    GridCascadeStats stats;
    const std::vector<GridMatch> top = portable.top_k(q, 50, &stats);
    EXPECT_EQ(stats.turns_kept, 1200u);
    EXPECT_EQ(stats.coarse_kept, 200u);
    ASSERT_EQ(top.size(), 50u);
    // The AVX-512 kernels (where the CPU has them) give the same answer as the portable ones.
    expect_equal(simd.top_k(q, 50), top, "simd " + std::to_string(t));
    // Each answer carries its exact score, in the scan's order; the scan's own best is among them when it
    // passed both stages, which a revisit of a stored place does here.
    const std::vector<int> counts = grid_counts(q);
    for (std::size_t r = 0; r < top.size(); ++r) {
      EXPECT_EQ(top[r].score, grid_similarity(q, counts, db.grids[top[r].index]) - db.mu[top[r].index]);
      if (r > 0) {
        EXPECT_TRUE(top[r - 1].score > top[r].score ||
                    (top[r - 1].score == top[r].score && top[r - 1].index < top[r].index));
      }
    }
  }
  // A stored grid queried with its own grid under every pose passes every stage and comes first.
  for (std::size_t i : {std::size_t{3}, std::size_t{1234}, std::size_t{3999}}) {
    Synthetic one = synthetic(1, 1, 99, config);
    std::vector<GridBits> grids = db.grids;
    std::vector<double> mu = db.mu;
    grids[i] = make_grid(one.places[0], config);
    mu[i] = 0;
    const GridCascade c(grids, mu, config, pruning());
    const std::vector<GridMatch> top = c.top_k(make_query_grids(one.places[0], config), 1);
    ASSERT_EQ(top.size(), 1u);
    EXPECT_EQ(top[0].index, i);
    EXPECT_EQ(top[0].score, 1.0);
  }
}

TEST(GridCascade, TurnsStageKeepsTheBestUnshiftedScoresTiesByIndex) {
  // turns_keep = coarse_keep: the coarse stage has nothing to drop, so the answer is the turns stage's list.
  const GridConfig config = succinct_grid_config();
  const Synthetic db = synthetic(403, 30, 21, config);  // not a multiple of 16: a partial last pair of blocks
  std::mt19937_64 rng(4);
  const int reach = config.max_shift * config.substeps, side = 2 * reach + 1;
  for (int t = 0; t < 4; ++t) {
    const std::vector<GridBits> q = make_query_grids(visit(db.places[rng() % db.places.size()], rng), config);
    std::vector<GridBits> turns;
    for (int turn = 0; turn < 4; ++turn)
      turns.push_back(q[static_cast<std::size_t>((turn * side + reach) * side + reach)]);
    std::vector<std::pair<int, std::size_t>> bins;  // (-bin, index): the expected order
    for (std::size_t i = 0; i < db.grids.size(); ++i) {
      float best = 0;  // the best Jaccard over the four turns, in single precision
      for (const GridBits& t : turns) {
        const int both = std::popcount(t.words[0] & db.grids[i].words[0]) +
                         std::popcount(t.words[1] & db.grids[i].words[1]);
        best = std::max(best, static_cast<float>(both) /
                                  static_cast<float>(std::max(t.count() + db.grids[i].count() - both, 1)));
      }
      const float s = best - static_cast<float>(db.mu[i]);
      bins.emplace_back(-std::clamp(static_cast<int>(std::floor(s * 128.0F)) + 128, 0, 256), i);
    }
    std::sort(bins.begin(), bins.end());
    std::vector<std::size_t> expected;
    for (std::size_t r = 0; r < 101; ++r) expected.push_back(bins[r].second);
    std::sort(expected.begin(), expected.end());
    for (bool simd : {false, true}) {
      const GridCascade c(
          db.grids, db.mu, config,
          {.turns_keep = 0.25, .turns_min = 1, .coarse_keep = 0.25, .coarse_min = 1, .use_simd = simd});
      GridCascadeStats stats;
      const std::vector<GridMatch> top = c.top_k(q, 101, &stats);
      EXPECT_EQ(stats.turns_kept, 101u);  // ceil(0.25 x 403)
      EXPECT_EQ(stats.coarse_kept, 101u);
      std::vector<std::size_t> got;
      for (const GridMatch& m : top) got.push_back(m.index);
      std::sort(got.begin(), got.end());
      EXPECT_EQ(got, expected) << "query " << t << " simd " << simd;
    }
  }
}

TEST(GridCascade, EmptyDatabasesAndEmptyGrids) {
  const GridConfig config = succinct_grid_config();
  std::mt19937_64 rng(2);
  const std::vector<GridBits> q = make_query_grids(random_place(rng), config);
  EXPECT_TRUE(GridCascade({}, {}, config).top_k(q, 5).empty());
  const std::vector<GridBits> empty_grids(40);  // every stored grid empty: all score 0, ties by index
  for (const GridCascadeConfig& c : {GridCascadeConfig{}, pruning()}) {
    const std::vector<GridMatch> top = GridCascade(empty_grids, {}, config, c).top_k(q, 3);
    ASSERT_EQ(top.size(), 3u);
    EXPECT_EQ(top[0].index, 0u);
    EXPECT_EQ(top[2].index, 2u);
    EXPECT_EQ(top[0].score, 0.0);
  }
  EXPECT_TRUE(GridCascade(empty_grids, {}, config).top_k(q, 0).empty());
}

TEST(GridCascade, RefusesBadInputNamingIt) {
  const GridConfig config = succinct_grid_config();
  const GridCascade ok(std::vector<GridBits>(3), {}, config);
  EXPECT_THROW(ok.top_k(std::vector<GridBits>(10), 1), InputError);  // not the config's poses
  EXPECT_THROW(GridCascade(std::vector<GridBits>(3), std::vector<double>(2), config), InputError);
  EXPECT_THROW(GridCascade(std::vector<GridBits>(3), {}, config, {.turns_keep = 0}), InputError);
  EXPECT_THROW(GridCascade(std::vector<GridBits>(3), {}, config, {.coarse_min = 0}), InputError);
  for (const double bad : {std::nan(""), 0.5, -1.0 / 127}) {  // off the 7-bit lattice, or outside [0, 1]
    try {
      const std::vector<double> mu{1.0 / 127, bad};
      GridCascade(std::vector<GridBits>(2), mu, config);
      FAIL() << "hubness " << bad << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("hubness of map 1"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace partslam
