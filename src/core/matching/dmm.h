// Direct map matching (docs/DESIGN.md, "dMM"; the paper's Eq. 1 and, for CPD, Eq. 2):
//   v = max_T sum_{x in X} P_Y(T(x)),   P_Y = 1 on an occupied (optionally dilated) cell of Y's grid.
// match_dmm computes the exact maximum over a discretised window of rigid transforms T_map_query:
//   rotations  theta_k about the query origin (its centroid for submaps): {0, 90, 180, 270} deg +- a residual
//              window when both maps are in the canonical (Manhattan) frame, else a full circle;
//   translations t = (i r, j r) for integers |i|, |j| <= linear_window / r (or every translation at which the
//              query overlaps the target when linear_window <= 0; see "Small crop vs large map" below).
// A query point x scores at lattice cell floor(R_k x / r) + (i, j); points that fall outside the target's grid
// score 0. The search is Cartographer's FastCorrelativeScanMatcher2D (Hess et al., ICRA 2016) / Olson's
// multi-resolution correlative matching (ICRA 2009): rotated, discretised query point sets are computed once
// per query (PreparedQuery), a max-pooled grid pyramid once per target map (PreparedMap); depth-first
// branch-and-bound over (rotation, translation block) with the best score so far as the bar. Here it is 16-way
// (a node's 4 x 4 children are bounded in one pass, dmm_bounds.h), a node visits only the query points that can
// score in it, and a pass stops as soon as no child can beat the bar. The result equals match_exhaustive, which
// scores every candidate of the same discretisation (the reference and the baseline).
//
// Frames: T_map_query maps query-frame points into the target map's frame (T_map_query * x_query = x_map).
//
// Small crop vs large map (CPD, Eq. 2): to find where a small crop (tens to hundreds of points, a 2-10 m box)
// fits best on a whole-building dictionary map (e.g. 60 m x 40 m at 0.1 m), prepare the dictionary ONCE with
// linear_window <= 0 (the default of dmm_config_for_dictionary()) and match every crop against it. The window is
// then every translation at which at least one rotated crop point can land on the dictionary's grid, and the
// pyramid gets enough levels that the top level tiles the dictionary with a handful of blocks. Express crops
// relative to their own centroid so the rotation is about the crop's centre. Cost grows with the crop's points
// and the ambiguity of the dictionary, not with its area.
#pragma once

#include <cstdint>
#include <memory>
#include <numbers>
#include <span>
#include <vector>

#include "core/maps/occupancy_grid.h"

