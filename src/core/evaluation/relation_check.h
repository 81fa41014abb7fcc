// Independent check of the ground truth (docs/DESIGN.md, "Tasks"): the Freiburg .relations files (Kuemmerle et al.
// 2009) give true relative poses between scans of the raw log. A relevant pair of submaps is *confirmed* when a
// relation links a scan of one map to a scan of the other and agrees with the relative pose of those scans in
// the log the submaps were built from (so the centroid offset of the two maps is right too).
// Corrected logs re-time their scans, so scans are first associated with the raw log's by content.
#pragma once

#include <optional>

#include "core/maps/submap.h"
#include "core/evaluation/tasks.h"

namespace partslam {

struct Relation {
  double t1 = 0.0;  ///< timestamp of the first scan (raw log) [s]
  double t2 = 0.0;  ///< timestamp of the second scan (raw log) [s]
  Pose2 T_1_2;      ///< pose of scan 2 in the frame of scan 1 [m, rad]
};
using Relations = std::vector<Relation>;

/// For each scan of `scans`, the index of the same scan in `reference` (same beams, found in order), or
/// nullopt. Scans match when they have the same valid beams and their endpoints differ by < 2 cm on average.
std::vector<std::optional<std::size_t>> associate_scans(const Scans& scans, const Scans& reference);

struct RelationCheckConfig {
  PoseTolerance agreement{0.3, 0.1};  ///< relation vs log relative pose
};

struct RelationCheck {
  std::size_t relevant_pairs = 0;   ///< pairs checked
  std::size_t with_relation = 0;    ///< pairs with at least one relation between their scans
  std::size_t confirmed = 0;        ///< pairs with at least one relation that agrees with the log
  std::size_t associated_scans = 0; ///< scans of the submaps' log found in the raw log
};

/// scans: the log the submaps were built from (Submap::scan_timestamps refer to it); reference: the raw log
/// the relations refer to.
RelationCheck check_relevant_pairs(const Submaps& maps, const std::vector<RelevantPair>& pairs, const Scans& scans,
                                   const Scans& reference, const Relations& relations,
                                   const RelationCheckConfig& config = {});

}  // namespace partslam
