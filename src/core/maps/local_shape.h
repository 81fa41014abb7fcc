// The shape of a map around each of its points: the scatter of the points within a radius. Its eigenvalues
// tell a straight wall (one large, one near zero) from a corner, a door jamb or clutter (both large).
// cpd's keypoints are the points whose smaller eigenvalue is largest; the verification weighs points by
// how little they lie on a line (docs/NOTES.md, "Corner-weighted terms").
#pragma once

#include <algorithm>
#include <vector>

#include "core/types.h"

namespace partslam {

struct LocalShape {
  int neighbours = 0;  ///< points within the radius, the point itself included
  /// smaller eigenvalue of their covariance [m^2] (may be a rounding error below 0 on a line)
  double lambda_min = 0;
  double lambda_max = 0;  ///< larger one [m^2]

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

}  // namespace partslam