namespace partslam {

struct DmmConfig {
  double resolution = kMapResolution;  ///< grid cell and translation step [m]
  double linear_window = 6.0;  ///< translations |t_x|, |t_y| <= this [m]; <= 0: every translation at which the
                               ///< query overlaps the target grid (whole target map; CPD's crop vs dictionary)
  double angular_window = 3.0 * std::numbers::pi / 180;  ///< canonical: residual +- this about each multiple of
                                                         ///< 90 deg [rad]; ignored when canonical is false
  double angular_step = 0.0;   ///< rotation step [rad]; 0: the largest step that moves the query point farthest
                               ///< from the origin by at most one cell (Cartographer's choice)
  bool canonical = true;       ///< both maps are in the canonical frame (search 4 x residual); false: full circle
  int canonical_turns = 4;     ///< canonical: rotation families, 4 (multiples of 90 deg) or 8 (of 45 deg: for a
                               ///< local map whose own Manhattan alignment may be off by half a quarter turn)
  /// canonical: further families, each multiple of 90 deg turned by one of these offsets and searched
  /// +- extra_window: the directions of a building's wings that are not Manhattan to its main axes (a local map
  /// there is aligned to the wing's walls; wall_directions, core/maps/manhattan.h) [rad], each in [-pi/4, pi/4]
  std::vector<double> extra_directions;
  double extra_window = 3.0 * std::numbers::pi / 180;  ///< residual searched about each extra direction [rad]
  int dilation = 1;            ///< target cells within this many cells (Euclidean) of a point are occupied [cells]
  int search_depth = 0;        ///< 16-way branch-and-bound steps: root blocks of 4^depth x 4^depth translations;
                               ///< 0: the smallest depth whose roots tile the window about 2 x 2
};

/// Throws InputError naming the offending field.
void validate(const DmmConfig& config);

/// DmmConfig for matching small crops against a whole dictionary map (translation window = whole target).
DmmConfig dmm_config_for_dictionary();

/// One rotation of the query, discretised on the lattice: cell k of the point set is (x[k], y[k]), sorted by
/// y (stable) so that the points whose row misses a grid are found by binary search.
struct RotatedQuery {
  double angle = 0.0;         ///< rotation about the query origin [rad]
  std::vector<int> x, y;      ///< lattice cells floor(R(angle) p / r), one per query point
  int x_min = 0, x_max = -1;  ///< cell bounds of the rotated set (empty set: max < min)
  int y_min = 0, y_max = -1;
};

/// A query prepared once and matched against many maps (1-to-N amortises the rotations).
struct PreparedQuery {
  DmmConfig config;         ///< what it was prepared with (its rotation search); bound here, checked at match
  double resolution = kMapResolution;  ///< lattice the cells live on [m] (= config.resolution)
  int num_points = 0;       ///< query points (the denominator of inlier_fraction)
  double angular_step = 0;  ///< rotation step actually used [rad]
  std::vector<RotatedQuery> rotations;
};

/// A target (database or dictionary) map prepared once: its occupancy grid (P_Y of Eq. 1) and every other level
/// of its max-pooled pyramid, packed 4 x 4 (PackedLevel) so one lookup bounds the sixteen children of a node.
/// Memory: 2 bytes per cell of each packed level (grid + padding of 3 blocks); ~110 KB for an fr079 submap at
/// 0.1 m with the default window (3 levels), ~2 MB for the intel building as a dictionary (whole-map window).
struct PreparedMap {
  DmmConfig config;                 ///< what it was prepared with: its translation window, dilation and depth
  OccupancyGrid grid;               ///< the (dilated) occupancy grid
  std::vector<PackedLevel> packed;  ///< packed[d]: pyramid level 2 d packed with step 4^d, d < search depth
  int num_points = 0;               ///< points the grid was built from
};

/// Throws InputError for an invalid config or non-finite points.
PreparedQuery prepare_query(const Points2& points_query, const DmmConfig& config = {});
PreparedMap prepare_map(const Points2& points_map, const DmmConfig& config = {});

struct DmmResult {
  int inliers = 0;               ///< Eq. 1 score: query points on occupied cells of the map at T_map_query
  double inlier_fraction = 0.0;  ///< inliers / query points (0 for an empty query)
  Pose2 T_map_query;             ///< maps query-frame points into the map frame
  bool exact = true;             ///< false when top-k pruning proved the map's score <= the k-th best score of
                                 ///< the maps before it: inliers is then 0 and T_map_query the identity
  std::int64_t candidates_scored = 0;  ///< (rotation, translation block) bounds and scores evaluated
  bool paused = false;           ///< DmmSearch::next ran out of its budget before the next pose (no pose here)
};

/// Exact maximum of Eq. 1 over the discretised window, by branch-and-bound. Ties keep the candidate found first.
/// The settings are those the two were prepared with (Cartographer binds a matcher's options at construction):
/// the query's rotations, the map's translation window. Throws InputError when the query and the map were
/// prepared on different lattices or rotation searches.
DmmResult match_dmm(const PreparedQuery& query, const PreparedMap& map);

/// The best match elsewhere than `avoid` (how unique a match is: the confidence of a localisation): the exact
/// maximum of Eq. 1 over the candidates whose translation lies at least min_distance [m] from avoid's or whose
/// rotation differs from avoid's by more than min_angle [rad]. Same search, excluded candidates skipped (a block
/// wholly inside the excluded disc is never expanded). inliers 0 and exact = true when every candidate is excluded.
DmmResult match_dmm_elsewhere(const PreparedQuery& query, const PreparedMap& map, const Pose2& avoid,
                              double min_distance, double min_angle);
/// The same, elsewhere than every pose in `avoid` (the next-best distinct candidates, one search each); with
/// bar >= 0 only a candidate scoring more than `bar` is reported (else exact = false, inliers 0), which prunes.
DmmResult match_dmm_elsewhere(const PreparedQuery& query, const PreparedMap& map, std::span<const Pose2> avoid,
                              double min_distance, double min_angle, int bar = -1);

/// The distinct best poses of one query on one map, best first (a localisation's candidates, the verified
/// ranking's alternatives): the first next() is match_dmm's optimum, each later one the best pose elsewhere than
/// every pose returned before, as match_dmm_elsewhere defines it (translation >= min_distance [m] away or
/// rotation > min_angle [rad] apart); the same scores, and among equal scores possibly another pose. One
/// best-first branch-and-bound serves every call: a node bounded once is never bounded again, so k poses cost
/// about what the k-th of k separate searches costs. Keeps references to the query and the map (both must
/// outlive it) and the expanded nodes' query cells (memory grows with the calls). Not thread-safe.
/// lazy: for a few poses (the verified ranking's best and three alternatives). A subtree is searched only for a
/// leaf that reaches the best one found so far in the call, so the first pose costs about what the depth-first
/// search costs, but a subtree put back may be searched again by each later call. Not lazy: each subtree is
/// searched for its best leaf outright when it first comes up, which pays when many poses are asked for (the
/// localiser's 32 candidates on a building map: 34 ms a query on fr079 against 56 ms lazy). The same scores
/// either way; among equal scores the poses may come in another order.
class DmmSearch {
 public:
  /// Throws InputError when the two were prepared on different lattices or rotation searches, or for a negative
  /// or non-finite distance or angle.
  DmmSearch(const PreparedQuery& query, const PreparedMap& map, double min_distance, double min_angle,
            bool lazy = false);
  ~DmmSearch();
  DmmSearch(const DmmSearch&) = delete;
  DmmSearch& operator=(const DmmSearch&) = delete;

