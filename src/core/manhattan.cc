#include "core/manhattan.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace partslam {
namespace {

double histogram_entropy(std::vector<std::int64_t>& bins) {
  if (bins.empty()) return 0.0;
  std::sort(bins.begin(), bins.end());
  const double n = static_cast<double>(bins.size());
  double h = 0.0;
  for (std::size_t i = 0; i < bins.size();) {
    std::size_t j = i;
    while (j < bins.size() && bins[j] == bins[i]) ++j;
    const double p = static_cast<double>(j - i) / n;
    h -= p * std::log(p);
    i = j;
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
  return histogram_entropy(bx) + histogram_entropy(by);
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
