#include "plot/render.h"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/error.h"
#include "plot/png_file.h"

namespace partslam::plot {
namespace {

constexpr double kPanelMargin = 24;  // panel margin [px]
constexpr double kCaption = 30;  // caption band above a panel [px]
constexpr double kPalette[][3] = {
    {0.84, 0.15, 0.16}, {0.12, 0.47, 0.71}, {0.17, 0.63, 0.17}, {1.0, 0.5, 0.05},   {0.58, 0.4, 0.74},
    {0.09, 0.75, 0.81}, {0.89, 0.47, 0.76}, {0.55, 0.34, 0.29}, {0.74, 0.74, 0.13}, {0.5, 0.5, 0.5}};

void set_part_colour(cairo_t* cr, std::size_t i, double alpha = 1.0) {
  const auto& c = kPalette[i % std::size(kPalette)];
  cairo_set_source_rgba(cr, c[0], c[1], c[2], alpha);
}

// World box [m] fitted into a pixel rectangle, aspect kept, centred; y points up.
struct Viewport {
  Box2 world;
  double left = 0, top = 0, width = 0, height = 0;  // pixel rectangle
  double scale = 1;                                 // px per m
  double px(double x) const { return left + width / 2 + (x - (world.x_min + world.x_max) / 2) * scale; }
  double py(double y) const { return top + height / 2 - (y - (world.y_min + world.y_max) / 2) * scale; }
};

Viewport fit(const Box2& world, double left, double top, double width, double height) {
  Viewport v{world, left, top, width, height, 1.0};
  v.scale = std::min(width / std::max(world.width(), 1e-3), height / std::max(world.height(), 1e-3));
  return v;
}

Box2 grow(Box2 b, const Box2& o) {
  if (!(o.width() > 0 || o.height() > 0)) return b;
  return {std::min(b.x_min, o.x_min), std::max(b.x_max, o.x_max), std::min(b.y_min, o.y_min),
          std::max(b.y_max, o.y_max)};
}

Box2 pad(const Box2& b, double m) { return {b.x_min - m, b.x_max + m, b.y_min - m, b.y_max + m}; }

// Points as squares, not antialiased: crisp dots and far fewer grey levels for the PNG to compress.
void draw_points(cairo_t* cr, const Viewport& v, const Points2& points, double radius) {
  const double side = std::max(1.0, std::round(2 * radius));
  for (const Vec2& p : points)
    cairo_rectangle(cr, std::round(v.px(p.x()) - side / 2), std::round(v.py(p.y()) - side / 2), side, side);
  cairo_save(cr);
  cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
  cairo_fill(cr);
  cairo_restore(cr);
}

void draw_box(cairo_t* cr, const Viewport& v, const Box2& b) {
  cairo_rectangle(cr, v.px(b.x_min), v.py(b.y_max), b.width() * v.scale, b.height() * v.scale);
  cairo_stroke(cr);
}

void draw_text(cairo_t* cr, double x, double y, const std::string& text) {
  cairo_move_to(cr, x, y);
  cairo_show_text(cr, text.c_str());
}

// Labels at the boxes' top-left corners, on white patches so they stay readable over points; a label that
// would cover an earlier one moves down below it.
class BoxLabels {
 public:
  void draw(cairo_t* cr, const Viewport& v, const Box2& b, std::size_t i, const std::string& text) {
    cairo_text_extents_t e;
    cairo_text_extents(cr, text.c_str(), &e);
    const double w = e.x_advance + 4, h = 17;
    const double x = v.px(b.x_min) + 2;
    double y = v.py(b.y_max) + 2;
    for (bool moved = true; moved;) {
      moved = false;
      for (const Box2& r : placed_) {
        if (x < r.x_max && x + w > r.x_min && y < r.y_max && y + h > r.y_min) y = r.y_max, moved = true;
      }
    }
    placed_.push_back({x, x + w, y, y + h});
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_rectangle(cr, x, y, w, h);
    cairo_fill(cr);
    set_part_colour(cr, i);
    draw_text(cr, x + 2, y + 13, text);
  }

