// The paper's dMM baseline (Sec. "Map Matching Schemes"): a hypothesise-and-test (RANSAC) maximiser of Eq. 1,
//   v = max_T sum_{x in X} P_Y(T(x)).
// Each iteration draws a minimal sample of two point correspondences (x1, x2 from the query, y1, y2 from the
// map, with |y1 - y2| = |x1 - x2| within length_tolerance and, for canonical maps, a rotation near a multiple
// of 90 deg), hypothesises the rigid T_map_query that maps x1, x2 onto y1, y2 (in the least-squares sense),
// and tests it by counting the query points within inlier_distance of a map point. The best hypothesis is
// kept. Random but seeded: the same inputs and seed give the same result. Unlike match_dmm it is not
// restricted to a discretisation, and it finds the maximum only with luck.
#pragma once

#include <cstdint>
#include <numbers>

#include "core/matching/dmm.h"

namespace partslam {

struct DmmRansacConfig {
  int iterations = 1000;              ///< hypotheses scored
  double inlier_distance = 0.1;       ///< a query point is an inlier within this distance of a map point [m],
                                      ///< tested on a grid: cells within round(d / resolution) cells of a point
  double resolution = kMapResolution;  ///< cell of the inlier grid [m]
  double min_sample_distance = 1.0;   ///< the two query points of a sample are at least this far apart [m]
  double length_tolerance = 0.1;      ///< |x1 - x2| and |y1 - y2| agree within this [m]
  bool canonical = true;              ///< only rotations within angular_window of a multiple of 90 deg
  double angular_window = 3.0 * std::numbers::pi / 180;  ///< [rad], used when canonical
  int max_draws = 50;                 ///< draws allowed per hypothesis before giving up on a sample
  std::uint64_t seed = 1;             ///< random generator seed
};

/// Throws InputError naming the offending field.
void validate(const DmmRansacConfig& config);

/// A map prepared once: its points (correspondence candidates) and its inlier grid.
struct PreparedRansacMap {
  Points2 points;
  OccupancyGrid inlier_grid;
};

PreparedRansacMap prepare_ransac_map(const Points2& points_map, const DmmRansacConfig& config = {});

/// Best hypothesis found; T_map_query maps query points into the map frame. candidates_scored counts the
/// hypotheses tested. An empty query or map, or no consistent sample, gives 0 inliers and the identity.
DmmResult match_dmm_ransac(const Points2& points_query, const PreparedRansacMap& map,
                           const DmmRansacConfig& config = {});

}  // namespace partslam
