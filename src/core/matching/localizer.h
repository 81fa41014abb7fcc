// Global localisation in a building map (docs/DESIGN.md, "Locate"): where does a new local map lie in a map of
// the whole building (a map_server map, a corrected log's map), with no initial pose? The building map is
// prepared once for dMM over its whole area (the dictionary's set-up: every translation at which the query
// overlaps it, dmm_config_for_dictionary), in its canonical (Manhattan) frame so that a canonical local map
// needs four quarter turns plus a small residual; each query is one exact branch-and-bound. How unique the
// answer is comes from a second exact search that skips every pose near the best (match_dmm_elsewhere):
// confidence = best inlier share - best inlier share elsewhere, near 0 for a corridor that fits two places
// or a place the map does not hold.
#pragma once

#include <numbers>

#include "core/matching/dmm.h"

namespace partslam {

struct LocalizerConfig {
  DmmConfig dmm = dmm_config_for_dictionary();  ///< whole-map window; canonical: both maps Manhattan-aligned
  double elsewhere_distance = 2.0;  ///< "elsewhere": the local map's centre at least this far away [m] ...
  double elsewhere_angle = 10.0 * std::numbers::pi / 180;  ///< ... or turned by more than this [rad]
};

/// Throws InputError naming the field.
void validate(const LocalizerConfig& config);

struct Localization {
  Pose2 T_map_query;              ///< the local map's frame in the building map's frame
  int inliers = 0;                ///< query points on occupied cells there (Eq. 1)
  double inlier_fraction = 0.0;   ///< inliers / query points
  double elsewhere_fraction = 0.0;  ///< the best inlier share of a pose elsewhere
  Pose2 T_map_elsewhere;          ///< that pose
  double confidence = 0.0;        ///< inlier_fraction - elsewhere_fraction, in [0, 1]
  double time_ms = 0.0;           ///< both searches [ms]
};

class Localizer {
 public:
  /// map_points: the building map's occupied points in its own frame (occupied_points of a GridMap). Throws
  /// InputError for an empty map, a bad config or a map beyond the dMM limits.
  explicit Localizer(const Points2& map_points, const LocalizerConfig& config = {});

  /// query_points: the local map in its own frame, canonical (Manhattan-aligned, as build_local_map returns it)
  /// when config.dmm.canonical. Throws InputError for an empty query or non-finite points.
  Localization locate(const Points2& query_points) const;

  const LocalizerConfig& config() const { return config_; }
  /// The rotation that took the building map into its canonical frame [rad].
  double alignment_angle() const { return T_canonical_map_.theta; }
  /// Time to prepare the building map [ms].
  double prepare_ms() const { return prepare_ms_; }

 private:
  LocalizerConfig config_;
  Pose2 T_canonical_map_;
  PreparedMap map_;
  double prepare_ms_ = 0.0;
};

}  // namespace partslam