 private:
  std::vector<Box2> placed_;  // pixel rectangles of the labels drawn so far
};

// A scale bar of a round length about a fifth of the panel, at its bottom-left corner.
void draw_scale_bar(cairo_t* cr, const Viewport& v) {
  const double target = v.width / 5 / v.scale;
  double length = 0.1;
  for (double c : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0})
    if (c <= target) length = c;
  const double x = v.left + 8, y = v.top + v.height - 8;
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 3);
  cairo_move_to(cr, x, y);
  cairo_line_to(cr, x + length * v.scale, y);
  cairo_stroke(cr);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g m", length);
  draw_text(cr, x, y - 6, buf);
}

void draw_frame(cairo_t* cr, const Viewport& v, const std::string& caption) {
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 1);
  cairo_rectangle(cr, v.left - 6, v.top - 6, v.width + 12, v.height + 12);
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 16);
  draw_text(cr, v.left - 6, v.top - 13, caption);
  cairo_set_font_size(cr, 13);
}

// The part's cropped map points carried onto its descriptor box: turned by its quarter turns about the
// keypoint box's centre and moved to the descriptor box's centre.
Points2 carried_crop(const Points2& map_points, const Part& part) {
  const Box2& k = part.keypoint_box;
  const Box2& d = part.descriptor_box;
  const Vec2 ck{(k.x_min + k.x_max) / 2, (k.y_min + k.y_max) / 2};
  const Vec2 cd{(d.x_min + d.x_max) / 2, (d.y_min + d.y_max) / 2};
  const Pose2 T_dict_map =
      Pose2{cd.x(), cd.y(), part.rotation * std::numbers::pi / 2} * Pose2{-ck.x(), -ck.y(), 0};
  Points2 out;
  for (const Vec2& p : map_points)
    if (p.x() >= k.x_min && p.x() <= k.x_max && p.y() >= k.y_min && p.y() <= k.y_max)
      out.push_back(T_dict_map * p);
  return out;
}

std::string part_label(std::size_t i, const Part& p, bool with_score) {
  char buf[48];
  if (!with_score) return std::to_string(i + 1);
  std::snprintf(buf, sizeof buf, "%zu  AS %.2f", i + 1, p.appearance_score);
  return buf;
}

}  // namespace

void validate(const RenderConfig& c) {
  if (c.width < 200 || c.width > 10000) throw InputError("render: width must be in [200, 10000] px");
  if (c.map_panel_height < 100 || c.map_panel_height > 10000)
    throw InputError("render: map_panel_height must be in [100, 10000] px");
  if (c.max_dictionary_height < 100 || c.max_dictionary_height > 10000)
    throw InputError("render: max_dictionary_height must be in [100, 10000] px");
  if (!(c.point_radius > 0 && c.point_radius <= 20))
    throw InputError("render: point_radius must be in (0, 20] px");
  if (!(c.box_line_width > 0 && c.box_line_width <= 20))
    throw InputError("render: box_line_width must be in (0, 20] px");
}

namespace {

// The dictionary's points, the crops carried onto the descriptor boxes and the boxes, in `view`.
void draw_dictionary_panel(cairo_t* cr, const Viewport& view, const PartsFigure& f, const RenderConfig& c,
                           const std::string& caption) {
  draw_frame(cr, view, caption);
  cairo_save(cr);
  cairo_rectangle(cr, view.left - 5, view.top - 5, view.width + 10, view.height + 10);
  cairo_clip(cr);
  cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
  const double radius = std::clamp(0.04 * view.scale, 0.6, c.point_radius);  // a 0.08 m dot, within limits
  draw_points(cr, view, f.dictionary_points, radius);
  for (std::size_t i = f.parts.size(); i-- > 0;) {
    set_part_colour(cr, i, 0.75);
    draw_points(cr, view, carried_crop(f.map_points, f.parts[i]), std::max(radius, 0.8 * c.point_radius));
    set_part_colour(cr, i);
    cairo_set_line_width(cr, c.box_line_width);
    draw_box(cr, view, f.parts[i].descriptor_box);
  }
  BoxLabels labels;
  for (std::size_t i = 0; i < f.parts.size(); ++i)
    labels.draw(cr, view, f.parts[i].descriptor_box, i, std::to_string(i + 1));
  cairo_restore(cr);
  draw_scale_bar(cr, view);
}

}  // namespace

