// Verifying a match (docs/NOTES.md, "Verifying a match"): is the query the same place as a stored map at a
// given pose? Eq. 1 only counts query points that land on the map's structure, so any cluttered map explains
// a query well. The verification reads both directions and the free space the beams crossed:
//   - each map is a grid of unknown / free / occupied cells: occupied as dMM's (dilated) grid, free where
//     a beam from one of the map's laser origins (Submap::origins) passed on its way to a point;
//   - at T_map_query the query's points are looked up in the map's grid and the map's points in the query's:
//     the shares that land on structure, on free space (a beam of the other map passed through that wall) and
//     on cells the other map saw at all (their common field of view);
//   - each map's points are read on the other's likelihood field (the front end's, 0.05 m cells): a
//     smooth fit that tells walls laid on each other from walls that only fall inside one another's
//     dilation;
//   - the same share on structure and fit, with each point weighted by how little it lies on a line
//     (core/maps/local_shape.h): straight walls are what every corridor shares, corners, door jambs and
//     clutter tell two corridors apart (docs/NOTES.md, "Corner-weighted terms");
//   - a logistic model of those terms and their products (weights fitted on the tuning split to rank each
//     task's right answer first, then Platt-scaled; docs/NOTES.md) turns them into the probability that
//     the two maps show the same place at that pose.
// refine_match moves a lattice pose to the smooth optimum (the front end's correlative + Gauss-Newton matcher
// on a likelihood field of the map's points), below the lattice that limits Eq. 1.
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <vector>

#include "core/matching/dmm.h"
#include "core/matching/scan_matcher.h"
#include "core/types.h"

namespace partslam {

struct VerifyConfig {
  double resolution = kMapResolution;  ///< cell of the free-space grid [m] (dMM's lattice)
  int dilation = 1;                    ///< occupied cells grown by this many cells, as dMM's grid [cells]
  double max_ray = 12.0;               ///< beams longer than this are not cast [m]
  double refine_window = 0.3;          ///< refine_match searches +- this around the pose [m]
  double refine_angle = 0.05;          ///< and +- this in rotation [rad]
  /// verify_dmm: besides Eq. 1's optimum, up to this many next-best distinct poses are verified (a Manhattan
  /// building's quarter turns and a corridor's shifts score alike under Eq. 1)
  int alternatives = 3;
  double alternative_bar = 0.6;       ///< an alternative must reach this share of the optimum's Eq. 1 score
  double alternative_distance = 1.0;  ///< distinct: translations this far apart [m]
  double alternative_angle = 0.3;     ///< or rotations this far apart [rad]
  /// verify_dmm: the most probable this many poses (at their lattice pose) are refined, and the most probable
  /// after refinement is the answer; 1: only the most probable at the lattice (a right pose a cell or a degree
  /// off often fits worse there than a wrong one sitting on the lattice)
  int refined = 4;
  /// a point's cornerness is read off its neighbours within this radius [m]
  double corner_radius = 0.7;
  /// refine_match keeps the pose's translation along the direction the query's walls do not fix
  /// (unconstrained_direction of its wall_scatter at this ratio, core/maps/local_shape.h: a bare corridor's
  /// axis, where the match fits about as well anywhere and slides) within keep_along_slack of the input pose's,
  /// in [0, 1); 0: the match moves it freely
  double keep_along_ratio = 0.0;
  double keep_along_slack = 0.0;  ///< [m], in [0, 5]; 0: the translation along it stays the input pose's
};

/// Throws InputError naming the offending field.
void validate(const VerifyConfig& config);

/// A map as the verification reads it.
class VerifyMap {
 public:
  static constexpr std::uint8_t kUnknown = 0, kFree = 1, kOccupied = 2;

  VerifyMap() = default;
  /// From the map's points and laser origins in its own frame (no origins: no free space, every cell not
  /// occupied is unknown); each point's cornerness over its neighbours within config.corner_radius. Each
  /// point is cast from the origin whose beam to it crosses the fewest occupied cells (the nearest among
  /// equals): a submap's origins lie along a short path, and the one that saw a point has a clear line to it.
  /// Throws InputError for non-finite points, a grid of more than 2^24 cells, or a point more than 2^30 cells
  /// from the frame's origin.
  VerifyMap(const Points2& points, const Points2& origins, const VerifyConfig& config = {});
  /// A map that knows its free space already (a building map's free cells, e.g. a map_server map): occupied
  /// cells from `points` (dilated), free ones under `free_points` where not occupied. Throws as the above.
  static VerifyMap with_free_space(const Points2& points, const Points2& free_points,
                                   const VerifyConfig& config = {});

