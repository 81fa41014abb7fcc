// Local consistency of an estimated trajectory against a reference (how the front end is judged): for
// every submap window of the estimate (anchor every `spacing` of travel, scans within `window_length` of
// travel after it, as submaps are built), each scan's pose relative to the anchor is compared with the same
// relative pose in the reference, and the error is measured where it matters: the displacement of that
// scan's beam endpoints (within max_range) between the two relative poses. Scans missing from the reference
// (a corrected subset) are skipped. The median of all displacements is what "a submap from the raw log matches
// the corrected one to d cm after aligning each pair by its anchor pose" means.
#pragma once

#include <optional>
#include <vector>

#include "core/maps/scan.h"
#include "core/evaluation/relation_check.h"
#include "core/maps/submap.h"

namespace partslam {

struct ConsistencyConfig {
  double window_length = 2.0;  ///< travel a window covers [m] (SubmapConfig::window_length)
  double spacing = 0.5;        ///< travel between anchors [m] (SubmapConfig::spacing)
  double max_range = kDefaultMaxRange;  ///< beam endpoints farther from the laser are not counted [m]
};

struct Consistency {
  std::size_t windows = 0;  ///< windows with an anchor found in the reference
  std::size_t points = 0;   ///< displacements measured
  double median = 0.0;      ///< median displacement [m]
  double p90 = 0.0;         ///< 90th percentile [m]
  double max = 0.0;         ///< largest [m]
};

/// `reference_index[i]`: the index in `reference` of estimate scan i, or nullopt (associate_scans).
Consistency local_consistency(const Scans& estimate, const Scans& reference,
                              const std::vector<std::optional<std::size_t>>& reference_index,
                              const ConsistencyConfig& config = {});

/// Ground truth for submaps built on an estimated trajectory (a raw log's): each submap's frame
/// in the reference's world frame, T_ref(j) * T_est(j)^-1 * T_world_map, through a scan j of the submap
/// (scans anchor_scan .. anchor_scan + scan_timestamps.size() - 1 of `estimate`) that has a reference. Every such
/// scan implies a frame; the one that more than half of them agree with (within `agree`; the earliest among
/// equals) is the truth: a single scan whose estimated pose is off from the rest of its submap (a front end that
/// lost a scan's heading in a fast turn and found it again) does not stand for the submap (docs/NOTES.md, "Loop
/// closures"). nullopt for a submap without a referenced scan or without such a majority (its scans disagree: it
/// has no one true frame). The relative pose of two submaps is then the reference's, up to the estimate's error
/// within each submap (local_consistency).
std::vector<std::optional<Pose2>> reference_frames(const Submaps& maps, const Scans& estimate, const Scans& reference,
                                                   const std::vector<std::optional<std::size_t>>& reference_index,
                                                   const PoseTolerance& agree = {0.25, 0.1});

/// A reference trajectory from a Freiburg .relations file (for a raw log without a corrected twin): the scans of `estimate` that a relation names (the scan of nearest timestamp, within 1 ms) become the nodes of a pose graph
/// whose edges are the relations (sigma 1 cm, 0.01 rad) and, joining consecutive nodes so that every component
/// is anchored, the estimate's own relative poses (sigma 1 m, 1 rad); the optimised poses are the reference.
/// `reference_index` gets, per scan of `estimate`, its node in the returned scans (nullopt for other scans).
/// Throws InputError when no relation names two scans of the estimate.
Scans reference_from_relations(const Scans& estimate, const Relations& relations,
                               std::vector<std::optional<std::size_t>>& reference_index);

/// The submaps that have a reference frame, with T_world_map set to it.
Submaps with_reference_frames(const Submaps& maps, const std::vector<std::optional<Pose2>>& frames);

/// The relations metric of Kuemmerle et al. 2009 ("On measuring the accuracy of SLAM algorithms"): for every
/// relation (t1, t2, T_1_2) whose two scans are in `scans` (matched to the scan of nearest timestamp, within 1 ms), the error pose
/// E = T_1_2^-1 * (T_world(t1)^-1 * T_world(t2)); mean and standard deviation of |E.translation| [m] and of
/// |E.theta| [rad]. With T_base_laser, the robot's poses are judged, T_world = T_world_laser * T_base_laser^-1; the
/// laser's otherwise. Which one a relations file relates is its own convention (the Freiburg hospital's relates its
/// robot's; docs/NOTES.md, "Which pose the relations relate"): judged at the other, a relation across a turn of theta
/// is off by up to 2 |t| sin(theta / 2) (|t| the mount's offset).
struct RelationsError {
  double translation_mean = 0.0, translation_std = 0.0;  ///< [m]
  double rotation_mean = 0.0, rotation_std = 0.0;        ///< [rad]
  std::size_t relations = 0;  ///< relations measured
  std::size_t missing = 0;    ///< relations with a scan not in `scans`
};

RelationsError relations_error(const Scans& scans, const Relations& relations, const Pose2& T_base_laser = {});

}  // namespace partslam
