#include "plot/grid_map_image.h"

#include <cairo.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

#include "core/error.h"
#include "plot/png_file.h"

namespace partslam::plot {
namespace {

constexpr int kGridTitleHeight = 24;  // one line of title; each more line adds kTitleLine
constexpr int kTitleLine = 18;
constexpr int kGridGap = 16;
constexpr double kTitleFont = 14;

// The title's words in lines no wider than `width` pixels in cr's font (a word wider than that alone on its
// line): a long title (slam's verdict and its reason) stays over its own grid.
std::vector<std::string> title_lines(cairo_t* cr, const std::string& title, double width) {
  std::vector<std::string> lines;
  std::string line, word;
  const auto fits = [&](const std::string& text) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, text.c_str(), &e);
    return e.x_advance <= width;
  };
  const auto add = [&] {
    if (word.empty()) return;
    const std::string longer = line.empty() ? word : line + " " + word;
    if (line.empty() || fits(longer)) line = longer;
    else lines.push_back(line), line = word;
    word.clear();
  };
  for (const char c : title) {
    if (c == ' ') add();
    else word += c;
  }
  add();
  if (!line.empty()) lines.push_back(line);
  return lines;
}

void set_title_font(cairo_t* cr) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, kTitleFont);
}

// The state of a block of cells: occupied when any cell is, else free when any is, else unknown.
CellState block_state(const GridMap& m, int column, int row, int f) {
  CellState s = CellState::kUnknown;
  for (int y = row; y < std::min(row + f, m.height); ++y)
    for (int x = column; x < std::min(column + f, m.width); ++x) {
      const CellState c = m.at(x, y);
      if (c == CellState::kOccupied) return c;
      if (c == CellState::kFree) s = c;
    }
  return s;
}

// The links (thin orange lines), the path (a blue line, a green dot at its start, a red one at its end) and the
// marks (red circles) of one grid,
// drawn at column `left` below a title `top` pixels high, shrunk by f: a map-frame point's cell is
// origin^-1 * p / resolution, row 0 at the bottom.
void draw_overlays(cairo_t* cr, const TitledGrid& g, int left, int top, int f) {
  const GridMap& m = *g.map;
  const int h = (m.height + f - 1) / f;
  const Pose2 to_grid = m.origin.inverse();
  const auto pixel = [&](const Vec2& p) {
    const Vec2 c = to_grid * p / (m.resolution * f);
    return Vec2(left + c.x(), top + h - c.y());
  };
  cairo_set_source_rgb(cr, 1.0, 0.55, 0.0);
  cairo_set_line_width(cr, 0.8);
  for (const auto& [a, b] : g.links) {
    const Vec2 p = pixel(a), q = pixel(b);
    cairo_move_to(cr, p.x(), p.y());
    cairo_line_to(cr, q.x(), q.y());
  }
  cairo_stroke(cr);
  if (!g.path.empty()) {
    cairo_set_source_rgb(cr, 0.1, 0.35, 0.9);
    cairo_set_line_width(cr, 1.0);
    for (std::size_t i = 0; i < g.path.size(); ++i) {
      const Vec2 q = pixel(g.path[i]);
      if (i == 0) cairo_move_to(cr, q.x(), q.y());
      else cairo_line_to(cr, q.x(), q.y());
    }
    cairo_stroke(cr);
    for (const auto& [p, r, gr, b] : {std::tuple{g.path.front(), 0.0, 0.7, 0.0}, std::tuple{g.path.back(), 0.85, 0.0, 0.0}}) {
      const Vec2 q = pixel(p);
      cairo_set_source_rgb(cr, r, gr, b);
      cairo_arc(cr, q.x(), q.y(), 4.0, 0, 2 * 3.14159265358979);
      cairo_fill(cr);
    }
  }
  cairo_set_source_rgb(cr, 0.85, 0.0, 0.0);
  cairo_set_line_width(cr, 2.0);
  for (const Vec2& p : g.marks) {
    const Vec2 q = pixel(p);
    cairo_new_sub_path(cr);
    cairo_arc(cr, q.x(), q.y(), 12.0, 0, 2 * 3.14159265358979);
    cairo_stroke(cr);
  }
}

}  // namespace

