// Scan-to-map matching for the local front end (docs/NOTES.md "Front end"): a scan's pose
// against a likelihood field of nearby map points, in two steps as in Cartographer's local trajectory builder:
//  1. correlative search: every pose of a window around the prediction on a grid of two cells and of the
//     rotation that moves the farthest point by two cells, then the one-cell grid around the best, scored by
//     the mean field value at (up to 100 of) the scan's points; the best pose seeds
//  2. Gauss-Newton refinement of sum_i (1 - M(T p_i))^2 on the bilinearly interpolated field (Hector SLAM's
//     cost), kept when it scores at least as well as the correlative pose.
// The field is M(q) = exp(-d(q)^2 / (2 sigma^2)), d = distance to the nearest map point, cut at 3 sigma.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/types.h"

namespace partslam {

struct ScanMatcherConfig {
  double resolution = 0.05;      ///< likelihood field cell [m]
  double sigma = 0.1;            ///< likelihood field width [m]
  double linear_window = 0.3;    ///< correlative search half-width in x and y [m]
  double angular_window = 0.2;   ///< correlative search half-width in rotation [rad]
  int max_iterations = 20;       ///< Gauss-Newton iterations
  int num_threads = 1;           ///< threads of the correlative search (the result does not depend on it)
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const ScanMatcherConfig& config);

/// M(q) on a grid covering the given points grown by 3 sigma. Empty (every value 0) for no points.
class LikelihoodField {
 public:
  LikelihoodField() = default;
  /// Throws InputError when the grid would exceed 2^26 cells (map points spread over more than ~400 m at the
  /// default 0.05 m cells).
  LikelihoodField(const Points2& points, double resolution, double sigma);

  /// Value at the cell holding q; 0 outside the grid.
  float at(const Vec2& q) const;
  /// The cell holding q (may lie outside the grid), and a cell's value (0 outside the grid).
  Eigen::Vector2i cell_of(const Vec2& q) const;
  float cell_value(int x, int y) const;
  /// The sums of cell_value(c.x + sx step, c.y + sy step) over `cells`, each in the cells' order, for every
  /// shift sx, sy in [-shifts, shifts]: out[(sy + shifts) (2 shifts + 1) + sx + shifts]. The cells are the outer
  /// loop (one cell's window of the field is read at once), yet each sum takes its additions in the cells' order,
  /// so every sum is the same double as adding that shift's cell values one by one.
  void shifted_sums(std::span<const Eigen::Vector2i> cells, int step, int shifts, std::vector<double>& out) const;
  /// Bilinear value at q and its gradient [1/m]; 0 outside the grid.
  double interpolate(const Vec2& q, Vec2* gradient) const;
  double resolution() const { return resolution_; }
  bool empty() const { return values_.empty(); }

 private:
  double resolution_ = 0.05;
  Vec2 origin_ = Vec2::Zero();  // world position of cell (0, 0)'s centre
  int width_ = 0, height_ = 0;
  std::vector<float> values_;   // row-major, y rows
};

struct ScanMatch {
  Pose2 pose;          ///< refined pose of the scan in the field's frame
  double score = 0.0;  ///< mean field value at the scan's points at `pose`, in [0, 1]
};

/// Matches scan points (in the scan's own frame) against the field around `prediction`. A scan without
/// points or an empty field returns the prediction with score 0.
ScanMatch match_scan(const LikelihoodField& field, const Points2& scan_points, const Pose2& prediction,
                     const ScanMatcherConfig& config = {});

}  // namespace partslam
