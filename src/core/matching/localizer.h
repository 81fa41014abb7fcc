// Global localisation in a building map (docs/NOTES.md, "Locate"): where does a new local map lie in a map of
// the whole building (a map_server map, a corrected log's map), with no initial pose? The building map is
// prepared once for dMM over its whole area (the dictionary's set-up: every translation at which the query
// overlaps it, dmm_config_for_dictionary), in its canonical (Manhattan) frame so that a canonical local map
// needs a few turns plus a small residual. Each query is one exact best-first branch-and-bound (DmmSearch)
// that yields the best pose, then the best pose elsewhere than the ones found so far, `candidates` in all.
// With a map that knows its free space (a GridMap), each candidate is rescored by what contradicts it: local
// map points that land on cells the map saw free (a corridor turned end for end, a room that is not there)
// cost free_weight inliers each. The best `verified` rescored candidates are verified
// (core/matching/verification.h) against the building map cut to each one's neighbourhood: refined below
// dMM's lattice, with the same-place probability of both directions and both free spaces; the most probable
// is the answer (in a long corridor the true place often scores a few inliers below an alias that the free
// space and the fit tell apart), verified again from starts around it (restart_distance). How unique it is:
// confidence = the best score at its place - the best score at another place (shares of the query's points;
// "another place": elsewhere.distance away, candidates may lie closer together), near 0 for a corridor that
// fits two places or a place the map does not hold; it is reported as found when that margin and its
// probability are both high enough (is_confident; docs/NOTES.md, "Locate"). Buildings with a wing at another
// angle have that wing's direction searched too (wall_directions).
#pragma once

#include <cstddef>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/maps/grid_map.h"
#include "core/matching/distinctiveness.h"
#include "core/matching/dmm.h"
#include "core/matching/verification.h"

