#include "core/matching/grid_descriptor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
#include "core/matching/ranking.h"
#include "core/sim/simulator.h"
#include "core/testing/simulated_maps.h"
#include "core/maps/submap.h"

namespace partslam {
namespace {

TEST(GridDescriptor, BinsPointsIntoRowMajorCells) {
  GridConfig c;
  c.cells = 4;
  c.box_size = 4.0;  // 1 m cells over [-2, 2)
  const GridBits g = make_grid({{-1.5, -1.5}, {0.5, -1.5}, {1.5, 1.5}, {9.0, 0.0}}, c);
  EXPECT_EQ(g.count(), 3);  // the point at x = 9 m is outside the box
  EXPECT_EQ(g.words[0], (1u << 0) | (1u << 2) | (1u << 15));
  c.min_points = 2;
  EXPECT_EQ(make_grid({{-1.5, -1.5}, {-1.4, -1.4}, {0.5, 0.5}}, c).count(), 1);
}

TEST(GridDescriptor, AQuarterTurnAndAShiftOfTheSameMapMatchExactly) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  Points2 map;
  for (int i = 0; i < 300; ++i) map.push_back({u(rng), u(rng)});
  GridConfig c;  // 11 x 11 over 12.8 m, +-1 cell
  const double cell = c.box_size / c.cells;
  // The stored map is the query turned by 90 deg and moved by one cell: one of the query's poses is exact.
  Points2 stored;
  for (const Vec2& p : map) stored.push_back(Vec2{-p.y(), p.x()} + Vec2{cell, 0.0});
  const std::vector<GridBits> q = make_query_grids(map, c);
  EXPECT_EQ(q.size(), 4u * 3u * 3u);
  EXPECT_DOUBLE_EQ(grid_similarity(q, make_grid(stored, c)), 1.0);
  // Without the shift search the same pair no longer matches exactly.
  c.max_shift = 0;
  EXPECT_LT(grid_similarity(make_query_grids(map, c), make_grid(stored, c)), 1.0);
}

// Every query grid is the stored grid of the query's points turned and moved by that pose, in the order
// quarter turn, y shift, x shift (for the counts threshold too).
TEST(GridDescriptor, QueryGridsAreTheGridsOfTheMovedPoints) {
  const Points2& points = testing::simulated_maps().at(7).points;
  for (int min_points : {1, 3}) {
    GridConfig c = succinct_grid_config();
    c.min_points = min_points;
    const std::vector<GridBits> q = make_query_grids(points, c);
    const int reach = c.max_shift * c.substeps, shifts = 2 * reach + 1;
    ASSERT_EQ(q.size(), static_cast<std::size_t>(4 * shifts * shifts));
    const double step = c.box_size / c.cells / c.substeps;
    for (int k = 0; k < 4; ++k)
      for (int j = -reach; j <= reach; j += 3)
        for (int i = -reach; i <= reach; i += 2) {
          Points2 moved;
          for (Vec2 p : points) {
            for (int t = 0; t < k; ++t) p = Vec2{-p.y(), p.x()};
            moved.push_back(p + Vec2{i * step, j * step});
          }
          const std::size_t v = static_cast<std::size_t>((k * shifts + j + reach) * shifts + i + reach);
          EXPECT_EQ(q[v], make_grid(moved, c)) << "turn " << k << " shift " << i << ", " << j;
        }
  }
}

TEST(GridDescriptor, JaccardOfEmptyAndDisjointGrids) {
  GridBits a, b;
  EXPECT_EQ(jaccard(a, b), 0.0);
  a.words[0] = 0b0011;
  b.words[0] = 0b0110;
  EXPECT_DOUBLE_EQ(jaccard(a, b), 1.0 / 3.0);
  b.words[1] = 1;
  EXPECT_DOUBLE_EQ(jaccard(a, b), 1.0 / 4.0);
}

TEST(GridDescriptor, SpecsAndBits) {
  EXPECT_EQ(parse_method_spec("grid").spec, "grid:11");
  EXPECT_EQ(parse_method_spec("grid:11").label(), "grid 11x11");
  EXPECT_EQ(parse_method_spec("grid:11:hub=100:box=80:shift=3:sub=2").spec, "grid:11:box=80:shift=3:sub=2:hub=100");
  EXPECT_FALSE(parse_method_spec("succinct").needs_points);
  EXPECT_FALSE(parse_method_spec("succinct").needs_parts);
  EXPECT_EQ(grid_bits_per_map(GridConfig{}), 121);
  EXPECT_EQ(grid_bits_per_map(succinct_grid_config()), 128);
  for (const char* bad : {"grid:12", "grid:0", "grid:11:shift", "grid:11:foo=1", "grid:11:sub=0", "succinct:3"}) {
    try {
      parse_method_spec(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

TEST(GridDescriptor, SuccinctRanksTheQueryItselfFirstAndThreadsDoNotChangeScores) {
  const Submaps& maps = testing::simulated_maps();
  std::vector<MapView> views;
  for (const Submap& m : maps) views.push_back({&m.points, nullptr});
  const std::unique_ptr<Ranker> one = make_ranker(parse_method_spec("succinct"), {});
  const std::unique_ptr<Ranker> two = make_ranker(parse_method_spec("succinct"), {});
  one->prepare(views, 1);
  two->prepare(views, 2);
  EXPECT_EQ(one->bits_per_map(), 128.0);
  const std::vector<std::size_t> candidates = {30, 5, 12, 0, 44, 61};
  const Ranking r1 = one->rank(views[12], candidates, {1, 0});
  const Ranking r2 = two->rank(views[12], candidates, {2, 0});
  EXPECT_EQ(r1.scores, r2.scores);
  EXPECT_EQ(ranking_order(r1.scores).front(), 2u);
  EXPECT_TRUE(r1.direct.empty());
}

TEST(GridDescriptor, HubnessSubtractsTheOtherMapsMeanSimilarityToEachStoredMap) {
  const Submaps& maps = testing::simulated_maps();
  std::vector<MapView> views;
  for (std::size_t i = 0; i < 12; ++i) views.push_back({&maps[i * 5].points, nullptr});
  const std::unique_ptr<Ranker> plain = make_ranker(parse_method_spec("grid:11:box=80"), {});
  const std::unique_ptr<Ranker> hub = make_ranker(parse_method_spec("grid:11:box=80:hub=50"), {});
  plain->prepare(views, 1);
  hub->prepare(views, 2);
  const std::vector<std::size_t> candidates = {0, 3, 7, 11};
  const Ranking p = plain->rank(views[5], candidates);
  const Ranking h = hub->rank(views[5], candidates);
  GridConfig c;
  c.box_size = 8.0;
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    const std::size_t m = candidates[j];
    // mu_m: the mean similarity of the 11 other maps' queries to map m's grid, on 7 bits.
    const GridBits stored = make_grid(*views[m].points, c);
    double sum = 0;
    for (std::size_t o = 0; o < views.size(); ++o)
      if (o != m) sum += grid_similarity(make_query_grids(*views[o].points, c), stored);
    const double mu = std::round(sum / 11.0 * 127) / 127;
    EXPECT_GT(mu, 0.0);
    EXPECT_NEAR(p.scores[j] - h.scores[j], 0.5 * mu, 1e-12) << "map " << m;
  }
  EXPECT_EQ(hub->bits_per_map(), 128.0);
  EXPECT_EQ(plain->bits_per_map(), 121.0);
}

}  // namespace
}  // namespace partslam