  /// The next pose. bar >= 0: only a pose scoring more than the highest bar given so far is reported, else
  /// exact = false and inliers 0 (bars are floors: a lower one later does not bring back what a higher one
  /// pruned). inliers 0 with exact = true when every candidate has been returned or excluded.
  /// budget > 0: once this call's work reaches `budget` (the query cells its bound passes read, plus 2000 per
  /// node popped: about proportional to time, about a millisecond per million), it stops between two steps of
  /// the search and returns paused = true (no pose); the next call goes on from there, so the poses come in the
  /// same order as without a budget (a search spread over several steps of a tracker). The work before the
  /// first pop (bounding the roots' children) is not split.
  DmmResult next(int bar = -1, std::int64_t budget = -1);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// The same maximum by scoring every (rotation, translation) of the discretisation; first maximum in the order
/// rotation, y, x. The reference for tests and the speed baseline.
DmmResult match_exhaustive(const PreparedQuery& query, const PreparedMap& map);

/// 1-to-N. top_k <= 0: every map's exact score (the default, what ranking needs); maps are independent, so
/// num_threads > 1 (OpenMP) gives the same results as 1. top_k > 0: maps are searched in order with the k-th
/// best exact score so far as the bar, so a map that cannot beat it is dropped early (exact = false); the k
/// maps with the highest scores (ties: the earlier map) are exact. Top-k mode runs serially.
std::vector<DmmResult> match_dmm_many(const PreparedQuery& query, std::span<const PreparedMap> maps, int top_k = 0,
                                      int num_threads = 1);
/// The same over maps held elsewhere (e.g. a subset of a prepared database).
std::vector<DmmResult> match_dmm_many(const PreparedQuery& query, std::span<const PreparedMap* const> maps,
                                      int top_k = 0, int num_threads = 1);

/// Joint exact 1-to-N search (after Olson's M3RSM, ICRA 2015): the top level of every map's search is bounded
/// first, then the maps are searched best bound first with the k-th best score so far as the bar, and the search
/// stops at the first map whose bound cannot beat it. The k maps with the highest scores (ties: the earlier map)
/// are exact and equal match_dmm's; every other result has exact = false, inliers 0. Serial. Memory: each map's
/// root bounds (roots x query points x 2 bytes) during the call.
std::vector<DmmResult> match_dmm_joint(const PreparedQuery& query, std::span<const PreparedMap* const> maps,
                                       int top_k = 1);

}  // namespace partslam
