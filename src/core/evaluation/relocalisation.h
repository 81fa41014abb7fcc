// The relocalisation protocol (docs/NOTES.md, "Locate"): a building map is made from the first
// visit of each place only — the scans of a corrected log before the first revisit (a scan within
// revisit_radius of one at least revisit_gap of travel earlier) — and local maps of the later scans, every
// query_spacing of travel, are located in it with no initial pose (core/matching/localizer.h). The map frame is
// the log's world frame, so a local map's true pose is its own T_world_map. A query's true overlap with the map
// is the share of its points that land, at that true pose, on the map's occupied cells as dMM sees them (0.1 m
// lattice, one cell of dilation); queries of places the first visit never saw have low overlap.
#pragma once

#include <numbers>
#include <vector>

#include "core/maps/grid_map.h"
#include "core/maps/submap.h"
#include "core/matching/localizer.h"

namespace partslam {

struct RelocalisationConfig {
  double revisit_radius = 2.0;   ///< a scan this close [m] ...
  double revisit_gap = 20.0;     ///< ... to one at least this much travel earlier [m] starts the revisits
  double query_spacing = 2.0;    ///< travel between the starts of consecutive query local maps [m]
  double min_overlap = 0.3;      ///< queries at least this much in the map are the ones that must be found
  PoseTolerance correct{0.3, 3.0 * std::numbers::pi / 180};  ///< a pose counts as correct within this
  ConfidenceRule confident_rule;  ///< which localisations are "confident" (is_confident)
  SubmapConfig submap;           ///< how local maps are built (window_length, range, alignment)
  LocalizerConfig localizer;
};

/// The q-quantile of v, q in [0, 1] (the nearest rank); 0 for no value.
double percentile(std::vector<double> v, double q);

/// Index of the first scan within revisit_radius of a scan at least revisit_gap of travel earlier; scans.size()
/// when the log never comes back.
std::size_t first_revisit(const Scans& scans, double revisit_radius, double revisit_gap);

struct RelocalisationOutcome {
  double travel = 0.0;   ///< start of the query's window along the log [m]
  double overlap = 0.0;  ///< true overlap with the map, [0, 1]
  Pose2 truth;           ///< the local map's true pose in the map frame
  Localization result;
  double translation_error = 0.0;  ///< [m]
  double rotation_error = 0.0;     ///< [rad]
  bool correct = false;            ///< within RelocalisationConfig::correct of the truth
  /// At the true pose, what the localizer would have seen: its candidates' score (a wrong answer scoring
  /// above it was chosen by the score, one below it was a true pose the searches missed) and the verification
  /// from there.
  double truth_score = 0.0;
  Verified truth_verified;
};

struct RelocalisationReport {
  std::vector<RelocalisationOutcome> outcomes;
  std::size_t in_map = 0;           ///< queries with overlap >= min_overlap
  std::size_t in_map_correct = 0;   ///< ... whose pose is correct
  std::size_t confident = 0;        ///< queries confident by the rule
  std::size_t confident_wrong = 0;  ///< ... whose pose is wrong (the rate a user would be misled)
  std::size_t outside = 0;          ///< queries with overlap < min_overlap
  std::size_t outside_confident = 0;  ///< ... reported as confident anyway
  double median_ms = 0.0, p95_ms = 0.0;  ///< time per query (both searches)
  std::vector<double> wing_directions;  ///< Localizer::wing_directions of the map [rad]
};

/// Locates local maps of scans[first_query, end) in `map` (built from earlier scans, in their world frame).
/// Throws InputError when no local map can be built after first_query.
RelocalisationReport evaluate_relocalisation(const GridMap& map, const Scans& scans, std::size_t first_query,
                                             const RelocalisationConfig& config = {});

}  // namespace partslam
