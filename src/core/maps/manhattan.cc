#include "core/maps/manhattan.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
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

std::vector<double> wall_directions(const Points2& points, const WallDirectionConfig& config) {
  constexpr int kBins = 90;  // 1 deg bins over a quarter turn
  const double bin = std::numbers::pi / 2 / kBins;
  std::unordered_map<std::int64_t, std::vector<Vec2>> cells;
  for (const Vec2& p : points) {
    const auto x = static_cast<std::int64_t>(std::floor(p.x() / config.cell));
    const auto y = static_cast<std::int64_t>(std::floor(p.y() / config.cell));
    cells[static_cast<std::int64_t>((static_cast<std::uint64_t>(x) << 32) ^ static_cast<std::uint32_t>(y))]
        .push_back(p);
  }
  std::vector<double> weight(kBins, 0.0);
  double total = 0.0;
  for (const auto& [key, cell] : cells) {
    if (static_cast<int>(cell.size()) < config.min_points) continue;
    Vec2 mean = Vec2::Zero();
    for (const Vec2& p : cell) mean += p;
    mean /= static_cast<double>(cell.size());
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
    for (const Vec2& p : cell) covariance += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(covariance);
    const Eigen::Vector2d variances = solver.eigenvalues();  // ascending
    if (!(variances(1) > 0.0) || variances(0) > config.max_flatness * variances(1)) continue;
    const Eigen::Vector2d along = solver.eigenvectors().col(1);
    double angle = std::fmod(std::atan2(along.y(), along.x()), std::numbers::pi / 2);
    if (angle < 0) angle += std::numbers::pi / 2;
    // The piece's length: a segment of length L spreads its points with variance L^2 / 12 along it.
    const double length = std::sqrt(12.0 * variances(1) / static_cast<double>(cell.size()));
    weight[static_cast<std::size_t>(std::lround(angle / bin)) % kBins] += length;
    total += length;
  }
  std::vector<double> out;
  if (total == 0.0) return out;
  const int half = static_cast<int>(std::lround(config.window / bin));
  std::vector<double> share(kBins, 0.0);
  for (int b = 0; b < kBins; ++b)
    for (int k = -half; k <= half; ++k) share[b] += weight[((b + k) % kBins + kBins) % kBins] / total;
  // Angular distance on the quarter-turn circle [rad].
  const auto apart = [](double a, double b) { return std::abs(std::remainder(a - b, std::numbers::pi / 2)); };
  while (static_cast<int>(out.size()) < config.max_directions) {
    int best = -1;
    for (int b = 0; b < kBins; ++b) {
      if (apart(b * bin, 0.0) < config.min_separation ||
          apart(b * bin, std::numbers::pi / 4) < config.min_separation)
        continue;
      if (std::any_of(out.begin(), out.end(),
                      [&](double d) { return apart(b * bin, d) < config.min_separation; }))
        continue;
      const bool peak = share[b] >= share[(b + 1) % kBins] && share[b] >= share[(b + kBins - 1) % kBins];
      if (peak && (best < 0 || share[b] > share[best]))
        best = b;  // a peak, not the shoulder of the axes' one
    }
    if (best < 0 || share[best] < config.min_share || share[best] * total < config.min_length) break;
    // The direction: the walls' weighted mean within the window (a flat-topped peak is found at its edge).
    double sum = 0.0, moment = 0.0;
    for (int k = -half; k <= half; ++k) {
      const double w = weight[((best + k) % kBins + kBins) % kBins];
      sum += w, moment += w * k;
    }
    out.push_back(std::remainder((best + moment / sum) * bin, std::numbers::pi / 2));
  }
  return out;
}

double log_wall_axis(const Scans& scans, std::size_t first) {
  double c = 0, s = 0;
  for (std::size_t k = 0; k < std::min(scans.size(), first); ++k) {
    const double heading = scans[k].T_world_laser.theta;
    for_each_surface_tangent(scans[k].points_laser, std::numeric_limits<double>::infinity(), [&](const Vec2& d) {
      const double normal = heading + std::atan2(d.x(), -d.y());
      c += std::cos(4 * normal), s += std::sin(4 * normal);
    });
  }
  if (std::hypot(c, s) < 1e-9) return 0.0;
  return std::atan2(s, c) / 4;
}

}  // namespace partslam