  /// The part of the map inside the box [lo, hi] (its frame): the cells there and the points in them, as if
  /// the map had only seen that much (a building map cut to the neighbourhood of a local map). An empty map
  /// when the box misses the grid or a corner is NaN.
  VerifyMap cropped(const Vec2& lo, const Vec2& hi) const;

  /// The state of the cell holding p (kUnknown outside the grid, or for a p that is not finite). The cell is
  /// found in double: a point far out has no int cell index.
  std::uint8_t at(const Vec2& p) const {
    const double cx = std::floor(p.x() * inv_resolution_) - x0_;
    const double cy = std::floor(p.y() * inv_resolution_) - y0_;
    return cx >= 0 && cx < width_ && cy >= 0 && cy < height_
               ? cells_[static_cast<std::size_t>(cy) * static_cast<std::size_t>(width_) +
                        static_cast<std::size_t>(cx)]
               : kUnknown;
  }
  const Points2& points() const { return points_; }
  /// points()[i]'s cornerness (LocalShape::cornerness), read on the whole map before any crop
  const std::vector<double>& cornerness() const { return cornerness_; }
  /// How its walls fix a translation (wall_scatter of its points' shapes), read on the whole map before any crop
  const Eigen::Matrix2d& wall_scatter() const { return wall_scatter_; }
  bool has_beams() const { return has_beams_; }
  double resolution() const { return resolution_; }
  std::size_t free_cells() const;

 private:
  /// An unknown grid over the cells of every point in `sets`, grown by `margin` cells (the map's points are
  /// set by the caller). Throws InputError for more than 2^24 cells or a cell index beyond 2^30.
  void allocate(std::initializer_list<const Points2*> sets, int margin);
  Eigen::Vector2i cell_of(const Vec2& p) const {
    return {static_cast<int>(std::floor(p.x() * inv_resolution_)),
            static_cast<int>(std::floor(p.y() * inv_resolution_))};
  }
  std::size_t index_of(int x, int y) const {
    return static_cast<std::size_t>(y - y0_) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(x - x0_);
  }
  /// The points' cornerness and wall scatter over their neighbours within `radius`.
  void set_shapes(double radius);
  /// The cells within `dilation` of `cell` (a disc) become occupied.
  void mark_occupied(const Eigen::Vector2i& cell, int dilation);

  double resolution_ = kMapResolution, inv_resolution_ = 1.0 / kMapResolution;
  int x0_ = 0, y0_ = 0, width_ = 0, height_ = 0;
  std::vector<std::uint8_t> cells_;
  Points2 points_;
  std::vector<double> cornerness_;
  Eigen::Matrix2d wall_scatter_ = Eigen::Matrix2d::Zero();
  bool has_beams_ = false;
};

/// What one map says of the other at a pose: shares of its points that land on the other's occupied, free and
/// seen (free or occupied) cells, and the share on occupied cells with each point weighted by its cornerness.
struct SideTerms {
  double occupied = 0, free = 0, seen = 0;
  double corner = 0;  ///< cornerness-weighted share on occupied cells (0 when no point has any)
};

struct MatchTerms {
  SideTerms query;       ///< the query's points in the map's grid (query.occupied is Eq. 1's inlier share)
  SideTerms map;         ///< the map's points in the query's grid
  double query_fit = 0;  ///< mean of the map's likelihood field at the query's points, in [0, 1]
  double map_fit = 0;    ///< mean of the query's likelihood field at the map's points
  double query_corner_fit = 0;  ///< query_fit with each point weighted by its cornerness
  double map_corner_fit = 0;    ///< map_fit with each point weighted by its cornerness
  bool beams = false;    ///< both maps had laser origins (the free and seen shares are meaningful)
};

/// The two maps' likelihood fields (the front end's: 0.05 m cells, sigma 0.1 m), built once per pair: the fit
/// terms and refine_match read them.
class PairFields {
 public:
  PairFields(const VerifyMap& query, const VerifyMap& map);
  /// With the query's field built before (verify_field of the same query), borrowed, not copied: it must outlive
  /// this. One query verified at many places builds it once.
  PairFields(const LikelihoodField& query_field, const VerifyMap& map);
  PairFields(const PairFields&) = delete;  // query() may point into own_query_
  PairFields& operator=(const PairFields&) = delete;

