// Submaps (docs/DESIGN.md, "Submap"): anchored at scan i, the points of all scans j with travel
// s_i <= s_j < s_i + L, downsampled to one point per occupied cell, cropped to a square around their
// centroid, expressed relative to that centroid and rotated into the canonical (Manhattan) frame.
#pragma once

#include <cstdint>

#include "core/maps/scan.h"

namespace partslam {

struct SubmapConfig {
  double window_length = 2.0;  ///< L: travel covered by one submap [m]
  double spacing = 0.5;        ///< travel between consecutive anchors [m]
  double resolution = kMapResolution;  ///< downsampling cell [m]
  double crop_size = kCropSize;  ///< side of the square crop around the centroid [m]
  double max_range = kDefaultMaxRange;  ///< beam endpoints farther from the laser are dropped [m]
  int min_points = 20;         ///< submaps with fewer points are dropped
  bool align = true;           ///< rotate into the canonical Manhattan frame
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const SubmapConfig& config);

struct Submap {
  std::int64_t id = -1;          ///< index within its dataset (database id once stored)
  std::int64_t anchor_scan = 0;  ///< index of the anchor scan in the scan stream
  double anchor_timestamp = 0;   ///< timestamp of the anchor scan [s]
  double travel = 0;             ///< s_i, distance travelled up to the anchor scan [m]
  double alignment_angle = 0;    ///< rotation applied to enter the canonical frame [rad], in [0, pi/2)
  Pose2 T_world_map;             ///< map frame (centroid, canonical axes) in the log's world frame
  Points2 points;                ///< points in the map frame [m]
  std::vector<double> scan_timestamps;  ///< timestamps of the scans that built it (relations check)
  /// Where the laser was while the map was recorded, in the map frame: the scan origins thinned to one per
  /// kOriginSpacing of travel. The free space the beams crossed is cast from them (core/matching/verification.h);
  /// empty for a map made from bare points (no beams known).
  Points2 origins;
};

/// Spacing of a submap's stored laser origins [m].
inline constexpr double kOriginSpacing = 0.25;

using Submaps = std::vector<Submap>;

/// Cumulative travel distance of the laser along the scan stream [m].
std::vector<double> travel_distances(const Scans& scans);

/// Builds all submaps of a scan stream (docs/DESIGN.md, "Submap").
Submaps build_submaps(const Scans& scans, const SubmapConfig& config = {});

/// A query's local map, built exactly as build_submaps builds a stored one, over the scans whose travel along
/// the log lies in [from, to) [m] (not anchored on the spacing grid). Throws InputError when no scan lies there or
/// fewer than min_points remain.
Submap build_local_map(const Scans& scans, double from, double to, const SubmapConfig& config = {});

/// A local map from points in any frame (a point file, another mapper's output), shaped as submaps are: one
/// point per cell, centred, canonical, cropped; T_world_map places it in the points' frame. Laser origins in
/// the points' frame (a point file's, partslam export) become the map's origins: its free space can then be
/// verified. Throws InputError for non-finite points or origins, or fewer than min_points cells.
Submap local_map_from_points(const Points2& points, const SubmapConfig& config = {},
                             const Points2& origins = {});

/// One point per occupied cell of the given size (the mean of the points that fall in it), in a fixed order.
Points2 voxel_downsample(const Points2& points, double resolution);

}  // namespace partslam
