#include "core/maps/manhattan.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace partslam {
namespace {

// Entropy of the histogram of integer bin indices, counted in a dense array over [min, max].
double histogram_entropy(const std::vector<std::int64_t>& bins, std::vector<int>& counts) {
  if (bins.empty()) return 0.0;
  const auto [lo, hi] = std::minmax_element(bins.begin(), bins.end());
  counts.assign(static_cast<std::size_t>(*hi - *lo + 1), 0);
  for (std::int64_t b : bins) ++counts[static_cast<std::size_t>(b - *lo)];
  const double n = static_cast<double>(bins.size());
  double h = 0.0;
  for (int c : counts) {
    if (c == 0) continue;
    const double p = c / n;
    h -= p * std::log(p);
  }
  return h;
}

}  // namespace

double axis_entropy(const Points2& points, double angle, double bin_size) {
  const double c = std::cos(angle), s = std::sin(angle);
  std::vector<std::int64_t> bx, by;
  bx.reserve(points.size());
  by.reserve(points.size());
  for (const Vec2& p : points) {
    bx.push_back(static_cast<std::int64_t>(std::floor((c * p.x() - s * p.y()) / bin_size)));
    by.push_back(static_cast<std::int64_t>(std::floor((s * p.x() + c * p.y()) / bin_size)));
  }
  std::vector<int> counts;
  return histogram_entropy(bx, counts) + histogram_entropy(by, counts);
}

double manhattan_angle(const Points2& points, const ManhattanConfig& config) {
  if (points.size() < 2) return 0.0;
  const double quarter = std::numbers::pi / 2;
  double best_angle = 0.0, best_h = axis_entropy(points, 0.0, config.bin_size);
  for (double a = config.coarse_step; a < quarter; a += config.coarse_step) {
    const double h = axis_entropy(points, a, config.bin_size);
    if (h < best_h) best_h = h, best_angle = a;
  }
  const double centre = best_angle;
  for (double d = -config.coarse_step; d <= config.coarse_step; d += config.fine_step) {
    const double a = centre + d;
    const double h = axis_entropy(points, a, config.bin_size);
    if (h < best_h) best_h = h, best_angle = a;
  }
  best_angle = std::fmod(best_angle, quarter);
  if (best_angle < 0) best_angle += quarter;
  return best_angle;
}

}  // namespace partslam
