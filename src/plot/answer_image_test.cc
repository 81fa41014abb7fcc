#include "plot/answer_image.h"

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

std::uint32_t rgb(const Rgb& c) {
  const auto byte = [](double v) { return static_cast<std::uint32_t>(std::lround(v * 255)); };
  return byte(c.r) << 16 | byte(c.g) << 8 | byte(c.b);
}

// 20 x 20 cells of 0.1 m from (0, 0): all free but cell (0, 0), occupied.
GridMap grid() {
  GridMap m;
  m.resolution = 0.1;
  m.width = m.height = 20;
  m.cells.assign(400, CellState::kFree);
  m.cells[0] = CellState::kOccupied;
  return m;
}

TEST(AnswerImage, PointsAndPathLandWhereTheMapSaysInEachPanel) {
  const fs::path png = fs::temp_directory_path() / ("partslam_answer_" + std::to_string(::getpid()) + ".png");
  const GridMap m = grid();
  Panel located{"located", &m, {{{Vec2(1.0, 1.0)}, kGood, 2.0}}, {}, {}, "", {}};
  // The second panel: points only, moved by a quarter turn about the origin, and a two-point path.
  Panel matched{"matched", nullptr,
                {{transformed({Vec2(0.0, -2.0), Vec2(2.0, 0.0)}, Pose2{0, 0, std::numbers::pi / 2}), kDoubtful, 2.0}},
                {Vec2(1.0, 0.5), Vec2(2.0, 2.0)},
                {kGood, kDoubtful},
                "a legend",
                {}};
  write_panels_png(png, {located, matched}, 200);
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(s), 2 * 200 + 12);
  EXPECT_EQ(cairo_image_surface_get_height(s), 200 + 26);
  // Panel 1: the map spans [0, 2] m in 180 px (10 px margins): (1, 1) m is the centre, the occupied cell (0, 0)
  // the bottom-left corner, a free cell white.
  EXPECT_EQ(pixel(s, 100, 26 + 100), rgb(kGood));
  EXPECT_EQ(pixel(s, 14, 26 + 186), 0x000000u);
  EXPECT_EQ(pixel(s, 150, 26 + 50), 0xFFFFFFu);
  // Panel 2 (from x = 212): (0, -2) turned a quarter is (2, 0), (2, 0) is (0, 2); the path's dots at (2, 2) and
  // (1, 0.5) the path's dots in their colours.
  EXPECT_EQ(pixel(s, 212 + 190, 26 + 190), rgb(kDoubtful));
  EXPECT_EQ(pixel(s, 212 + 10, 26 + 10), rgb(kDoubtful));
  EXPECT_EQ(pixel(s, 212 + 100, 26 + 145), rgb(kGood));
  cairo_surface_destroy(s);
  fs::remove(png);
}

// A path of three dots on a line whose middle one is not joined to the first: no line between the first two, a
// line between the last two.
TEST(AnswerImage, APathIsBrokenWhereItsPointsAreNotJoined) {
  const fs::path png = fs::temp_directory_path() / ("partslam_answer_break_" + std::to_string(::getpid()) + ".png");
  Panel p{"broken path", nullptr, {}, {Vec2(0.0, 0.0), Vec2(1.0, 0.0), Vec2(2.0, 0.0)}, {}, "", {true, false, true}};
  write_panels_png(png, {p}, 200);
  cairo_surface_t* s = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(s), CAIRO_STATUS_SUCCESS);
  // The path spans [0, 2] m in 180 px: x = 0.5 m at pixel 55, x = 1.5 m at 145, the line's y at the middle.
  const int y = 26 + cairo_image_surface_get_height(s) / 2 - 13;
  EXPECT_NE(pixel(s, 145, y), pixel(s, 55, y));
  EXPECT_EQ(pixel(s, 55, y), pixel(s, 55, y - 15));  // no line: the background
  cairo_surface_destroy(s);
  p.path_joined = {true, true};
  EXPECT_THROW(write_panels_png(png, {p}, 200), InputError);
  fs::remove(png);
}

TEST(AnswerImage, RefusesWhatItCannotDraw) {
  const fs::path png = fs::temp_directory_path() / ("partslam_answer_bad_" + std::to_string(::getpid()) + ".png");
  EXPECT_THROW(write_panels_png(png, {}), InputError);
  EXPECT_THROW(write_panels_png(png, {Panel{"empty", nullptr, {}, {}, {}, "", {}}}), InputError);
  EXPECT_THROW(write_panels_png(png, {Panel{"colours", nullptr, {}, {Vec2(0, 0)}, {kGood, kGood}, "", {}}}), InputError);
  GridMap broken = grid();
  broken.cells.pop_back();
  EXPECT_THROW(write_panels_png(png, {Panel{"broken", &broken, {}, {}, {}, "", {}}}), InputError);
  EXPECT_FALSE(fs::exists(png));
}

}  // namespace
}  // namespace partslam::plot