void write_grid_maps_png(const std::filesystem::path& path, const std::vector<TitledGrid>& grids, int max_side) {
  if (grids.empty()) throw InputError(path.string() + ": no map to draw");
  if (max_side < 16 || max_side > 20000) throw InputError("grid map picture: max_side must be in [16, 20000]");
  int total_width = 0, max_height = 0;
  for (const TitledGrid& g : grids) {
    if (!g.map) throw InputError(path.string() + ": no map to draw");
    validate(*g.map);
    total_width += g.map->width;
    max_height = std::max(max_height, g.map->height);
  }
  // The smallest whole factor at which the grids, side by side with their gaps, fit max_side.
  const auto drawn_size = [&](int f) {
    int w = kGridGap * (static_cast<int>(grids.size()) - 1), h = 0;
    for (const TitledGrid& g : grids) w += (g.map->width + f - 1) / f, h = std::max(h, (g.map->height + f - 1) / f);
    return std::pair(w, h);
  };
  int f = std::max(1, std::max((total_width + max_side - 1) / max_side, (max_height + max_side - 1) / max_side));
  while (f < std::max(total_width, max_height) && (drawn_size(f).first > max_side || drawn_size(f).second > max_side))
    ++f;
  auto [width, height] = drawn_size(f);
  width = std::max(width, 200);
  // Each title wrapped to its grid's width (the last grid's to the picture's edge), measured on a scratch surface.
  std::vector<int> room;  // the title's width over each grid
  for (int i = 0, left = 0; i < static_cast<int>(grids.size()); ++i) {
    const int w = (grids[static_cast<std::size_t>(i)].map->width + f - 1) / f;
    room.push_back(i + 1 == static_cast<int>(grids.size()) ? width - left : w);
    left += w + kGridGap;
  }
  std::vector<std::vector<std::string>> titles;
  {
    cairo_surface_t* scratch = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
    cairo_t* measure = cairo_create(scratch);
    set_title_font(measure);
    for (std::size_t i = 0; i < grids.size(); ++i) titles.push_back(title_lines(measure, grids[i].title, room[i] - 8));
    cairo_destroy(measure);
    cairo_surface_destroy(scratch);
  }
  std::size_t most_lines = 1;
  for (const auto& t : titles) most_lines = std::max(most_lines, t.size());
  const int top = kGridTitleHeight + kTitleLine * static_cast<int>(most_lines - 1);
  height += top;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_surface_flush(surface);
  unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  int left = 0;
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const TitledGrid& g = grids[i];
    const GridMap& m = *g.map;
    const int w = (m.width + f - 1) / f, h = (m.height + f - 1) / f;
    for (int py = 0; py < h; ++py) {
      const int row = (h - 1 - py) * f;  // row 0 of the grid is the lowest y: the image's last row
      auto* line = reinterpret_cast<std::uint32_t*>(
          data + static_cast<std::ptrdiff_t>(py + top) * stride);
      for (int px = 0; px < w; ++px) {
        const CellState c = block_state(m, px * f, row, f);
        line[left + px] = c == CellState::kOccupied ? 0x000000u : c == CellState::kFree ? 0xFFFFFFu : 0xB4B4B4u;
      }
    }
    cairo_surface_mark_dirty(surface);
    draw_overlays(cr, g, left, top, f);
    cairo_set_source_rgb(cr, 0, 0, 0);
    set_title_font(cr);
    cairo_save(cr);  // a word longer than its grid is wide is cut at the grid's edge
    cairo_rectangle(cr, left, 0, room[i], top);
    cairo_clip(cr);
    for (std::size_t l = 0; l < titles[i].size(); ++l) {
      cairo_move_to(cr, left + 4, 17 + kTitleLine * static_cast<double>(l));
      cairo_show_text(cr, titles[i][l].c_str());
    }
    cairo_restore(cr);
    cairo_surface_flush(surface);
    left += w + kGridGap;
  }
  cairo_destroy(cr);
  write_png_atomically(path, surface);
}

}  // namespace partslam::plot
