#include "plot/render.h"

#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"

namespace partslam::plot {
namespace {

namespace fs = std::filesystem;

PartsFigure test_figure() {
  PartsFigure f;
  f.map_title = "map";
  for (int i = 0; i < 60; ++i) f.map_points.emplace_back(-3.0 + 0.1 * i, 0.5 * std::sin(i * 0.2));
  const Box2 keypoint{-2.0, 1.0, -1.0, 1.0};
  f.parts.push_back({keypoint, place_rotated_box(keypoint, 1, {10.0, 5.0}), 0.8, 1});
  f.dictionary_title = "dictionary";
  for (int i = 0; i < 200; ++i) f.dictionary_points.emplace_back(0.15 * i, 0.1 * i);
  return f;
}

struct Counts {
  int width = 0, height = 0;
  int top_part_pixels = 0, bottom_part_pixels = 0;  // pixels in the first part's colour (214, 38, 41) +- 2
};

Counts read_back(const fs::path& path, int split_row) {
  cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
  Counts c;
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    c.width = cairo_image_surface_get_width(s);
    c.height = cairo_image_surface_get_height(s);
    const int stride = cairo_image_surface_get_stride(s);
    const unsigned char* data = cairo_image_surface_get_data(s);
    for (int y = 0; y < c.height; ++y) {
      for (int x = 0; x < c.width; ++x) {
        const auto pixel = *reinterpret_cast<const std::uint32_t*>(data + y * stride + 4 * x);
        const int r = (pixel >> 16) & 0xff, g = (pixel >> 8) & 0xff, b = pixel & 0xff;
        if (std::abs(r - 214) <= 2 && std::abs(g - 38) <= 2 && std::abs(b - 41) <= 2)
          ++(y < split_row ? c.top_part_pixels : c.bottom_part_pixels);
      }
    }
  }
  cairo_surface_destroy(s);
  return c;
}

TEST(Render, DrawsKeypointBoxesAndDescriptorBoxesInThePartColour) {
  const fs::path path = fs::temp_directory_path() / "partslam_render_test.png";
  fs::remove(path);
  PartsFigure f = test_figure();
  RenderConfig config;
  write_parts_figure(path, f, config);
  Counts only_map = read_back(path, config.map_panel_height);
  EXPECT_EQ(only_map.width, config.width);
  EXPECT_LE(only_map.height, config.map_panel_height + 24);  // the map is 6 m x 1 m: a flat panel
  EXPECT_GT(only_map.height, 150);
  EXPECT_GT(only_map.top_part_pixels, 200);  // the keypoint box outline
  EXPECT_EQ(only_map.bottom_part_pixels, 0);

  f.show_dictionary = true;
  write_parts_figure(path, f, config);
  Counts both = read_back(path, only_map.height);  // the same top panel, then the dictionary
  EXPECT_GT(both.height, only_map.height + 100);
  EXPECT_EQ(both.top_part_pixels, only_map.top_part_pixels);
  EXPECT_GT(both.bottom_part_pixels, 100);  // the descriptor box outline
  fs::remove(path);
}

TEST(Render, UnwritablePathOrBadConfigThrows) {
  EXPECT_THROW(write_parts_figure("/nonexistent-dir/fig.png", test_figure()), InputError);
  RenderConfig config;
  config.width = 10;
  EXPECT_THROW(write_parts_figure(fs::temp_directory_path() / "x.png", test_figure(), config), InputError);
}

}  // namespace
}  // namespace partslam::plot
