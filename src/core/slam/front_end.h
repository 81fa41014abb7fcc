// The local front end (docs/NOTES.md "Front end"): turns a raw log's scans, whose poses are
// drifting odometry, into a locally consistent trajectory by matching each scan against a local map of the
// last few key scans (scan_matcher.h), seeded by the odometry increment since the previous scan:
//   prediction_i = T_world_laser(i-1) * odom(i-1)^-1 * odom(i),   T_world_laser(i) = match(local map, scan i).
// A scan becomes a key scan (and joins the local map, oldest key scan out) after key_translation of travel or
// key_rotation of turn since the last key scan, as Cartographer's motion filter does. Where the front end's own
// last step, continued at the same velocity, predicts a pose far from the odometry's (odometry that stalls and
// catches up), the scan is matched from that prediction too, and that match kept when it scores clearly better
// (FrontEndConfig::second_prediction, second_margin); a match that still scores poorly is searched for again over
// every heading (FrontEndConfig::wide_score: a heading lost between two scans). A match scoring below
// min_score is rejected and the prediction kept (counted); a scan whose surfaces leave one direction of translation
// unconstrained (a bare corridor) keeps the prediction along it (counted). Scans whose timestamp goes backwards are dropped
// (counted). The first scan keeps its odometry pose, so the trajectory lives in the odometry frame. Scans that turn
// against the odometry (a laser mounted upside down) are matched again mirrored (FrontEndConfig::mirror_check).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/maps/scan.h"
#include "core/parallel.h"
#include "core/slam/front_end_config.h"
#include "core/matching/scan_matcher.h"

namespace partslam {

/// A step on which the odometry turns at least this much counts towards FrontEndStats::turn_slope [rad].
inline constexpr double kTurningStep = 0.02;
/// Fewer turning steps than this say nothing about which way the scans turn (FrontEndStats::turns_against_odometry).
inline constexpr std::size_t kMinTurningSteps = 20;

/// A kept match scoring below this fits its local map poorly (FrontEndStats::weak_matches).
inline constexpr double kWeakMatch = 0.4;

struct FrontEndStats {
  std::size_t scans = 0;            ///< scans in the result
  std::size_t rejected = 0;         ///< scans whose match scored below min_score (prediction kept)
  std::size_t degenerate = 0;       ///< matched scans that kept the prediction along an unconstrained direction
  /// matched scans whose move along a half-constrained direction was bounded (FrontEndConfig::half_constrained_ratio)
  std::size_t half_constrained = 0;
  /// Of the degenerate scans, those whose prediction along the corridor was the odometry's step times its learned
  /// scale (FrontEndConfig::scale_memory), and that scale at the end of the log (1 when none was learned).
  std::size_t scaled = 0;
  double odometry_scale = 1.0;
  std::size_t heading_jumps = 0;    ///< scans whose turn disagrees with the odometry's by more than jump_turn
  std::vector<std::size_t> jump_scans;  ///< the first 100 of them (indices into the result's scans)
  std::size_t time_reversals = 0;   ///< scans dropped because their timestamp went backwards
  std::size_t second_predictions = 0;  ///< scans also matched from the constant-velocity prediction
  std::size_t velocity_kept = 0;    ///< of those, scans whose constant-velocity match scored better (kept)
  std::size_t wide_searches = 0;    ///< scans matched again over every heading (their match scored below wide_score)
  std::size_t wide_kept = 0;        ///< of those, scans whose wide match scored better (kept)
  bool odometry_moves = false;      ///< false when the odometry never moves (no odometry in the log)
  /// Steps between consecutive scans on which the odometry turns at least kTurningStep, and over them the sums
  /// of the front end's turn times the odometry's and of the odometry's squared: turn_slope() is the least-squares
  /// slope of the scans' turns on the wheels'. About 1 when they agree; negative when the scans turn against the
  /// wheels (a laser mounted upside down, read as upright: its scans are a mirror image).
  std::size_t turning_steps = 0;
  double turn_products = 0.0, odometry_turn_squares = 0.0;
  double turn_slope() const { return odometry_turn_squares > 0 ? turn_products / odometry_turn_squares : 0.0; }
  /// The scans turn against the wheels: a negative turn_slope over at least kMinTurningSteps.
  bool turns_against_odometry() const { return turning_steps >= kMinTurningSteps && turn_slope() < 0; }
  /// The scans were matched mirrored (FrontEndConfig::mirror_check): the result's points are the mirror images of
  /// the log's, and unmirrored_turn_slope is the slope of the first run, as read.
  bool mirrored = false;
  double unmirrored_turn_slope = 0.0;
  double mean_score = 0.0;          ///< over matched scans
  /// The weakest match kept (its score, the scan's index in the result; 1 and 0 when none was kept), and how many
  /// kept matches scored below kWeakMatch: the steps where the chain rests on a poor fit.
  double weakest_score = 1.0;
  std::size_t weakest_scan = 0;
  std::size_t weak_matches = 0;
  double seconds = 0.0;             ///< time spent
  double log_seconds = 0.0;         ///< time the log covers (last - first timestamp)
};

struct FrontEndResult {
  /// The input scans in order, minus dropped ones, T_world_laser = the scan-matched pose (points mirrored when
  /// stats.mirrored)
  Scans scans;
  FrontEndStats stats;
};

/// What a mirrored run did, for a warning ("the scans turned against the odometry (slope ...); read mirrored, ...");
/// empty when the scans were not mirrored.
std::string mirrored_description(const FrontEndStats& stats);

/// The points of a scan the front end matches: its beam endpoints within max_range, one per point_resolution cell
/// (in the laser's frame).
Points2 matching_points(const Scan& scan, const FrontEndConfig& config);

/// Runs the front end over a log's scans (serial: each scan depends on the previous ones).
FrontEndResult scan_match_log(const Scans& raw, const FrontEndConfig& config = {},
                              const Progress& progress = {});

}  // namespace partslam
