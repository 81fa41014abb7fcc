#include "core/maps/grid_map.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace partslam {
namespace {

// One laser at the origin looking at a wall 2 m ahead (x = 2.02, y in [-1, 1]).
Scans wall_scans() {
  Scan s;
  for (int k = -20; k <= 20; ++k) s.points_laser.emplace_back(2.02, k * 0.05 + 0.012);  // off the cell edges
  return {s};
}

CellState state_at(const GridMap& m, double x, double y) {
  const int column = static_cast<int>(std::floor((x - m.origin.x) / m.resolution));
  const int row = static_cast<int>(std::floor((y - m.origin.y) / m.resolution));
  return m.at(column, row);
}

TEST(GridMap, RayCastingFreesTheBeamsAndMarksTheirEnds) {
  const GridMap m = build_grid_map(wall_scans());
  EXPECT_EQ(state_at(m, 2.01, 0.02), CellState::kOccupied);
  EXPECT_EQ(state_at(m, 1.0, 0.02), CellState::kFree);    // crossed by a beam
  EXPECT_EQ(state_at(m, 0.5, -0.2), CellState::kFree);
  EXPECT_EQ(state_at(m, 2.3, 0.02), CellState::kUnknown);  // behind the wall, inside the margin
  EXPECT_EQ(state_at(m, 1.0, 0.9), CellState::kUnknown);   // outside every beam
  const Points2 points = occupied_points(m);
  ASSERT_GE(points.size(), 40u);
  for (const Vec2& p : points) {
    EXPECT_NEAR(p.x(), 2.02, 0.05);
    EXPECT_LE(std::abs(p.y()), 1.05);
  }
}

TEST(GridMap, OriginAndCellCentresFollowTheMapFrame) {
  GridMap m;
  m.resolution = 0.5;
  m.origin = {10.0, -2.0, std::numbers::pi / 2};
  m.width = 2, m.height = 1;
  m.cells = {CellState::kFree, CellState::kOccupied};
  const Points2 points = occupied_points(m);
  ASSERT_EQ(points.size(), 1u);
  // Cell (1, 0) centre (0.75, 0.25) in the grid, rotated a quarter turn about the origin.
  EXPECT_NEAR(points[0].x(), 10.0 - 0.25, 1e-12);
  EXPECT_NEAR(points[0].y(), -2.0 + 0.75, 1e-12);
}

TEST(GridMap, RefusesBadSettingsAndEmptyOrHugeInput) {
  GridMapConfig c;
  c.resolution = 0;
  EXPECT_THROW(build_grid_map(wall_scans(), c), InputError);
  EXPECT_THROW(build_grid_map(Scans{}), InputError);
  Scans far = wall_scans();
  far.push_back(far[0]);
  far[1].T_world_laser = {5000.0, 0.0, 0.0};
  try {
    build_grid_map(far);
    FAIL() << "a 5 km map was built";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stray"), std::string::npos) << e.what();
  }
  GridMap bad;
  bad.width = 3, bad.height = 3;
  EXPECT_THROW(occupied_points(bad), InputError);  // no cells
}

}  // namespace
}  // namespace partslam