namespace partslam {

/// The whole-map window, canonical frames, eight rotation families: a 2 m local map's own Manhattan alignment
/// is off by about 45 degrees often enough in a cluttered lab (intel) to need them (docs/NOTES.md, "Locate").
DmmConfig localizer_dmm_config();

/// The verification of the answer, refined within +-0.15 m (a lattice step and a half): with +-0.3 m the fit terms
/// drew one of intel's answers 0.37 m along a corridor, a confident wrong answer (docs/NOTES.md, "Locate").
inline VerifyConfig localizer_verify_config() {
  VerifyConfig config;
  config.refine_window = 0.15;
  return config;
}

struct LocalizerConfig {
  DmmConfig dmm = localizer_dmm_config();
  VerifyConfig verify = localizer_verify_config();  ///< the verification of the answer
  /// The confidence's "elsewhere": the local map's centre at least 2 m away, or turned by more than 10 degrees.
  OtherPlace elsewhere{2.0, 10.0 * std::numbers::pi / 180};
  /// The search's candidates are poses at least this far apart (or turned by more than elsewhere.angle) [m],
  /// in (0, elsewhere.distance]: finer than "elsewhere", so that the true place a metre along a corridor from
  /// an alias that Eq. 1 prefers is examined too. 1 m with 32 candidates and 16 verified (chosen on fr079 and
  /// intel: 75 of 80 and 184 of 192 within 0.3 m / 3 deg, against 74 and 180 with 2 m, 16 and 8; 1 m with 16
  /// candidates: 71 and 181; 0.5 m with 32 and 16: 71 and 182; docs/NOTES.md, "Locate").
  double candidate_distance = 1.0;
  /// Distinct poses examined, in [2, 100] (with candidate_distance; 48 gives the same answers).
  int candidates = 32;
  double free_weight = 1.0;         ///< inliers a point on the map's free space costs (maps with free space only)
  double neighbourhood = 1.0;       ///< verification: the building map cut to the local map's box grown by this [m]
  /// The building's wall directions off its axes and diagonals holding at least this share of its walls and
  /// this length (wall_directions: a wing built at another angle) are searched too (DmmConfig::extra_directions,
  /// four families each, about 1.3-1.6x the time where there is one); share 0: none. 10 m is above what fr079
  /// and intel, the floor's sets, hold (at most 8-10 m, intel's whole-log map; docs/NOTES.md, "Locate").
  double wall_direction_share = 0.03;
  double wall_direction_length = 10.0;  ///< [m]
  /// The best-scoring candidates verified (refined, with their same-place probability): the most probable is
  /// the answer, in [1, 100]. 16 (with candidate_distance: 8 put 182 of intel's 192 within 0.3 m / 3 deg, 16
  /// 184).
  int verified = 16;
  /// The answer is verified again from starts this far from it along each axis of the map [m] (0: not), and
  /// the most probable is the answer: a candidate half a metre from the true pose does not refine onto it.
  /// 0.5 (chosen on fr079 and intel: 0 / 0.3 / 0.4 / 0.5 put 66 / 67 / 66 / 67 of 80 and 166 / 173 / 170 /
  /// 170 of 192 within 0.1 m / 1 deg, 184 / 183 / 184 / 184 of 192 within 0.3 m / 3 deg; docs/NOTES.md,
  /// "Locate").
  double restart_distance = 0.5;
};

/// Throws InputError naming the field.
void validate(const LocalizerConfig& config);

struct Localization {
  Pose2 T_map_query;              ///< the local map's frame in the building map's frame
  Pose2 T_map_lattice;            ///< the answer's candidate pose on dMM's lattice (T_map_query before refining)
  int inliers = 0;                ///< query points on occupied cells at the lattice pose (Eq. 1)
  double inlier_fraction = 0.0;   ///< inliers / query points
  int free_conflicts = 0;         ///< query points on cells the map saw free (not counted as inliers)
  double score = 0.0;             ///< (inliers - free_weight * free_conflicts) / query points
  double elsewhere_score = 0.0;   ///< the best score at another place (0 when there is none)
  Pose2 T_map_elsewhere;          ///< that candidate's pose
  /// max(0, the best score at the answer's place (the candidates within "elsewhere" of it) -
  /// elsewhere_score): 0 when a less probable place scores higher
  double confidence = 0.0;
  MatchTerms terms;               ///< the verification's terms at T_map_query
  double probability = 0.0;       ///< same_place_probability there
  /// both maps had free space (the building map's free cells, the local map's laser origins): the probability
  /// reads both free spaces; false for bare points (a point file)
  bool calibrated = false;
  int candidates = 0;             ///< candidates examined
  double time_ms = 0.0;           ///< all searches and verification [ms]
};

/// Whether an answer is reported as found: the rule's verdict on its confidence and, when `calibrated`, its
/// probability.
bool is_confident(const Localization& l, const ConfidenceRule& rule = {});
/// Whether the answers for two local maps of one log agree with the log's own motion between them: the second
/// answer's pose seen from the first's, and the log's second pose seen from its first, differ by at most
/// `tolerance` plus a tenth of the distance between the log's poses in translation (its odometry drifts with
/// travel). T_map_*: the answers' robot poses in the map; T_log_*: the same scans' poses in the log.
bool answers_agree(const Pose2& T_map_a, const Pose2& T_map_b, const Pose2& T_log_a, const Pose2& T_log_b,
                   const PoseTolerance& tolerance = {0.5, 10.0 * std::numbers::pi / 180});

/// Why an answer is not confident, in words ("margin 0.12 < 0.2", "same-place probability 0.010 < 0.025", or
/// both, joined by "; "); empty when it is.
std::string not_confident_because(const Localization& l, const ConfidenceRule& rule = {});

class Localizer {
  struct Candidate;
  struct Candidates;

 public:
  /// A building map with its free space (a map_server map, build_grid_map of a corrected log). Throws
  /// InputError for a map without an occupied cell, a bad config or a map beyond the dMM limits.
  explicit Localizer(const GridMap& map, const LocalizerConfig& config = {});
  /// Occupied points only (in the map's frame): nothing to contradict, the verification reads structure only.
  explicit Localizer(const Points2& map_points, const LocalizerConfig& config = {});

