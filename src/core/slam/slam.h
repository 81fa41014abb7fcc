// The whole chain for a raw log, turned onto its walls' direction first (log_wall_axis, core/maps/manhattan.h) and
// its result back: front end (front_end.h) -> submaps on the scan-matched trajectory -> loop closures among them
// (loop_closure.h), the confident ones refined on the scans (closure_refinement.h) -> a pose graph over the submap
// frames (consecutive submaps joined by the front end's relative poses, accepted closures with a robust loss, those
// that disagree with the solution set aside, and a verdict: back_end.h) -> every scan's pose corrected by its
// submaps' corrections, interpolated along the travel between the two anchors around it -> every scan refined on
// its neighbours in time (neighbour_refinement.h) -> the map checked against itself (map_check.h).
#pragma once

#include <functional>
#include <string>

#include "core/maps/submap.h"
#include "core/slam/back_end.h"
#include "core/slam/closure_refinement.h"
#include "core/slam/front_end_agreement.h"
#include "core/slam/neighbour_refinement.h"
#include "core/slam/front_end.h"
#include "core/slam/loop_closure.h"
#include "core/slam/map_check.h"
#include "core/slam/pose_graph.h"

namespace partslam {

struct SlamConfig {
  FrontEndConfig front_end;
  SubmapConfig submaps;
  LoopClosureConfig loops;
  double min_confidence = 0.2;  ///< closures at least this confident are offered to the back end
  ClosureRefinementConfig refinement;  ///< those closures' poses refined on the scans (closure_refinement.h)
  BackEndConfig back_end;       ///< the graph's weights, which closures it keeps, the verdict (back_end.h)
  MapCheckConfig map_check;     ///< the finished map against itself (map_check.h): a failed check is "doubtful"
  /// A map whose front end kept the odometry's position along a bare corridor (FrontEndStats::degenerate: the
  /// scans fix no position along it) on more than this share of its matched scans is "doubtful": its lengths
  /// there are the odometry's, which nothing in the laser data checks (a ring of bare corridors with harsh
  /// odometry came out 0.157 m off, "closed"; docs/NOTES.md, "SLAM on real raw logs"). 1 turns it off.
  double max_degenerate_share = 0.4;
  /// The corrected scans refined once more against their neighbours in time (neighbour_refinement.h).
  NeighbourRefinementConfig neighbours;
  /// The log is turned onto its walls' direction (log_wall_axis, core/maps/manhattan.h) before anything runs,
  /// and every pose of the result turned back: the grids then lie along the walls whatever the odometry frame's
  /// heading (docs/NOTES.md, "The bench's resolution").
  bool align_to_walls = true;
  /// The log scan-matched a second time with another fine field, the two paths compared over windows of travel
  /// (front_end_agreement.h): where they part beyond the limits the map is "doubtful". It runs beside the first
  /// front end when threads allow (front_end.matcher.num_threads > 1 gives it one of them), else after it.
  SecondOpinionConfig second_opinion;
};

/// Every part's validate, the failing field named by its path ("slam config: back_end.max_rounds must be ...").
void validate(const SlamConfig& config);

struct SlamResult {
  Scans scans;                        ///< the log's scans with corrected poses (scans the front end dropped excluded)
  std::vector<Pose2> front_end_poses; ///< the same scans' poses from the front end, before loop closing
  Submaps submaps;                    ///< with optimised frames
  std::vector<Pose2> stored_frames;   ///< the submaps' frames before optimisation (on the front end's poses)
  std::vector<LoopClosure> closures;  ///< every hypothesis
  std::size_t accepted = 0;           ///< closures offered to the back end (confident enough)
  std::vector<LoopClosure> offered;   ///< those closures, in the order of back_end.used
  FrontEndStats front_end;
  BackEndResult back_end;             ///< which closures were used, the graph's summary, the verdict
  MapCheck map_check;                 ///< of the corrected scans (map_check.h)
  MapCheck front_end_map_check;       ///< of the front end's scans, for comparison
  /// The walls' direction in the log's frame, by which the log was turned before mapping (log_wall_axis) [rad];
  /// 0 with SlamConfig::align_to_walls off.
  double wall_axis = 0;
  NeighbourRefinementStats neighbours;  ///< what the last stage moved (neighbour_refinement.h)
  /// The second front end's path against the first's (SlamConfig::second_opinion; not judged when it is off).
  FrontEndAgreement second_opinion;
  double second_opinion_s = 0;  ///< the second front end's own time (beside the first's when threads allow) [s]
  double front_end_s = 0, loops_s = 0, refine_s = 0, graph_s = 0, neighbours_s = 0, check_s = 0;
};

/// Called on the accepted closures before they join the graph (a bench injects wrong ones here).
using ClosureHook = std::function<void(const Submaps& maps, std::vector<LoopClosure>& accepted)>;

/// Throws InputError when no submap can be built or a setting is out of range.
SlamResult run_slam(const Scans& raw, const SlamConfig& config = {}, const Progress& progress = {},
                    const ClosureHook& hook = {});

/// Moves every scan by the correction (T_new * T_old^-1, in the world frame) of the submaps around it,
/// interpolated along the travel between their anchors; scans before the first anchor and after the last take
/// the nearest one's. `old_maps` and `new_maps` are the same submaps before and after optimisation.
Scans corrected_scans(const Scans& scans, const Submaps& old_maps, const Submaps& new_maps);

/// The share of the scans after the first on which the front end kept the prediction's position along a bare
/// corridor (FrontEndStats::degenerate / (scans - 1)); 0 for fewer than two scans.
double degenerate_share(const FrontEndStats& stats);

/// What the verdict checked, in one sentence: how many closures agreed, how far the closures bent the front end's
/// trajectory against its limit, how many revisiting beams cross a wall another visit saw against its limit, and
/// how far a second front end parted from the first.
std::string verdict_checks(const SlamResult& result, const SlamConfig& config);

}  // namespace partslam
