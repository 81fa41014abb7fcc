#include "plot/line_plot.h"

#include <cairo.h>

#include <algorithm>
#include <cstdio>

#include "core/error.h"
#include "plot/png_file.h"

namespace partslam::plot {
namespace {

constexpr int kWidth = 900, kHeight = 600;
constexpr double kLeft = 70, kRight = 240, kTop = 40, kBottom = 60;

void set_colour(cairo_t* cr, std::size_t i) {
  static const double palette[][3] = {{0.12, 0.47, 0.71}, {1.0, 0.5, 0.05}, {0.17, 0.63, 0.17}, {0.84, 0.15, 0.16},
                                      {0.58, 0.4, 0.74},  {0.55, 0.34, 0.29}, {0.89, 0.47, 0.76}, {0.5, 0.5, 0.5},
                                      {0.74, 0.74, 0.13}, {0.09, 0.75, 0.81}};
  const auto& c = palette[i % 10];
  cairo_set_source_rgb(cr, c[0], c[1], c[2]);
}

}  // namespace

void write_line_plot(const std::filesystem::path& path, const Axes& axes, const std::vector<Curve>& curves) {
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, kWidth, kHeight);
  cairo_t* cr = cairo_create(surface);
  const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
  auto X = [&](double x) { return kLeft + pw * std::clamp(x, 0.0, 1.0); };
  auto Y = [&](double y) { return kTop + ph * (1.0 - std::clamp(y, 0.0, 1.0)); };

  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 13);
  // Grid and axes.
  cairo_set_line_width(cr, 1);
  char buf[64];
  for (int i = 0; i <= 10; ++i) {
    const double t = i / 10.0;
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, X(t), Y(0));
    cairo_line_to(cr, X(t), Y(1));
    cairo_move_to(cr, X(0), Y(t));
    cairo_line_to(cr, X(1), Y(t));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    std::snprintf(buf, sizeof buf, "%.*f", axes.x_tick_decimals, t * axes.x_tick_scale);
    cairo_move_to(cr, X(t) - 7, Y(0) + 18);
    cairo_show_text(cr, buf);
    std::snprintf(buf, sizeof buf, "%.1f", t);
    cairo_move_to(cr, X(0) - 32, Y(t) + 4);
    cairo_show_text(cr, buf);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, X(0), Y(1), pw, ph);
  cairo_stroke(cr);
  cairo_move_to(cr, X(0.5) - 70, kHeight - 20);
  cairo_show_text(cr, axes.x_label.c_str());
  cairo_move_to(cr, 10, kTop - 15);
  cairo_show_text(cr, axes.y_label.c_str());
  cairo_set_font_size(cr, 15);
  cairo_move_to(cr, X(0.5) - 4 * static_cast<double>(axes.title.size()), kTop - 15);
  cairo_show_text(cr, axes.title.c_str());
  cairo_set_font_size(cr, 13);

  cairo_set_line_width(cr, 2);
  for (std::size_t c = 0; c < curves.size(); ++c) {
    set_colour(cr, c);
    // Past ten curves the palette repeats; dashes keep them apart.
    const double dash[] = {8.0, 4.0};
    cairo_set_dash(cr, dash, c >= 10 ? 2 : 0, 0);
    for (std::size_t i = 0; i < curves[c].points.size(); ++i) {
      const auto [x, y] = curves[c].points[i];
      if (i == 0) {
        cairo_move_to(cr, X(x), Y(y));
      } else {
        cairo_line_to(cr, X(x), Y(y));
      }
    }
    cairo_stroke(cr);
    const double ly = kTop + 20 + 20 * static_cast<double>(c);
    cairo_move_to(cr, kWidth - kRight + 15, ly);
    cairo_line_to(cr, kWidth - kRight + 40, ly);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, kWidth - kRight + 46, ly + 4);
    cairo_show_text(cr, curves[c].label.c_str());
  }
  cairo_destroy(cr);

  write_png_atomically(path, surface);
}

}  // namespace partslam::plot