  /// query_points: the local map in its own frame, canonical (Manhattan-aligned, as build_local_map returns it)
  /// when config.dmm.canonical; query_origins: where the laser was (Submap::origins), none for bare points.
  /// Throws InputError for an empty query or non-finite points.
  Localization locate(const Points2& query_points, const Points2& query_origins = {}) const;

  /// The candidates' score at a pose (T_map_query, in the map's frame): query points on the map's dilated occupied
  /// cells minus free_weight times those on its free cells, as a share of the query's points.
  double score_at(const Points2& query_points, const Pose2& T_map_query) const;
  /// The verification at a pose: the building map cut to the local map's box there grown by `neighbourhood`,
  /// refined and scored (verify_match). query_points must not be empty.
  Verified verify(const Points2& query_points, const Points2& query_origins, const Pose2& T_map_query) const;

  /// A local map prepared for verification once, however many poses are verified: its grid (beams cast from
  /// its laser origins), the box of its points and origins, and its likelihood field.
  struct VerifyQuery {
    VerifyMap map;
    Vec2 lo, hi;
    LikelihoodField field;  ///< verify_field(map): built once, read by every verification of this query
  };
  /// query_points must not be empty.
  VerifyQuery verify_query(const Points2& query_points, const Points2& query_origins) const;

  /// The global search's distinct answers, most probable first (a tracker's hypotheses): locate()'s best
  /// `verified` candidates (config().verified when < 1) refined and scored as its answer is; an answer that
  /// refines within candidate_distance and elsewhere.angle of a more probable one is the same pose and dropped;
  /// at most `count`. min_share in [0, 1): the search stops at candidates with no more than this share of the
  /// first one's inliers (a pose that fits half as well as the best is not one to carry; it cuts the search's
  /// work where the second place is far below the first; 0: every candidate, as locate() searches). Throws
  /// InputError as locate() does, and for min_share out of range.
  std::vector<Verified> hypotheses(const Points2& query_points, const Points2& query_origins, int count,
                                   int verified = 0, double min_share = 0.0) const;
  /// The same with the local map already prepared for verification (verify_query of the same points).
  std::vector<Verified> hypotheses(const Points2& query_points, const VerifyQuery& prepared, int count,
                                   int verified = 0, double min_share = 0.0) const;
  /// hypotheses() spread over several calls (a tracker whose steps have a time limit): each advance() goes on
  /// with the dMM search for about `budget` of its work (DmmSearch::next's budget, about a millisecond per
  /// million; 0: to its end), and the call that ends the search verifies its candidates. The hypotheses are
  /// those hypotheses() gives for the same local map, however the work was split. Keeps a reference to the
  /// localizer; not copied or moved (the search refers to its own prepared query).
  class HypothesisSearch {
   public:
    /// Throws InputError as hypotheses() does.
    HypothesisSearch(const Localizer& localizer, const Points2& query_points, VerifyQuery prepared, int count,
                     int verified = 0, double min_share = 0.0);
    ~HypothesisSearch();
    HypothesisSearch(const HypothesisSearch&) = delete;
    HypothesisSearch& operator=(const HypothesisSearch&) = delete;
    /// True once the hypotheses are ready (result()); then it does nothing more.
    bool advance(std::int64_t budget);
    bool done() const;
    /// Most probable first, as hypotheses() returns them; empty until done().
    const std::vector<Verified>& result() const { return result_; }

   private:
    const Localizer& localizer_;
    const Points2 points_;
    const VerifyQuery prepared_;
    const int count_, verified_;
    const PreparedQuery query_;
    std::unique_ptr<Candidates> candidates_;
    std::vector<Verified> result_;
  };

