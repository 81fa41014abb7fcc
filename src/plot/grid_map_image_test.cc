#include "plot/grid_map_image.h"

#include <cairo.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>

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
  write_grid_maps_png(png, {{&a, "slam"}, {&b, "odometry"}});
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
  write_grid_maps_png(png, {{&a, ""}}, 20);  // 40 columns into 20 pixels: blocks of 2 x 2
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(pixel(s, 15, 24 + 9), 0x000000u);  // cell (30, 0) in block (15, 0), the last of 10 rows
  cairo_surface_destroy(s);
  fs::remove(png);
  EXPECT_THROW(write_grid_maps_png(png, {}), InputError);
  EXPECT_FALSE(fs::exists(png));
}

}  // namespace
}  // namespace partslam::plot
