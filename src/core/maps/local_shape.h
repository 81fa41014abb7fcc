// The shape of a map around each of its points: the scatter of the points within a radius. Its eigenvalues
// tell a straight wall (one large, one near zero) from a corner, a door jamb or clutter (both large).
// cpd's keypoints are the points whose smaller eigenvalue is largest; the verification weighs points by
// how little they lie on a line (docs/NOTES.md, "Corner-weighted terms").
#pragma once

#include <algorithm>
#include <optional>
#include <vector>

#include "core/types.h"

namespace partslam {

struct LocalShape {
  int neighbours = 0;  ///< points within the radius, the point itself included
  /// smaller eigenvalue of their covariance [m^2] (may be a rounding error below 0 on a line)
  double lambda_min = 0;
  double lambda_max = 0;  ///< larger one [m^2]
  double angle = 0;       ///< direction of the larger one's eigenvector (along a wall) [rad], in (-pi/2, pi/2]

  /// lambda_min / lambda_max: 0 on a straight wall, up to 1 in a corner or clutter; 1 with fewer than three
  /// neighbours (nothing says the point lies on a line).
  double cornerness() const {
    return neighbours < 3 || !(lambda_max > 0) ? 1.0 : std::max(0.0, lambda_min) / lambda_max;
  }
};

/// The shape around every point, over its neighbours within `radius` [m] (points bucketed in cells of that
/// side, so the cost is the number of neighbour pairs). Throws InputError for a radius that is not positive
/// and finite, or a point that is not finite or lies more than 1e15 radii out.
std::vector<LocalShape> local_shapes(const Points2& points, double radius);

/// local_shapes(points, radius)[i].cornerness() for every i.
std::vector<double> cornerness(const Points2& points, double radius);

/// How the map's walls fix a translation: sum w n n^T over the shapes' wall normals n (across each shape's
/// angle), each weighed by how straight a wall it lies on (w = 1 - cornerness) [dimensionless].
Eigen::Matrix2d wall_scatter(const std::vector<LocalShape>& shapes);

/// The direction (unit, the points' frame) in which the walls of a wall_scatter do not fix a translation, if
/// any: its weaker eigenvector, when the eigenvalue is below `ratio` times the stronger one's. A bare
/// corridor's walls all have normals across it: its axis. None when ratio <= 0 or there is no wall.
std::optional<Vec2> unconstrained_direction(const Eigen::Matrix2d& scatter, double ratio);

/// `moved` with its translation along `direction` (a unit vector in the pose's own frame, e.g. a matched scan's
/// or local map's unconstrained_direction, turned into the parent frame by moved.theta) brought back to within
/// `slack` [m] of `start`'s: a match along a bare corridor's axis keeps at most that much of its move there, the
/// rest is the start's (the odometry's prediction). slack 0: start's translation along it.
Pose2 keep_along(const Pose2& moved, const Pose2& start, const Vec2& direction, double slack);


}  // namespace partslam
