#include "core/matching/grid_descriptor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/error.h"
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

TEST(GridDescriptor, Bits) {
  EXPECT_EQ(grid_bits_per_map(GridConfig{}), 121);
  EXPECT_EQ(grid_bits_per_map(succinct_grid_config()), 128);
}

}  // namespace
}  // namespace partslam
