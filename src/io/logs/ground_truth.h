// Ground truth for a log whose own poses are not it (a raw log's drifting odometry), from either source the
// benchmark logs come with: a corrected twin of the same run (a CARMEN log; its scans associated with the log's
// by content, core/evaluation/relation_check.h) or a Freiburg .relations file (a reference trajectory solved
// from the relations, core/evaluation/trajectory_check.h). The file name decides: *.relations is a relations
// file, anything else a log.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/maps/scan.h"

namespace partslam::io {

struct GroundTruth {
  Scans reference;  ///< reference poses (T_world_laser) of the scans that have one
  std::vector<std::optional<std::size_t>> index;  ///< per scan of the log: its reference scan, or nullopt
  std::string description;  ///< e.g. "corrected twin X: 4741 of 4934 scans associated"
};

/// Throws InputError naming the file when it cannot be read or matches no scan of `scans`.
GroundTruth load_ground_truth(const std::string& path, const Scans& scans);

}  // namespace partslam::io
