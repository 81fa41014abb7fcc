// The settings of the local front end (front_end.h; its scan matcher's are core/matching/scan_matcher.h), apart from the
// code that runs them: what a caller stores or validates (the map database keeps a dataset's front-end settings,
// io/store/map_database.h) needs only these plain structs, not the front end's interface.
#pragma once

#include "core/matching/scan_matcher.h"

namespace partslam {

/// The odometry's learned scale (FrontEndConfig::scale_memory) is used once this much odometry travel on scans that
/// fix both directions was seen [m], and is clamped to [1 / kMaxOdometryScale, kMaxOdometryScale].
inline constexpr double kMinScaleTravel = 5.0;
inline constexpr double kMaxOdometryScale = 1.25;
/// The scale is measured over stretches of this much odometry travel [m]; a stretch whose match lies farther than
/// kScaleOutlier plus (kMaxOdometryScale - 1) times its length from the odometry's is not counted (a slip) [m].
inline constexpr double kScaleStretch = 0.5;
inline constexpr double kScaleOutlier = 0.05;

struct FrontEndConfig {
  ScanMatcherConfig matcher;
  /// The match is refined once more (Gauss-Newton, no search) on a second field of this sigma: the first field's
  /// wide basin finds the pose, the narrow one places it (docs/NOTES.md, "SLAM bench"). 0 turns it off [m].
  double fine_sigma = 0.05;
  double max_range = 40.0;         ///< beam endpoints farther from the laser are not matched [m] (20 m: see NOTES)
  double point_resolution = 0.05;  ///< scan and local-map points are downsampled to one per cell [m]
  int local_map_scans = 30;        ///< key scans in the local map
  double key_translation = 0.2;    ///< travel that makes a key scan [m]
  double key_rotation = 0.1;       ///< turn that makes a key scan [rad]
  double min_score = 0.25;         ///< matches scoring lower are rejected (the prediction is kept)
  /// Degeneracy: when the scan's surfaces leave one direction of translation unconstrained (the weaker eigenvalue
  /// of sum n n^T over its surface normals below this share of the stronger: a bare corridor's axis), the match
  /// keeps the prediction's translation along it (counted; not when the log's odometry never moves). 0 turns it off.
  double degenerate_ratio = 0.1;
  /// Half-constrained scans: where the weaker eigenvalue is below this share of the stronger but not below
  /// degenerate_ratio (a corridor with a few door frames across it), the match's move from the odometry's
  /// prediction along the weak direction is bounded by half_constrained_slack times the root mean square of the
  /// moves on scans that fix both directions (an exponential mean over about the last 50): the match may correct
  /// the odometry there by as much as the odometry has lately been wrong, not slide further along the corridor
  /// (counted; only where the prediction is the odometry's own step, not a stall, the step after one or another
  /// prediction kept, and once a well-constrained scan was seen). Off by default (0): with 0.3 and slack 2 it
  /// halves an 8 m laser's error on aces and meets aces's floor, but costs intel and fr101 about a millimetre
  /// and lets a front end slide back less after stalled odometry (docs/NOTES.md, "Real logs degraded").
  double half_constrained_ratio = 0.0;
  double half_constrained_slack = 2.0;
  /// The odometry's scale, learned as the log is read: on scans whose surfaces fix both directions of translation
  /// (the weaker eigenvalue at least scale_ratio of the stronger) the least-squares ratio of the match's step to
  /// the odometry's (its own step: not a stall or the step after one), the older steps forgotten over scale_memory
  /// of travel. Where a scan keeps the prediction along a bare corridor's axis, the prediction is the odometry's
  /// step times that scale (clamped to [1 / kMaxOdometryScale, kMaxOdometryScale], once kMinScaleTravel of such
  /// steps were seen): wheels 5 % short no longer shorten every corridor by 5 %. 0 turns it off [m].
  double scale_memory = 50.0;
  double scale_ratio = 0.3;
  /// Jump detector: a scan whose matched turn since the previous scan differs from the odometry's by more than
  /// this is counted as a heading jump (kept; reported, as a front end losing its heading shows) [rad].
  double jump_turn = 0.1;
  /// Odometry that stalls and catches up (a pose repeated for a few scans while the robot moves, then one
  /// increment of all the motion since: MIT CSAIL's raw log turns 1.2 rad while its odometry stands still, then
  /// jumps 1.5 rad in one scan) puts the prediction outside the search window. When the front end's own motion
  /// over the last step, carried forward at the same velocity, predicts a pose more than this share of the search
  /// window away from the odometry's prediction, the scan is matched from both, and the second match is kept when
  /// it scores at least second_margin higher (counted). 0 turns it off.
  double second_prediction = 0.25;
  double second_margin = 0.2;
  /// A lost heading: where the best match from either prediction scores below wide_score (a prediction a turn
  /// outside the search window: odometry stamped out of step with the scans, a gap in the log), the scan is matched
  /// again over every heading and +- wide_window of translation around the odometry's prediction, and that match
  /// kept when it scores at least wide_margin higher (counted; docs/NOTES.md, "A heading lost between two scans":
  /// the right ones scored 0.40-0.77 higher, a square building's quarter-turn alias 0.23 higher where the scan saw
  /// a new room). 0 turns it off.
  double wide_score = 0.5;
  double wide_window = 0.5;  ///< [m]
  double wide_margin = 0.3;
  /// A laser mounted upside down and read as upright gives scans that are a mirror image of the place: they turn
  /// against the wheels (FrontEndStats::turn_slope is about -1 where real logs give 0.85-1.01). When the slope
  /// over at least kMinTurningSteps turning steps is negative, the log is matched again with every scan's points
  /// mirrored (y -> -y), and that run is kept when its scans turn with the wheels (FrontEndStats::mirrored).
  bool mirror_check = true;
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const FrontEndConfig& config);

}  // namespace partslam