  /// Each of `poses` verified as verify() does, refined within `config`'s window instead of the localizer's
  /// (a pose carried by odometry is further off than a lattice pose); the local map's beams cast once.
  /// at_poses (when given): each pose's terms and probability where it is, before refining.
  std::vector<Verified> verify_all(const Points2& query_points, const Points2& query_origins,
                                   std::span<const Pose2> poses, const VerifyConfig& config,
                                   std::vector<Verified>* at_poses = nullptr) const;
  /// The same with the local map already prepared (a tracker verifies one local map at several steps' poses).
  std::vector<Verified> verify_all(const VerifyQuery& prepared, std::span<const Pose2> poses,
                                   const VerifyConfig& config, std::vector<Verified>* at_poses = nullptr) const;

  const LocalizerConfig& config() const { return config_; }
  /// The rotation that took the building map into its canonical frame [rad].
  double alignment_angle() const { return T_canonical_map_.theta; }
  /// Its wings' directions searched beside the axes (in the canonical frame) [rad].
  const std::vector<double>& wing_directions() const { return config_.dmm.extra_directions; }
  /// Time to prepare the building map [ms].
  double prepare_ms() const { return prepare_ms_; }

 private:
  Localizer(const Points2& map_points, const Points2& free_points, const LocalizerConfig& config);
  int free_conflicts(const Points2& query_points, const Pose2& T_map_query) const;
  Verified verify(const VerifyQuery& query, const Pose2& T_map_query) const;
  Verified verify(const VerifyQuery& query, const Pose2& T_map_query, const VerifyConfig& config,
                  Verified* at_pose = nullptr) const;
  /// One of locate()'s candidate poses: dMM's match, rescored with the map's free space.
  struct Candidate {
    DmmResult dmm;
    Pose2 T_map_query;
    int conflicts = 0;
    double score = 0;
    bool place = false;  ///< the best of its place: no candidate found before it lies within "elsewhere" of it
  };
  /// One search's distinct candidates as they are found, and the search's state between budgets.
  struct Candidates {
    Candidates(const Localizer& localizer, const PreparedQuery& query, const Vec2& centre, double min_share = 0);
    DmmSearch search;
    Vec2 centre;
    double min_share = 0;  ///< hypotheses()'s
    std::vector<Candidate> found;
    /// The two best rescored scores of distinct places so far [points]: a candidate with no more inliers than
    /// the second cannot change the answer's confidence (rescoring only subtracts), so it is the next search's
    /// bar.
    double first = -1e300, second = -1e300;
    bool done = false;
  };
  /// Goes on finding candidates for about `budget` of the search's work (0: to the end); true when it is done, its
  /// candidates (at most `candidates`) then sorted best rescored first.
  bool search_candidates(const Points2& query_points, Candidates& state, std::int64_t budget) const;
  /// The distinct candidates of one search (at most `candidates`), best rescored first.
  std::vector<Candidate> search_candidates(const Points2& query_points, const PreparedQuery& query,
                                           const Vec2& centre) const;
  /// The best `verified` candidates (config().verified when < 1) verified, distinct, at most `count`, most
  /// probable first (hypotheses()).
  std::vector<Verified> distinct_verified(const VerifyQuery& query, const std::vector<Candidate>& found, int count,
                                          int verified) const;
  /// The most probable of the best few candidates, verified (and verified again from starts around it); sets
  /// `chosen` to its index.
  Verified verify_best(const VerifyQuery& query, const std::vector<Candidate>& found, std::size_t& chosen) const;
  /// The margin of the answer (found[chosen]) over the other places: elsewhere_score, T_map_elsewhere and
  /// confidence.
  void set_margin(const std::vector<Candidate>& found, std::size_t chosen, const Vec2& centre,
                  Localization& out) const;

  LocalizerConfig config_;
  std::optional<GridMap> free_space_;  ///< the map, when it knows its free cells
  Pose2 T_canonical_map_;
  PreparedMap map_;
  VerifyMap verify_;  ///< the building map in its own frame, with its free cells
  double prepare_ms_ = 0.0;
};

}  // namespace partslam
