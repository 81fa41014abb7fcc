#include "plot/grid_map_image.h"

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <tuple>

#include "core/error.h"
#include "plot/testing/pixels.h"

namespace partslam::plot {
namespace {

namespace fs = std::filesystem;

// 40 x 20 cells: the left half free, one occupied cell at column 30, row 0 (the lowest y), the rest unknown.
GridMap test_grid() {
  GridMap m;
  m.width = 40, m.height = 20;
  m.cells.assign(800, CellState::kUnknown);
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x) m.cells[static_cast<std::size_t>(y * 40 + x)] = CellState::kFree;
  m.cells[30] = CellState::kOccupied;
  return m;
}

TEST(GridMapImage, DrawsFreeOccupiedAndUnknownNorthUpSideBySide) {
  const fs::path png = fs::temp_directory_path() / ("partslam_grid_" + std::to_string(::getpid()) + ".png");
  const GridMap a = test_grid(), b = test_grid();
  write_grid_maps_png(png, {{&a, "slam", {}, {}, {}}, {&b, "odometry", {}, {}, {}}});
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(s), 200);  // 40 + 16 + 40, widened to 200
  EXPECT_EQ(cairo_image_surface_get_height(s), 24 + 20);
  EXPECT_EQ(pixel(s, 5, 24 + 10), 0xFFFFFFu);        // free
  EXPECT_EQ(pixel(s, 35, 24 + 10), 0xB4B4B4u);       // unknown
  EXPECT_EQ(pixel(s, 30, 24 + 19), 0x000000u);       // occupied: row 0 is the image's last row
  EXPECT_EQ(pixel(s, 56 + 30, 24 + 19), 0x000000u);  // the second grid, after a 16-pixel gap
  cairo_surface_destroy(s);
  fs::remove(png);
}

TEST(GridMapImage, ShrinksLargeGridsKeepingOccupiedCells) {
  const fs::path png = fs::temp_directory_path() / ("partslam_grid_small_" + std::to_string(::getpid()) + ".png");
  const GridMap a = test_grid();
  write_grid_maps_png(png, {{&a, "", {}, {}, {}}}, 20);  // 40 columns into 20 pixels: blocks of 2 x 2
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(pixel(s, 15, 24 + 9), 0x000000u);  // cell (30, 0) in block (15, 0), the last of 10 rows
  cairo_surface_destroy(s);
  fs::remove(png);
  EXPECT_THROW(write_grid_maps_png(png, {}), InputError);
  EXPECT_FALSE(fs::exists(png));
}

// The robot's path over the grid: blue along it, its start green, its end red; a marked place circled in red.
TEST(GridMapImage, DrawsThePathItsEndsAndMarkedPlaces) {
  const fs::path png = fs::temp_directory_path() / ("partslam_grid_path_" + std::to_string(::getpid()) + ".png");
  GridMap a = test_grid();
  a.resolution = 1.0;  // a cell a metre: map-frame metres are pixels
  const TitledGrid g{&a, "slam", {Vec2(2.5, 10.5), Vec2(17.5, 10.5)}, {Vec2(30.5, 10.5)},
                     {{Vec2(10.5, 2.5), Vec2(10.5, 6.5)}}};
  write_grid_maps_png(png, {g});
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  const auto rgb = [&](int x, int y) {
    const std::uint32_t p = pixel(s, x, y);
    return std::tuple{static_cast<int>(p >> 16 & 0xFF), static_cast<int>(p >> 8 & 0xFF), static_cast<int>(p & 0xFF)};
  };
  const auto [r1, g1, b1] = rgb(10, 24 + 9);  // the middle of the path (row 10.5 from the bottom of 20)
  EXPECT_GT(b1, 150);
  EXPECT_LT(r1, 100);
  const auto [r2, g2, b2] = rgb(2, 24 + 9);  // its start
  EXPECT_GT(g2, 120);
  EXPECT_LT(r2, 100);
  const auto [r3, g3, b3] = rgb(17, 24 + 9);  // its end
  EXPECT_GT(r3, 150);
  EXPECT_LT(g3, 100);
  const auto [r4, g4, b4] = rgb(30, 24 + 9 - 12);  // the top of the circle around the mark
  EXPECT_GT(r4, 150);
  EXPECT_LT(b4, 100);
  EXPECT_EQ(pixel(s, 30, 24 + 9), 0xB4B4B4u);  // inside the circle the map shows through
  const auto [r5, g5, b5] = rgb(10, 24 + 15);  // the middle of the closure's line, (10.5, 4.5)
  EXPECT_GT(r5, 150);
  EXPECT_LT(b5, 150);
  EXPECT_NE(pixel(s, 12, 24 + 15), pixel(s, 10, 24 + 15));  // beside it, the map
  (void)g1, (void)b2, (void)b3, (void)g4, (void)g5;
  cairo_surface_destroy(s);
  fs::remove(png);
}

// A title longer than its grid is wide wraps over that grid, the picture a line taller for each line more, and
// nothing of it is drawn over the grid beside it.
TEST(GridMapImage, WrapsALongTitleOverItsOwnGrid) {
  const fs::path png = fs::temp_directory_path() / ("partslam_grid_title_" + std::to_string(::getpid()) + ".png");
  GridMap a = test_grid(), b = test_grid();
  a.width = b.width = 200, a.height = b.height = 20;  // two grids 200 pixels wide
  a.cells.assign(4000, CellState::kFree), b.cells.assign(4000, CellState::kFree);
  const std::string title = "corrected map (2194 loop closures, orange; verdict doubtful: 17.2 % of the beams "
                            "that revisit a place cross a wall another visit saw)";
  write_grid_maps_png(png, {{&a, title, {}, {}, {}}, {&b, "", {}, {}, {}}});
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  const int height = cairo_image_surface_get_height(s);
  EXPECT_GE(height, 24 + 18 * 2 + 20);  // at least three lines of title over 20 rows of grid
  const int top = height - 20;
  int ink_left = 0, ink_right = 0;
  for (int y = 0; y < top; ++y)
    for (int x = 0; x < cairo_image_surface_get_width(s); ++x)
      if (pixel(s, x, y) != 0xFFFFFFu) (x < 200 ? ink_left : ink_right) += 1;
  EXPECT_GT(ink_left, 0);
  EXPECT_EQ(ink_right, 0);  // the second grid's title (empty) and the gap stay blank
  EXPECT_EQ(pixel(s, 5, top + 10), 0xFFFFFFu);  // the grid below the title, free
  cairo_surface_destroy(s);
  fs::remove(png);
}

}  // namespace
}  // namespace partslam::plot