void write_parts_figure(const std::filesystem::path& path, const PartsFigure& f, const RenderConfig& c) {
  validate(c);
  const double inner_w = c.width - 2 * kPanelMargin;
  // A panel of `world` below y = top: as wide as the image, as tall as the world's aspect asks up to max_h.
  auto panel_below = [&](const Box2& world, double top, double max_h) {
    const double h = std::min(max_h, inner_w * world.height() / std::max(world.width(), 1e-3));
    return fit(world, kPanelMargin, top + kCaption, inner_w, std::max(h, 40.0));
  };
  auto bottom = [](const Viewport& v) { return v.top + v.height + kPanelMargin; };

  Box2 map_world = f.map_points.empty() ? Box2{-1, 1, -1, 1} : bounding_box(f.map_points);
  for (const Part& p : f.parts) map_world = grow(map_world, p.keypoint_box);
  const Viewport map_view =
      panel_below(pad(map_world, 0.3), kPanelMargin, c.map_panel_height - kCaption - kPanelMargin);
  double height = bottom(map_view);

  // The whole dictionary, and a zoom on the descriptor boxes when they cover a small part of it.
  Viewport dict_view, zoom_view;
  bool zoom = false;
  Box2 zoom_world;
  if (f.show_dictionary) {
    Box2 world = f.dictionary_points.empty() ? Box2{-1, 1, -1, 1} : bounding_box(f.dictionary_points);
    for (const Part& p : f.parts) world = grow(world, p.descriptor_box);
    world = pad(world, 1.0);
    dict_view = panel_below(world, height, c.max_dictionary_height);
    height = bottom(dict_view);
    if (!f.parts.empty()) {
      zoom_world = f.parts.front().descriptor_box;
      for (const Part& p : f.parts) zoom_world = grow(zoom_world, p.descriptor_box);
      zoom_world = pad(zoom_world, 2.0);
      zoom = zoom_world.area() < 0.25 * world.area();
    }
    if (zoom) {
      zoom_view = panel_below(zoom_world, height, c.map_panel_height - kCaption - kPanelMargin);
      height = bottom(zoom_view);
    }
  }

  cairo_surface_t* surface =
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, c.width, static_cast<int>(std::ceil(height)));
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);

  // Top panel: the map and its keypoint boxes.
  draw_frame(cr, map_view, f.map_title);
  cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
  draw_points(cr, map_view, f.map_points, c.point_radius);
  cairo_set_line_width(cr, c.box_line_width);
  for (std::size_t i = f.parts.size(); i-- > 0;) {  // best part drawn last, on top
    set_part_colour(cr, i);
    draw_box(cr, map_view, f.parts[i].keypoint_box);
  }
  BoxLabels map_labels;
  for (std::size_t i = 0; i < f.parts.size(); ++i)
    map_labels.draw(cr, map_view, f.parts[i].keypoint_box, i, part_label(i, f.parts[i], f.show_scores));
  draw_scale_bar(cr, map_view);

  if (f.show_dictionary) {
    draw_dictionary_panel(cr, dict_view, f, c, f.dictionary_title);
    if (zoom) {
      cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
      cairo_set_line_width(cr, 1);
      const double dash = 4;
      cairo_save(cr);
      cairo_rectangle(cr, dict_view.left - 5, dict_view.top - 5, dict_view.width + 10, dict_view.height + 10);
      cairo_clip(cr);
      cairo_set_dash(cr, &dash, 1, 0);
      draw_box(cr, dict_view, zoom_world);
      cairo_restore(cr);
      draw_dictionary_panel(cr, zoom_view, f, c, "the dashed area enlarged");
    }
  }
  cairo_destroy(cr);

  write_png_atomically(path, surface);
}

}  // namespace partslam::plot
