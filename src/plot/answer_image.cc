#include "plot/answer_image.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "core/error.h"
#include "plot/png_file.h"

namespace partslam::plot {
namespace {

constexpr int kTitleHeight = 26;
constexpr int kGap = 12;
constexpr int kMargin = 10;

struct Box {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  void add(const Vec2& p) {
    x0 = std::min(x0, p.x()), y0 = std::min(y0, p.y()), x1 = std::max(x1, p.x()), y1 = std::max(y1, p.y());
  }
  bool empty() const { return !(x1 >= x0); }
};

Box bounds(const Panel& p) {
  Box b;
  if (p.map) {
    const double w = p.map->width * p.map->resolution, h = p.map->height * p.map->resolution;
    for (const Vec2& c : {Vec2(0, 0), Vec2(w, 0), Vec2(0, h), Vec2(w, h)}) b.add(p.map->origin * c);
  }
  for (const PointLayer& l : p.layers)
    for (const Vec2& q : l.points) b.add(q);
  for (const Vec2& q : p.path) b.add(q);
  return b;
}

// The grid as an image, shrunk by a whole factor f to at most max_side pixels a side (a block is occupied when any
// of its cells is, else free when any is); row 0 of the grid is the image's last row.
cairo_surface_t* grid_image(const GridMap& m, int max_side, int& f) {
  f = std::max(1, std::max((m.width + max_side - 1) / max_side, (m.height + max_side - 1) / max_side));
  const int w = (m.width + f - 1) / f, h = (m.height + f - 1) / f;
  cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  cairo_surface_flush(s);
  unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  for (int py = 0; py < h; ++py) {
    auto* line = reinterpret_cast<std::uint32_t*>(data + static_cast<std::ptrdiff_t>(py) * stride);
    const int row = (h - 1 - py) * f;
    for (int px = 0; px < w; ++px) {
      CellState c = CellState::kUnknown;
      for (int y = row; y < std::min(row + f, m.height) && c != CellState::kOccupied; ++y)
        for (int x = px * f; x < std::min(px * f + f, m.width); ++x) {
          const CellState v = m.at(x, y);
          if (v == CellState::kOccupied) {
            c = v;
            break;
          }
          if (v == CellState::kFree) c = v;
        }
      line[px] = c == CellState::kOccupied ? 0x000000u : c == CellState::kFree ? 0xFFFFFFu : 0xC8C8C8u;
    }
  }
  cairo_surface_mark_dirty(s);
  return s;
}

// A panel's size in pixels: its longer side `side`, the other as the drawing's aspect asks (at least a quarter).
std::pair<int, int> panel_size(const Panel& p, int side) {
  const Box b = bounds(p);
  const double w = std::max(b.x1 - b.x0, 1e-3), h = std::max(b.y1 - b.y0, 1e-3);
  const auto other = [side](double ratio) {
    return std::max(side / 4, static_cast<int>(std::lround(2 * kMargin + (side - 2 * kMargin) * ratio)));
  };
  return w >= h ? std::pair{side, other(h / w)} : std::pair{other(w / h), side};
}

// A panel's frame in pixels: x right, y up, the box of its content centred.
struct PanelView {
  double cx, cy;  ///< the panel's centre [px]
  double mx, my;  ///< the content box's centre [m]
  double scale;   ///< [px/m]
  Vec2 px(const Vec2& q) const { return Vec2(cx + (q.x() - mx) * scale, cy - (q.y() - my) * scale); }
};

void draw_grid(cairo_t* cr, const GridMap& map, const PanelView& v, int width, int height) {
  int f = 1;
  cairo_surface_t* image = grid_image(map, 2 * std::max(width, height), f);
  const int h = cairo_image_surface_get_height(image);
  cairo_save(cr);
  cairo_translate(cr, v.cx - v.mx * v.scale, v.cy + v.my * v.scale);
  cairo_scale(cr, v.scale, -v.scale);  // now in the panel's frame, y up
  cairo_translate(cr, map.origin.x, map.origin.y);
  cairo_rotate(cr, map.origin.theta);
  cairo_translate(cr, 0, h * f * map.resolution);
  cairo_scale(cr, f * map.resolution, -f * map.resolution);  // image pixels, y down
  cairo_set_source_surface(cr, image, 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
  cairo_surface_destroy(image);
}

void draw_path(cairo_t* cr, const Panel& p, const PanelView& v) {
  cairo_set_source_rgb(cr, 0.2, 0.4, 0.9);
  cairo_set_line_width(cr, 1.2);
  for (std::size_t i = 0; i < p.path.size(); ++i) {
    const Vec2 d = v.px(p.path[i]);
    if (i == 0 || (!p.path_joined.empty() && !p.path_joined[i])) cairo_move_to(cr, d.x(), d.y());
    else cairo_line_to(cr, d.x(), d.y());
  }
  cairo_stroke(cr);
  for (std::size_t i = 0; i < p.path.size(); ++i) {
    const Rgb c = p.path_colours.empty() ? kGood : p.path_colours[i];
    const Vec2 d = v.px(p.path[i]);
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_arc(cr, d.x(), d.y(), 3.0, 0, 2 * 3.14159265358979);
    cairo_fill(cr);
  }
}

// A 1 m scale bar (or 10 m when 1 m is under 20 pixels), bottom left; the legend bottom right.
void draw_scale_and_legend(cairo_t* cr, const Panel& p, double scale, double left, int width, int height) {
  const double metres = scale >= 20 ? 1 : scale >= 2 ? 10 : 100;
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 3);
  cairo_move_to(cr, left + kMargin, kTitleHeight + height - kMargin);
  cairo_line_to(cr, left + kMargin + metres * scale, kTitleHeight + height - kMargin);
  cairo_stroke(cr);
  cairo_set_font_size(cr, 12);
  cairo_move_to(cr, left + kMargin, kTitleHeight + height - kMargin - 6);
  cairo_show_text(cr, (std::to_string(static_cast<int>(metres)) + " m").c_str());
  if (!p.legend.empty()) {
    cairo_text_extents_t extents;
    cairo_text_extents(cr, p.legend.c_str(), &extents);
    cairo_move_to(cr, left + width - kMargin - extents.x_advance, kTitleHeight + height - kMargin);
    cairo_show_text(cr, p.legend.c_str());
  }
}

void draw_panel(cairo_t* cr, const Panel& p, double left, int width, int height) {
  const Box b = bounds(p);
  const double scale = std::min((width - 2 * kMargin) / std::max(b.x1 - b.x0, 1e-3),
                                (height - 2 * kMargin) / std::max(b.y1 - b.y0, 1e-3));
  const PanelView v{left + width / 2.0, kTitleHeight + height / 2.0, (b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2, scale};
  cairo_save(cr);
  cairo_rectangle(cr, left, kTitleHeight, width, height);
  cairo_clip(cr);
  cairo_set_source_rgb(cr, 0.97, 0.97, 0.97);
  cairo_paint(cr);
  if (p.map) draw_grid(cr, *p.map, v, width, height);
  for (const PointLayer& l : p.layers) {
    cairo_set_source_rgb(cr, l.colour.r, l.colour.g, l.colour.b);
    for (const Vec2& q : l.points) {
      const Vec2 d = v.px(q);
      cairo_rectangle(cr, d.x() - l.radius, d.y() - l.radius, 2 * l.radius, 2 * l.radius);
    }
    cairo_fill(cr);
  }
  if (!p.path.empty()) draw_path(cr, p, v);
  draw_scale_and_legend(cr, p, scale, left, width, height);
  cairo_restore(cr);
  cairo_save(cr);
  cairo_rectangle(cr, left, 0, width, kTitleHeight);
  cairo_clip(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 14);
  cairo_move_to(cr, left + 4, 18);
  cairo_show_text(cr, p.title.c_str());
  cairo_restore(cr);
}

}  // namespace

Points2 transformed(const Points2& points, const Pose2& T) {
  Points2 out;
  out.reserve(points.size());
  for (const Vec2& p : points) out.push_back(T * p);
  return out;
}

void write_panels_png(const std::filesystem::path& path, const std::vector<Panel>& panels, int panel_side) {
  if (panels.empty()) throw InputError(path.string() + ": no panel to draw");
  if (panel_side < 64 || panel_side > 8000) throw InputError("answer picture: panel_side must be in [64, 8000]");
  for (const Panel& p : panels) {
    if (p.map) validate(*p.map);
    if (!p.path_colours.empty() && p.path_colours.size() != p.path.size())
      throw InputError(path.string() + ": panel '" + p.title + "': one path colour per path point");
    if (!p.path_joined.empty() && p.path_joined.size() != p.path.size())
      throw InputError(path.string() + ": panel '" + p.title + "': one path_joined flag per path point");
    if (bounds(p).empty()) throw InputError(path.string() + ": panel '" + p.title + "' has nothing to draw");
  }
  int width = -kGap, height = 0;
  for (const Panel& p : panels) {
    const auto [w, h] = panel_size(p, panel_side);
    width += w + kGap, height = std::max(height, h);
  }
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, std::max(width, 300), height + kTitleHeight);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  int left = 0;
  for (const Panel& p : panels) {
    const int w = panel_size(p, panel_side).first;
    draw_panel(cr, p, left, w, height);
    left += w + kGap;
  }
  cairo_destroy(cr);
  write_png_atomically(path, surface);
}

}  // namespace partslam::plot
