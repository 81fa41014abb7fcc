#include "core/maps/local_shape.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "core/error.h"

namespace partslam {

std::vector<LocalShape> local_shapes(const Points2& points, double radius) {
  if (!(radius > 0.0) || !std::isfinite(radius)) throw InputError("local shape: radius must be positive");
  const double r2 = radius * radius;
  // Points bucketed by cells of side `radius`, sorted by cell: a neighbourhood lies in the 3 x 3 cells
  // around its point.
  using Cell = std::pair<std::int64_t, std::int64_t>;
  const auto cell_of = [radius](const Vec2& p) {
    return Cell{static_cast<std::int64_t>(std::floor(p.x() / radius)),
                static_cast<std::int64_t>(std::floor(p.y() / radius))};
  };
  std::vector<std::pair<Cell, std::size_t>> sorted;
  sorted.reserve(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!((points[k] / radius).array().abs() < 1e15).all())
      throw InputError("local shape: point " + std::to_string(k) + " is not finite or lies too far out");
    sorted.emplace_back(cell_of(points[k]), k);
  }
  std::sort(sorted.begin(), sorted.end());
  std::vector<LocalShape> shapes(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2& p = points[i];
    // Moments of the offsets from p (well conditioned far from the origin).
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    int n = 0;
    const Cell c = cell_of(p);
    for (std::int64_t bx = c.first - 1; bx <= c.first + 1; ++bx) {
      for (std::int64_t by = c.second - 1; by <= c.second + 1; ++by) {
        auto it =
            std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(Cell{bx, by}, std::size_t{0}));
        for (; it != sorted.end() && it->first == Cell{bx, by}; ++it) {
          const Vec2 d = points[it->second] - p;
          if (d.squaredNorm() > r2) continue;
          sx += d.x(), sy += d.y(), sxx += d.x() * d.x(), sxy += d.x() * d.y(), syy += d.y() * d.y(), ++n;
        }
      }
    }
    LocalShape& s = shapes[i];
    s.neighbours = n;
    if (n == 0) continue;
    const double mx = sx / n, my = sy / n;
    const double cxx = sxx / n - mx * mx, cxy = sxy / n - mx * my, cyy = syy / n - my * my;
    const double half_trace = (cxx + cyy) / 2;
    const double root = std::sqrt(std::max(0.0, half_trace * half_trace - (cxx * cyy - cxy * cxy)));
    s.lambda_min = half_trace - root, s.lambda_max = half_trace + root;
    s.angle = 0.5 * std::atan2(2 * cxy, cxx - cyy);
  }
  return shapes;
}

Eigen::Matrix2d wall_scatter(const std::vector<LocalShape>& shapes) {
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  for (const LocalShape& s : shapes) {
    const double w = 1.0 - s.cornerness();
    if (!(w > 0)) continue;
    const Vec2 n(-std::sin(s.angle), std::cos(s.angle));
    A += w * n * n.transpose();
  }
  return A;
}

std::optional<Vec2> unconstrained_direction(const Eigen::Matrix2d& scatter, double ratio) {
  if (!(ratio > 0)) return std::nullopt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  const Eigen::Vector2d l = eig.eigenvalues();  // ascending
  if (!(l(1) > 0) || l(0) >= ratio * l(1)) return std::nullopt;
  return Vec2(eig.eigenvectors().col(0));
}

Pose2 keep_along(const Pose2& moved, const Pose2& start, const Vec2& direction, double slack) {
  const Vec2 v = Eigen::Rotation2Dd(moved.theta) * direction;
  const double along = v.dot(moved.translation() - start.translation());
  const Vec2 t = moved.translation() + v * (std::clamp(along, -slack, slack) - along);
  return {t.x(), t.y(), moved.theta};
}

std::vector<double> cornerness(const Points2& points, double radius) {
  const std::vector<LocalShape> shapes = local_shapes(points, radius);
  std::vector<double> c(shapes.size());
  std::transform(shapes.begin(), shapes.end(), c.begin(), [](const LocalShape& s) { return s.cornerness(); });
  return c;
}

}  // namespace partslam
