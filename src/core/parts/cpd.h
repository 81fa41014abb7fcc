// Common pattern discovery (docs/DESIGN.md, "CPD"; paper §"Common Pattern Discovery", after Randomized Visual
// Phrases, Jiang et al. 2012). Candidate keypoint boxes crop the input map; for each, the descriptor box is
// where the cropped points fit the dictionary best, AS(B) = max_T sum_{x in crop(B)} P_R(T(x)) (Eq. 2, an exact
// dMM search of the crop against the whole dictionary grid R).
// Candidates (CandidateMode):
//   kPartitions — the paper: random partitions of the map's bounding box into grids of boxes, many times.
//   kCorners (default) — squares of box_sizes centred on the map's strongest corner points. Two maps of the
//       same place see the same corners, so they crop the same structure and their descriptor boxes land on
//       the same dictionary spot; random partitions of two differently shaped maps rarely crop the same thing.
// Criteria, each a parameter:
//   MC (maximality): literal reading — the crop holds at least t_size of the map's points (few, large parts);
//       inlier-share reading (default) — at least t_size of the crop's points are inliers on R.
//   GC (geometric consistency, off by default): the descriptor boxes of the selected parts pairwise overlap.
//   AS: among candidates meeting MC and GC, the highest AS first (greedy); ties keep the seeded shuffled
//       candidate order.
// The defaults are what measured best on the five data sets (docs/NOTES.md); the paper's setting is
// candidates = kPartitions, maximality = kPointShare, geometric_consistency = true.
// MD (select_top_parts) then keeps the top K. Everything is seeded and deterministic; parallel over maps gives
// the same parts as serial.
#pragma once

#include <cstdint>
#include <vector>

#include "core/matching/dmm.h"
#include "core/parallel.h"
#include "core/parts/part.h"

namespace partslam {

enum class MaximalityMode {
  kPointShare,  ///< literal: |crop| / |map| >= t_size
  kInlierShare  ///< |inliers of crop on dictionary| / |crop| >= t_size
};

/// Where candidate keypoint boxes come from.
enum class CandidateMode {
  kPartitions,  ///< RVP: random partitions of the map's bounding box into grids of boxes (the paper)
  kCorners      ///< squares of a few sizes centred on the map's corner points (repeatable across revisits)
};

struct CpdConfig {
  int max_parts = 100;           ///< parts returned per map (the hMM query keeps ~100)
  CandidateMode candidates = CandidateMode::kCorners;  ///< candidate keypoint boxes
  int partitions = 64;           ///< random partitions of the map tried at most
  double min_cell_fraction = 0.4;  ///< smallest partition cell side, as a share of the map's box side
  double max_cell_fraction = 1.2;  ///< largest partition cell side, as a share of the map's box side
  MaximalityMode maximality = MaximalityMode::kInlierShare;  ///< MC reading
  double t_size = 0.9;           ///< MC threshold T^size
  int min_crop_points = 20;      ///< crops with fewer points are never candidates
  bool geometric_consistency = false;  ///< GC: selected descriptor boxes must pairwise overlap
  int corners = 24;              ///< kCorners: corner points kept per map (strongest first)
  std::vector<double> box_sizes = {2.0, 4.0};  ///< kCorners: sides of the squares centred on a corner [m]
  double corner_radius = 0.8;    ///< kCorners: neighbourhood of the corner response [m]
  double corner_spacing = 1.0;   ///< kCorners: kept corners are at least this far apart [m]
  double crop_extent = 6.4;      ///< kCorners: boxes are clipped to |x|, |y| <= this (the codec's crop) [m]
  double crop_resolution = kMapResolution;  ///< crops are downsampled to this cell before matching [m] (speed)
  std::uint64_t seed = 1;        ///< base seed; each map mixes in its own key
  DmmConfig dmm = dmm_config_for_dictionary();  ///< the crop-vs-dictionary search (Eq. 2)
};

/// Throws InputError naming the offending field.
void validate(const CpdConfig& config);

/// The dictionary prepared once for CPD (grid + pyramid) and the extent descriptor boxes live in.
struct PreparedDictionary {
  PreparedMap map;
  Box2 extent;  ///< bounding box of the dictionary points [m]
};

PreparedDictionary prepare_dictionary(const Points2& dictionary_points, const CpdConfig& config = {});

struct CpdStats {
  int candidates = 0;       ///< distinct boxes generated
  int passed_mc = 0;        ///< candidates meeting MC
  int matched = 0;          ///< AS searches run
  int passed_gc = 0;        ///< parts kept after GC
};

struct CpdResult {
  std::vector<Part> parts;  ///< best AS first, at most max_parts
  CpdStats stats;
  double ms = 0;            ///< wall time of this map's CPD [ms] (discover_parts_many)
};

/// kCorners: the map's corner points, strongest first: points whose neighbourhood (corner_radius) has a large
/// smaller structure-tensor eigenvalue, at least corner_spacing apart, at most config.corners of them.
Points2 find_corners(const Points2& map_points, const CpdConfig& config);

/// Parts of one map (points in its canonical frame). map_key (e.g. the map id) seeds its partitions and the
/// shuffle of its candidates.
CpdResult discover_parts(const Points2& map_points, const PreparedDictionary& dictionary, const CpdConfig& config,
                         std::uint64_t map_key);

/// The offline stage of every path (eval, describe, tools): discover_parts over many maps, each seeded by its
/// key (the map's id: Submap::id), timed per map; num_threads > 1 runs maps in parallel (OpenMP) with identical
/// results. Progress is reported as stage "parts (CPD)".
std::vector<CpdResult> discover_parts_many(const std::vector<const Points2*>& maps,
                                           const std::vector<std::uint64_t>& map_keys,
                                           const PreparedDictionary& dictionary, const CpdConfig& config,
                                           int num_threads = 1, const Progress& progress = {});

}  // namespace partslam
