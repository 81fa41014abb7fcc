// Reader for the relation files of the Freiburg SLAM benchmark (Kuemmerle et al., "On measuring the
// accuracy of SLAM algorithms", 2009): one relation per line, "t1 t2 x y z roll pitch yaw", the true
// relative pose of the scan at time t2 seen from the scan at time t1 (timestamps = FLASER ipc_timestamp
// of the raw log). In 2D only x, y and yaw are kept; z, roll and pitch must still be numbers. Comments
// (#) and blank lines are skipped; anything else malformed throws InputError "<file>:<line>: <field>: ...".
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/evaluation/relation_check.h"
#include "core/evaluation/trajectory_check.h"
#include "core/maps/scan.h"
#include "core/types.h"

namespace partslam::io {

/// Relations are partslam::Relation (core/evaluation/relation_check.h).
using partslam::Relation;
using partslam::Relations;

/// Reads a .relations file (plain or gzip); throws InputError on a missing, malformed or empty file.
Relations read_relations(const std::filesystem::path& path);

/// Index of the scan whose timestamp is nearest to timestamp, if within tolerance [s]; scans need not
/// be sorted. Relation timestamps equal the raw logs' FLASER timestamps to the printed microsecond.
std::optional<std::size_t> find_scan_by_timestamp(const Scans& scans, double timestamp,
                                                  double tolerance = 1e-4);

/// Relation errors as JSON with their units in the keys: translation_m and rotation_deg (mean, std), relations,
/// missing; without a matched relation, no figure at all (a note says so).
nlohmann::json relations_error_json(const RelationsError& e);

}  // namespace partslam::io
