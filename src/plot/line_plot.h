// Line plots on the unit square with cairo (the paper's Fig. D, loop-closure precision-recall curves): grid,
// axes with ten ticks, a title and a legend, one polyline per curve, written as PNG atomically.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace partslam::plot {

struct Curve {
  std::string label;
  std::vector<std::pair<double, double>> points;  ///< (x, y) in [0, 1] x [0, 1], clamped, drawn in order
};

struct Axes {
  std::string title;
  std::string x_label;
  std::string y_label;
  double x_tick_scale = 1.0;  ///< tick labels show x * scale (e.g. 100 for percent)
  int x_tick_decimals = 1;
};

/// Throws InputError naming the path when it cannot be written.
void write_line_plot(const std::filesystem::path& path, const Axes& axes, const std::vector<Curve>& curves);

}  // namespace partslam::plot
