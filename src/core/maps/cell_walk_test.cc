#include "core/maps/cell_walk.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace partslam {
namespace {

std::vector<std::pair<int, int>> cells_of(const Vec2& a, const Vec2& b) {
  std::vector<std::pair<int, int>> cells;
  walk_cells(a, b, [&](int x, int y) {
    cells.emplace_back(x, y);
    return false;
  });
  return cells;
}

TEST(CellWalk, VisitsEveryCellTheSegmentCrossesFromTheFirstToTheLast) {
  using Cells = std::vector<std::pair<int, int>>;
  EXPECT_EQ(cells_of({0.5, 0.5}, {3.5, 0.5}), (Cells{{0, 0}, {1, 0}, {2, 0}, {3, 0}}));
  EXPECT_EQ(cells_of({2.5, 1.5}, {0.2, 1.5}), (Cells{{2, 1}, {1, 1}, {0, 1}}));
  // A shallow diagonal, one step in x or in y at a time: it reaches y = 1 at x = 2.1, in cell column 2.
  EXPECT_EQ(cells_of({0.5, 0.2}, {2.5, 1.2}), (Cells{{0, 0}, {1, 0}, {2, 0}, {2, 1}}));
  EXPECT_EQ(cells_of({-0.5, -0.5}, {-0.4, -0.4}), (Cells{{-1, -1}}));
}

TEST(CellWalk, StopsWhenTheVisitSaysSo) {
  int visited = 0;
  EXPECT_TRUE(walk_cells({0.5, 0.5}, {9.5, 0.5}, [&](int x, int) { return ++visited, x == 3; }));
  EXPECT_EQ(visited, 4);
  EXPECT_FALSE(walk_cells({0.5, 0.5}, {9.5, 0.5}, [](int, int) { return false; }));
}

}  // namespace
}  // namespace partslam
