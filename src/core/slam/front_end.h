// The local front end (docs/NOTES.md "Front end"): turns a raw log's scans, whose poses are
// drifting odometry, into a locally consistent trajectory by matching each scan against a local map of the
// last few key scans (scan_matcher.h), seeded by the odometry increment since the previous scan:
//   prediction_i = T_world_laser(i-1) * odom(i-1)^-1 * odom(i),   T_world_laser(i) = match(local map, scan i).
// A scan becomes a key scan (and joins the local map, oldest key scan out) after key_translation of travel or
// key_rotation of turn since the last key scan, as Cartographer's motion filter does. Where the front end's own
// last step, continued at the same velocity, predicts a pose far from the odometry's (odometry that stalls and
// catches up), the scan is matched from that prediction too, and that match kept when it scores clearly better
// (FrontEndConfig::second_prediction, second_margin). A match scoring below
// min_score is rejected and the prediction kept (counted); a scan whose surfaces leave one direction of translation
// unconstrained (a bare corridor) keeps the prediction along it (counted). Scans whose timestamp goes backwards are dropped
// (counted). The first scan keeps its odometry pose, so the trajectory lives in the odometry frame.
#pragma once

#include <cstddef>
#include <vector>

#include "core/maps/scan.h"
#include "core/parallel.h"
#include "core/slam/front_end_config.h"
#include "core/matching/scan_matcher.h"

namespace partslam {

struct FrontEndStats {
  std::size_t scans = 0;            ///< scans in the result
  std::size_t rejected = 0;         ///< scans whose match scored below min_score (prediction kept)
  std::size_t degenerate = 0;       ///< matched scans that kept the prediction along an unconstrained direction
  std::size_t heading_jumps = 0;    ///< scans whose turn disagrees with the odometry's by more than jump_turn
  std::vector<std::size_t> jump_scans;  ///< the first 100 of them (indices into the result's scans)
  std::size_t time_reversals = 0;   ///< scans dropped because their timestamp went backwards
  std::size_t second_predictions = 0;  ///< scans also matched from the constant-velocity prediction
  std::size_t velocity_kept = 0;    ///< of those, scans whose constant-velocity match scored better (kept)
  bool odometry_moves = false;      ///< false when the odometry never moves (no odometry in the log)
  double mean_score = 0.0;          ///< over matched scans
  double seconds = 0.0;             ///< time spent
  double log_seconds = 0.0;         ///< time the log covers (last - first timestamp)
};

struct FrontEndResult {
  Scans scans;  ///< the input scans in order, minus dropped ones, T_world_laser = the scan-matched pose
  FrontEndStats stats;
};

/// Runs the front end over a log's scans (serial: each scan depends on the previous ones).
FrontEndResult scan_match_log(const Scans& raw, const FrontEndConfig& config = {},
                              const Progress& progress = {});

}  // namespace partslam
