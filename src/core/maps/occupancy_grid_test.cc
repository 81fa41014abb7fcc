#include "core/maps/occupancy_grid.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"

namespace partslam {
namespace {

TEST(OccupancyGrid, CellsOnTheGlobalLattice) {
  const OccupancyGrid grid = build_occupancy_grid({{0.05, 0.05}, {-0.15, 0.32}, {0.05, 0.07}}, 0.1);
  EXPECT_EQ(grid.x0, -2);
  EXPECT_EQ(grid.y0, 0);
  EXPECT_EQ(grid.width, 3);
  EXPECT_EQ(grid.height, 4);
  EXPECT_EQ(grid.num_occupied(), 2u);
  EXPECT_EQ(grid.at(0, 0), 1);
  EXPECT_EQ(grid.at(-2, 3), 1);
  EXPECT_EQ(grid.at(-1, 3), 0);
  EXPECT_EQ(grid.at(100, 0), 0);   // outside reads 0
  EXPECT_EQ(grid.at(Vec2(-0.11, 0.39)), 1);
}

TEST(OccupancyGrid, DilationIsAEuclideanDisc) {
  const OccupancyGrid one = build_occupancy_grid({{0.05, 0.05}}, 0.1, 1);
  EXPECT_EQ(one.num_occupied(), 5u);  // the cell and its 4 neighbours
  EXPECT_EQ(one.at(1, 0), 1);
  EXPECT_EQ(one.at(1, 1), 0);
  const OccupancyGrid two = build_occupancy_grid({{0.05, 0.05}}, 0.1, 2);
  EXPECT_EQ(two.num_occupied(), 13u);
  EXPECT_EQ(two.width, 5);
  EXPECT_EQ(two.at(-2, 0), 1);
  EXPECT_EQ(two.at(-2, 1), 0);
}

TEST(OccupancyGrid, EmptyAndBadInput) {
  EXPECT_EQ(build_occupancy_grid({}, 0.1).cells.size(), 0u);
  EXPECT_EQ(build_occupancy_grid({}, 0.1).at(0, 0), 0);
  EXPECT_THROW(build_occupancy_grid({{0, 0}}, 0.0), InputError);
  EXPECT_THROW(build_occupancy_grid({{0, 0}}, 0.1, -1), InputError);
  EXPECT_THROW(build_occupancy_grid({{0, 0}, {1e6, 1e6}}, 0.01), InputError);
  EXPECT_THROW(build_occupancy_grid({{0, std::nan("")}}, 0.1), InputError);
}

TEST(GridPyramid, LevelsAreMaxOverTheBlockBruteForce) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  Points2 points;
  for (int k = 0; k < 40; ++k) points.emplace_back(u(rng), u(rng));
  const OccupancyGrid base = build_occupancy_grid(points, 0.1);
  const GridPyramid pyramid = build_grid_pyramid(base, 5);
  ASSERT_EQ(pyramid.levels.size(), 5u);
  for (int h = 0; h < 5; ++h) {
    const OccupancyGrid& level = pyramid.levels[static_cast<std::size_t>(h)];
    const int w = 1 << h;
    EXPECT_EQ(level.x0, base.x0 - w + 1);
    for (int y = level.y0 - 3; y < level.y0 + level.height + 3; ++y) {
      for (int x = level.x0 - 3; x < level.x0 + level.width + 3; ++x) {
        std::uint8_t expected = 0;
        for (int b = 0; b < w; ++b) {
          for (int a = 0; a < w; ++a) expected = std::max(expected, base.at(x + a, y + b));
        }
        ASSERT_EQ(level.at(x, y), expected) << "level " << h << " cell " << x << "," << y;
      }
    }
  }
  EXPECT_THROW(build_grid_pyramid(base, 0), InputError);
  EXPECT_THROW(build_grid_pyramid(base, 17), InputError);
}

TEST(PackedLevel, PacksSixteenShiftedCellsBruteForce) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.5);
  Points2 points;
  for (int k = 0; k < 30; ++k) points.emplace_back(u(rng), u(rng));
  const OccupancyGrid level = build_occupancy_grid(points, 0.1, 1);
  for (const int step : {1, 4}) {
    const PackedLevel packed = build_packed_level(level, step);
    EXPECT_EQ(packed.x0, level.x0 - 3 * step);
    for (int y = level.y0 - 14; y < level.y0 + level.height + 3; ++y) {
      for (int x = level.x0 - 14; x < level.x0 + level.width + 3; ++x) {
        unsigned expected = 0;
        for (int b = 0; b < 4; ++b) {
          for (int a = 0; a < 4; ++a) expected |= static_cast<unsigned>(level.at(x + a * step, y + b * step)) << (a + 4 * b);
        }
        ASSERT_EQ(packed.at(x, y), expected) << "step " << step << " cell " << x << "," << y;
      }
    }
  }
  EXPECT_EQ(build_packed_level(OccupancyGrid{}, 2).at(0, 0), 0);
  EXPECT_THROW(build_packed_level(level, 0), InputError);
}

TEST(CountInliers, CountsPointsOnOccupiedCellsAfterThePose) {
  const OccupancyGrid grid = build_occupancy_grid({{1.05, 0.05}, {1.05, 0.15}}, 0.1);
  const Points2 query = {{0.05, 0.05}, {0.05, 0.15}, {0.5, 0.5}};
  EXPECT_EQ(count_inliers(query, grid, Pose2{}), 0);
  EXPECT_EQ(count_inliers(query, grid, Pose2{1.0, 0.0, 0.0}), 2);
}

}  // namespace
}  // namespace partslam