  const LikelihoodField& query() const { return *query_; }
  LikelihoodField map;

 private:
  LikelihoodField own_query_;  // empty when borrowed
  const LikelihoodField* query_;
};

/// A map's field as PairFields builds it.
LikelihoodField verify_field(const VerifyMap& map);

/// The terms at T_map_query (maps query-frame points into the map frame). Empty maps give zero terms.
MatchTerms match_terms(const VerifyMap& query, const VerifyMap& map, const PairFields& fields,
                       const Pose2& T_map_query);

/// The probability that the two maps show the same place at that pose: a logistic model of the terms,
/// coefficients in verification.cc, fitted by tools/fit_verification.py on the tuning split with beams on
/// both sides. Without beams (a map of bare points: terms.beams false) the free shares are 0 and it ranks by
/// the two occupied shares, but it is not calibrated for that case.
double same_place_probability(const MatchTerms& terms);

/// The pose moved to the best fit of the query's points on the map's likelihood field (fields.map) within
/// +- refine_window / refine_angle (correlative search on 0.05 m cells, then Gauss-Newton); the input pose
/// when either map has no points.
Pose2 refine_match(const VerifyMap& query, const PairFields& fields, const Pose2& T_map_query,
                   const VerifyConfig& config = {});

struct Verified {
  Pose2 T_map_query;       ///< refined pose
  MatchTerms terms;        ///< at that pose
  double probability = 0;  ///< same_place_probability(terms)
};

/// The terms and probability at T_map_query as it is (no refinement).
Verified verify_at(const VerifyMap& query, const VerifyMap& map, const PairFields& fields,
                   const Pose2& T_map_query);

/// refine_match, then the terms and probability at the refined pose (or at the input pose when refining
/// lowers the probability). at_pose (when given): the terms and probability at T_map_query itself.
Verified verify_match(const VerifyMap& query, const VerifyMap& map, const Pose2& T_map_query,
                      const VerifyConfig& config = {}, Verified* at_pose = nullptr);
/// The same with the query's field built before (verify_field(query)): the same answer.
Verified verify_match(const VerifyMap& query, const LikelihoodField& query_field, const VerifyMap& map,
                      const Pose2& T_map_query, const VerifyConfig& config = {}, Verified* at_pose = nullptr);

/// The poses verify_dmm verifies: Eq. 1's exact optimum first, then up to config.alternatives next-best
/// distinct poses scoring at least alternative_bar of it (one DmmSearch).
std::vector<DmmResult> dmm_poses(const PreparedQuery& query, const PreparedMap& map,
                                 const VerifyConfig& config = {});

/// dmm_poses, each verified at its lattice pose; the config.refined most probable ones refined (verify_match),
/// and the most probable after that returned.
/// `eq1` is the optimum's Eq. 1 result (the search's statistics and the paper's score).
struct VerifiedDmm {
  DmmResult eq1;
  Verified best;
  int poses = 0;  ///< poses verified
  /// The probability of the most probable other pose verified: at least alternative_distance [m] or more
  /// than alternative_angle [rad] from best's (0 when there is none). Near best.probability, the map is the
  /// same place at either pose and the answer's pose cannot be trusted (a corridor's half turn:
  /// docs/NOTES.md, "Pose ambiguity").
  double runner_up = 0;
};
VerifiedDmm verify_dmm(const PreparedQuery& query, const PreparedMap& map, const VerifyMap& query_verify,
                       const VerifyMap& map_verify, const VerifyConfig& config = {});

/// Whether a verified answer's pose is ambiguous: its runner-up pose is at least kAmbiguousPoseShare of its
/// probability (chosen on the tuning split; docs/NOTES.md, "Pose ambiguity").
inline constexpr double kAmbiguousPoseShare = 0.5;
inline bool pose_ambiguous(double probability, double runner_up) {
  return probability > 0 && runner_up >= kAmbiguousPoseShare * probability;
}
/// The same for a ranked candidate that may not have been verified (Ranking::probability, ::runner_up): none
/// unless both are known.
inline std::optional<bool> pose_ambiguous(const std::optional<double>& probability,
                                          const std::optional<double>& runner_up) {
  if (!probability || !runner_up) return std::nullopt;
  return pose_ambiguous(*probability, *runner_up);
}

}  // namespace partslam
