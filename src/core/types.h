// Basic 2D geometry types shared by every layer: points, point sets and rigid poses (SE(2)).
// Frames are spelled in variable names: T_world_map maps map-frame points into the world frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <vector>

namespace partslam {

using Vec2 = Eigen::Vector2d;

/// The map lattice every layer shares unless told otherwise: points are downsampled to one per cell of this
/// side, grids, codecs and matchers quantise on it [m] (docs/DESIGN.md, "Submap").
inline constexpr double kMapResolution = 0.1;
/// Side of the square crop of a submap around its centroid [m]; map points lie within +-kCropSize / 2.
inline constexpr double kCropSize = 12.8;
/// One degree [rad].
inline constexpr double kDegree = std::numbers::pi / 180;
/// Degrees in a radian (for printing angles).
inline constexpr double kDegreesPerRadian = 180 / std::numbers::pi;
/// A 2D point set [m]. std::vector is fine for Vector2d under C++17 aligned new.
using Points2 = std::vector<Vec2>;

/// Wraps an angle to (-pi, pi].
inline double wrap_angle(double a) {
  a = std::fmod(a + std::numbers::pi, 2.0 * std::numbers::pi);
  if (a <= 0.0) a += 2.0 * std::numbers::pi;
  return a - std::numbers::pi;
}

/// A rigid 2D pose: rotation by theta, then translation by (x, y).
struct Pose2 {
  double x = 0.0;      ///< [m]
  double y = 0.0;      ///< [m]
  double theta = 0.0;  ///< [rad]

  Vec2 translation() const { return {x, y}; }
  Eigen::Matrix2d rotation() const { return Eigen::Rotation2Dd(theta).toRotationMatrix(); }
  /// The map of operator*(Vec2) with its cosine and sine taken once: for one pose applied to many points (the
  /// same arithmetic, so the same doubles).
  struct Applied {
    double c, s, x, y;
    Vec2 operator()(const Vec2& p) const { return {c * p.x() - s * p.y() + x, s * p.x() + c * p.y() + y}; }
  };
  Applied applied() const { return {std::cos(theta), std::sin(theta), x, y}; }
  /// Maps a point from this pose's child frame into its parent frame.
  Vec2 operator*(const Vec2& p) const { return applied()(p); }
  /// Composition: (T_a_b * T_b_c) = T_a_c.
  Pose2 operator*(const Pose2& o) const {
    const Vec2 t = (*this) * o.translation();
    return {t.x(), t.y(), wrap_angle(theta + o.theta)};
  }
  Pose2 inverse() const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {-(c * x + s * y), -(-s * x + c * y), wrap_angle(-theta)};
  }
};

/// How close two poses must be to count as the same pose: every "pose within tolerance" check (the relevant map's
/// pose in eval, a loop closure, a relocalisation, a relation, consistency in a pose graph).
struct PoseTolerance {
  double translation = 0.5;  ///< [m]
  double rotation = 0.2;     ///< [rad]
  bool accepts(const Pose2& a, const Pose2& b) const {
    return (a.translation() - b.translation()).norm() <= translation && std::abs(wrap_angle(a.theta - b.theta)) <= rotation;
  }
  bool valid() const { return translation >= 0 && rotation >= 0 && std::isfinite(translation) && std::isfinite(rotation); }
};

/// Applies a pose to every point of a set.
inline Points2 transform(const Pose2& T, const Points2& points) {
  Points2 out;
  out.reserve(points.size());
  const Pose2::Applied apply = T.applied();
  for (const Vec2& p : points) out.push_back(apply(p));
  return out;
}

/// Every k-th point, k the smallest stride that leaves at most max_points (all of them when they are fewer), in
/// order. max_points must be positive.
inline Points2 thinned(const Points2& points, std::size_t max_points) {
  if (points.size() <= max_points) return points;
  Points2 out;
  const std::size_t stride = (points.size() + max_points - 1) / max_points;
  for (std::size_t i = 0; i < points.size(); i += stride) out.push_back(points[i]);
  return out;
}

/// Mean of a point set; (0, 0) for an empty set.
inline Vec2 centroid(const Points2& points) {
  Vec2 c = Vec2::Zero();
  for (const Vec2& p : points) c += p;
  return points.empty() ? c : Vec2(c / static_cast<double>(points.size()));
}

/// Axis-aligned box [x_min, x_max) x [y_min, y_max) [m].
struct Box2 {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0;
  double width() const { return x_max - x_min; }
  double height() const { return y_max - y_min; }
  double area() const { return width() > 0 && height() > 0 ? width() * height() : 0.0; }
  bool contains(const Vec2& p) const {
    return p.x() >= x_min && p.x() < x_max && p.y() >= y_min && p.y() < y_max;
  }
};

/// Bounding box of a point set (empty box for an empty set).
inline Box2 bounding_box(const Points2& points) {
  if (points.empty()) return {};
  Box2 b{points[0].x(), points[0].x(), points[0].y(), points[0].y()};
  for (const Vec2& p : points) {
    b.x_min = std::min(b.x_min, p.x());
    b.x_max = std::max(b.x_max, p.x());
    b.y_min = std::min(b.y_min, p.y());
    b.y_max = std::max(b.y_max, p.y());
  }
  return b;
}

}  // namespace partslam
