// Manhattan alignment (docs/DESIGN.md, "Canonical frame"; the paper's ref. [18]): the rotation in [0, pi/2)
// that minimises the summed Shannon entropy of the x and y point histograms. Walls of a Manhattan building
// then run along the axes, so two maps of one place differ by a multiple of 90 degrees plus a small residual.
#pragma once

#include <vector>

#include "core/maps/scan.h"
#include "core/types.h"

namespace partslam {

struct ManhattanConfig {
  double bin_size = kMapResolution;                   ///< histogram bin [m]
  double coarse_step = 1.0 * std::numbers::pi / 180;  ///< first sweep over [0, pi/2) [rad]
  double fine_step = 0.05 * std::numbers::pi / 180;   ///< refinement step around the best coarse angle [rad]
};

/// Summed entropy of the x and y histograms of the points rotated by angle [nats].
double axis_entropy(const Points2& points, double angle, double bin_size);

/// The angle in [0, pi/2) by which to rotate the points (about the origin) into the canonical frame.
double manhattan_angle(const Points2& points, const ManhattanConfig& config = {});

struct WallDirectionConfig {
  /// Points are grouped in square cells of this size [m]; a cell of at least min_points points whose second
  /// principal variance is at most max_flatness times the first is a wall piece, weighted by its length.
  double cell = 0.5;
  int min_points = 6;
  double max_flatness = 0.05;
  /// A direction's share: the wall length within +- window of it. A direction is kept when its share is a
  /// peak of at least min_share and min_length metres of wall, min_separation away from every multiple of 45
  /// deg and from the directions kept before it; at most max_directions, the strongest first. The length
  /// does not shrink as the rest of the building is mapped (a share does), the share keeps a large map's
  /// scattered pieces out.
  double window = 3.0 * std::numbers::pi / 180;
  double min_share = 0.03;
  double min_length = 10.0;
  double min_separation = 6.0 * std::numbers::pi / 180;
  int max_directions = 2;
};

/// The directions of walls that run neither along the axes nor the diagonals of the points' frame (the
/// canonical frame: a building's wings built at another angle), modulo 90 deg, in [-pi/4, pi/4] [rad],
/// strongest first. Empty for a Manhattan building.
std::vector<double> wall_directions(const Points2& points, const WallDirectionConfig& config = {});

/// The direction of a log's walls in its world frame, modulo a quarter turn, in (-pi/4, pi/4]: the circular mean
/// of four times the world angles of the surface normals the first `first` scans see (for_each_surface_tangent,
/// core/maps/scan.h, turned by the scan's logged heading), divided by four;
/// 0 when no surface is seen or the angles cancel. Unlike manhattan_angle it reads a raw log before any map
/// exists: each normal comes from one scan, so the odometry's drift between scans moves it only by the heading's
/// error. slam turns a log by minus this before mapping it (SlamConfig::align_to_walls): its grids, laid along
/// the world's axes, rasterise walls along them best (docs/NOTES.md, "The bench's resolution").
double log_wall_axis(const Scans& scans, std::size_t first = 300);

}  // namespace partslam
