// The dictionary map (docs/DESIGN.md, "Dictionary map"): a whole-building map of another dataset — every scan of a
// corrected log in the world frame, one point per occupied cell, Manhattan-aligned about its centroid. Parts
// of every map are described against it (CPD, Eq. 2).
#pragma once

#include <string>

#include "core/maps/scan.h"

namespace partslam {

struct DictionaryConfig {
  double resolution = kMapResolution;  ///< downsampling cell [m]
  bool align = true;        ///< rotate into the canonical Manhattan frame
  int min_points = 100;     ///< fewer points than this is an error (not a building)
  double max_range = kDefaultMaxRange;  ///< beam endpoints farther from the laser are dropped [m]
};

struct Dictionary {
  std::string name;              ///< unique within a database, non-empty
  std::string source;            ///< log it was built from
  double resolution = kMapResolution;  ///< cell the points were downsampled to [m]
  double alignment_angle = 0;    ///< rotation applied about the centroid [rad]
  Pose2 T_world_dict;            ///< dictionary frame in the source log's world frame
  Points2 points;                ///< dictionary frame [m]
  std::string metadata = "{}";   ///< free JSON object (builder parameters)
};

/// Builds the dictionary from a scan stream; throws InputError when it has too few points.
Dictionary build_dictionary(const std::string& name, const Scans& scans, const DictionaryConfig& config = {});

/// The same from a building's points in its world frame (a map_server map's occupied cells); max_range unused.
Dictionary build_dictionary(const std::string& name, const Points2& points_world, const DictionaryConfig& config = {});

}  // namespace partslam
