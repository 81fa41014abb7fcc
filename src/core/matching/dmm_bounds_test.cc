#include "core/matching/dmm_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/matching/dmm.h"

#include <random>

namespace partslam {
namespace {

// Brute force over PackedLevel::at, which reads 0 off the grid.
std::array<int, 16> brute_force(const PackedLevel& packed, const RotatedQuery& r, int i, int j) {
  std::array<int, 16> bounds{};
  for (std::size_t k = 0; k < r.x.size(); ++k) {
    const unsigned v = packed.at(r.x[k] + i, r.y[k] + j);
    for (unsigned c = 0; c < 16; ++c) bounds[c] += static_cast<int>((v >> c) & 1u);
  }
  return bounds;
}

TEST(ChildBounds, SimdAndPortableEqualBruteForceOnAndOffTheGrid) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  Points2 map_points, query_points;
  for (int k = 0; k < 300; ++k) map_points.emplace_back(u(rng), u(rng));
  for (int k = 0; k < 200; ++k) query_points.emplace_back(u(rng), u(rng));
  DmmConfig config;
  config.angular_step = 0.3;
  const PreparedQuery query = prepare_query(query_points, config);
  const OccupancyGrid grid = build_occupancy_grid(map_points, 0.1, 1);
  for (const int step : {1, 4, 16}) {
    const PackedLevel packed = build_packed_level(grid, step);
    for (const RotatedQuery& r : query.rotations) {
      for (const auto& [i, j] : {std::pair{0, 0}, {-40, 7}, {55, -61}, {-100, -100}, {3, 90}}) {
        const std::array<int, 16> expected = brute_force(packed, r, i, j);
        const CellList cells{r.x.data(), r.y.data(), r.x.size()};
        for (const bool avx2 : {false, true}) {
          std::array<int, 16> bounds;
          std::vector<std::uint16_t> values(r.x.size(), 0xffff);
          ASSERT_TRUE(child_bounds(packed, cells, i, j, -1, values.data(), bounds, avx2));
          ASSERT_EQ(bounds, expected) << step << " " << i << "," << j << " avx2 " << avx2;
          for (std::size_t k = 0; k < r.x.size(); ++k) ASSERT_EQ(values[k], packed.at(r.x[k] + i, r.y[k] + j));
          // Filtering by a child's bit keeps exactly the points that score in it, in order.
          std::vector<int> fx(r.x.size()), fy(r.x.size());
          const std::size_t kept = filter_cells(cells, values.data(), 5, fx.data(), fy.data());
          ASSERT_EQ(static_cast<int>(kept), expected[5]);
          for (std::size_t k = 1; k < kept; ++k) ASSERT_LE(fy[k - 1], fy[k]);
        }
        // With a bar no child can beat, the pass may stop early; with a bar below the best it must finish.
        std::array<int, 16> bounds;
        const int top = *std::max_element(expected.begin(), expected.end());
        if (child_bounds(packed, cells, i, j, top, nullptr, bounds)) {
          ASSERT_EQ(bounds, expected);
        }
        ASSERT_TRUE(child_bounds(packed, cells, i, j, top - 1, nullptr, bounds));
        ASSERT_EQ(bounds, expected);
      }
    }
  }
  std::array<int, 16> bounds;
  const CellList first{query.rotations[0].x.data(), query.rotations[0].y.data(), query.rotations[0].x.size()};
  EXPECT_TRUE(child_bounds(PackedLevel{}, first, 0, 0, -1, nullptr, bounds));
  EXPECT_EQ(bounds, (std::array<int, 16>{}));
  RecordProperty("avx2", cpu_has_avx2() ? "yes" : "no");
}

// More than 65535 points: the 16-bit lanes are flushed in chunks.
TEST(ChildBounds, CountsBeyondSixteenBits) {
  RotatedQuery r;
  r.x.assign(70000, 0);
  r.y.assign(70000, 0);
  r.x_min = r.x_max = r.y_min = r.y_max = 0;
  const PackedLevel packed = build_packed_level(build_occupancy_grid({{0.05, 0.05}}, 0.1), 1);
  const CellList cells{r.x.data(), r.y.data(), r.x.size()};
  std::array<int, 16> bounds;
  ASSERT_TRUE(child_bounds(packed, cells, 0, 0, -1, nullptr, bounds));
  EXPECT_EQ(bounds[0], 70000);
  EXPECT_EQ(bounds[1], 0);
  ASSERT_TRUE(child_bounds(packed, cells, 0, 0, -1, nullptr, bounds, false));
  EXPECT_EQ(bounds[0], 70000);
  ASSERT_TRUE(child_bounds(packed, cells, -1, -1, -1, nullptr, bounds));
  EXPECT_EQ(bounds[5], 70000);  // child (1, 1) of the node at (-1, -1) is cell (0, 0)
}

}  // namespace
}  // namespace partslam
