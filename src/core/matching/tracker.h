// Global localisation over travel (docs/NOTES.md, "Tracking"): where a robot is in a building map, from the
// local maps it builds as it drives and the motion between them, keeping several hypotheses until the motion
// tells them apart (clustered particle filters, Milstein et al. 2002; AMCL's global localisation, with a few
// verified poses instead of thousands of particles).
//
// Each step takes a local map (points and laser origins in its own frame, core/maps/submap.h) and its frame in
// the odometry's frame (T_odom_map: the robot's own motion estimate, odometry or scan matching). Then:
//   1. every hypothesis (a pose of the local map in the building map) is carried by the odometry's motion
//      since the last step and verified there (Localizer::verify_all: refined within track_window /
//      track_angle, with the same-place probability of core/matching/verification.h);
//   2. its weight is multiplied by that probability (at least floor_probability: one local map that matches
//      badly, a person in the way, does not end the true hypothesis); a "none of these" weight, multiplied by
//      other_probability each step, stands for "the robot is somewhere no hypothesis is" and keeps the shares
//      honest when every hypothesis fits badly;
//   3. while not localised (the first step, and every search_every steps), the global search's best distinct
//      poses (Localizer::hypotheses, candidates above search_min_share of the best one's inliers) join as new
//      hypotheses, each with the none weight's share times its
//      probability (the newborn are also weighed on the last weighed_back local maps since the robot was last lost,
//      where the odometry says they were: evidence for the comparison of 4, not for their weight);
//      hypotheses that meet merge into the heavier, those below drop_share of the heaviest drop, at most
//      max_hypotheses stay; the none weight's share never falls below min_none_share (odds of 99 at most: a
//      kidnapped pose is not immune by what it once fitted);
//   4. a hypothesis is declared when a global search begun on a later local map than the one it was found on has ended
//      (one starts as soon as it holds declare_share: a search on a local map mostly outside the map finds only
//      look-alikes; docs/NOTES.md, "A declaration waits for a later search"), and its share of the weight (the none
//      weight included) reaches declare_share on declare_steps consecutive steps on which it fits (probability at least
//      declare_probability; a step on which it would but for its match having moved it beyond claim_shift is skipped,
//      not a break) and the steps since each rival place's birth weighed it above that rival by the same odds
//      (declare_share / (1 - declare_share)): a rival the search found only later (a corridor's mirror image, where the
//      true place fits as well) starts from the none weight's share, so its small weight says when it was found, not
//      that it fits worse (docs/NOTES.md, "Rivals found later"); the others are still carried (they may win back); when
//      the declared one's probability stays below lost_probability for lost_steps steps in a row the robot was carried
//      elsewhere (kidnapped) or the map no longer holds the place: "lost", every hypothesis is dropped and the search
//      starts again at once; the pose it was lost at, carried on by the odometry, joins as a newborn on the first later
//      step where it fits with declare_probability (a robot that was not carried anywhere, whose local maps a crowd or
//      turning on the spot spoiled for two steps, is found where it was without waiting for a search begun on a spoiled
//      local map).
// Nothing is claimed (the status reads "searching", the declared hypothesis is kept and declared again at
// once when it fits again with declare_share, ahead of its rivals; if it fits again short of them, it is given
// up then: "lost", the hypotheses kept, until one is declared) on a step where the declared pose fits
// below lost_probability, lies where the building map saw little of the local map (query seen share below
// min_seen: a room the map does not hold, or a pose drifted off; such a hypothesis is weighed as the none
// weight is, the local map says nothing of it; it is given up as above once its share falls below
// declare_share, others having taken the weight), or was moved by the match more than claim_shift from where
// the odometry carried it. Such a move is taken only when the match is move_gain times as probable as the
// odometry's pose (along a corridor it fits about as well anywhere).
//   5. a step's time is bounded (search_budget): a global search spends at most that much of its dMM search
//      per step and goes on over the next steps (a step waits for no whole search); its hypotheses, found for
//      the local map it started on, are carried by the odometry since then and weighed on the step it ends,
//      as the carried ones are (refined within track_window). A search is dropped when the tracker declares a
//      pose, and when it is lost (a new one starts on that step's local map).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/matching/localizer.h"
#include "core/types.h"

namespace partslam {

struct TrackerConfig {
  int hypotheses = 8;            ///< the global search's distinct poses taken per search, in [1, 100]
  /// the global search's best-scoring candidates verified to find them (locate verifies 16; 8 found the same
  /// hypotheses on the tuning split at two thirds of the time)
  int search_verified = 8;
  int max_hypotheses = 16;       ///< hypotheses kept at most, in [1, 1000]
  double track_window = 0.5;     ///< a carried hypothesis is refined within +- this [m] ...
  double track_angle = 0.1;      ///< ... and +- this [rad]
  double merge_distance = 0.5;   ///< hypotheses this close [m] ...
  double merge_angle = 10.0 * std::numbers::pi / 180;  ///< ... and turned by no more than this are one [rad]
  double floor_probability = 0.001;  ///< a step weighs a hypothesis by its probability, at least this
  double other_probability = 0.01;   ///< the "none of these" weight's factor per step
  double declare_share = 0.95;      ///< share of the weight that declares a hypothesis ...
  int declare_steps = 2;            ///< ... on this many consecutive steps
  double lost_probability = 0.005;  ///< the declared hypothesis's probability below this ...
  int lost_steps = 2;               ///< ... on this many consecutive steps: lost
  double drop_share = 1e-3;         ///< hypotheses below this share of the heaviest are dropped
  /// a step is evidence (and a pose is claimed) when some hypothesis sees this share of the local map; 0.4
  /// (docs/NOTES.md, "A declaration waits for a later search": at 0.3 a pose carried by harsh odometry out of aces's
  /// map was claimed 0.36 m off on a local map 30 % in the map)
  double min_seen = 0.4;
  /// while not localised, the global search runs every this many steps (and whenever there is no hypothesis)
  int search_every = 3;
  double min_none_share = 0.01;     ///< the none weight's share never falls below this (odds of 99 at most)
  /// no claim on a step whose match moved the declared hypothesis further than this from where the odometry
  /// carried it (a local map that fits the map a few degrees off)
  PoseTolerance claim_shift{0.25, 2.5 * std::numbers::pi / 180};
  /// a match that moves a hypothesis beyond claim_shift is taken only when it is this many times as probable
  /// as the odometry's pose; else the odometry's pose stays (a corridor's length)
  double move_gain = 2.0;
  /// a hypothesis counts towards being declared only on steps where its probability reaches this
  /// (0.03: docs/NOTES.md, "A lower bar to declare"; 0.05 held back intel's and fhw's harsh-odometry starts)
  double declare_probability = 0.03;
  /// a carried hypothesis's match moves it at most corridor_slack along a direction the local map's walls do
  /// not fix (VerifyConfig::keep_along_ratio: a bare corridor's axis, where the match slides; the rest of the
  /// move is the odometry's), in [0, 1); 0: the match moves it freely. 0.1 and 0.1 m (docs/NOTES.md, "A
  /// corridor's axis kept from the odometry": infinite-corridor's slides and freiburg-campus's mild wrong steps
  /// went, 8 -> 1; chosen looking at those two validation buildings, so their figures are not independent)
  double corridor_ratio = 0.1;
  double corridor_slack = 0.1;  ///< [m], in [0, 5]
  /// The global search's work per step (DmmSearch::next's budget, about a millisecond per million): a search
  /// longer than that goes on over the next steps (step 5 above), so that no step waits for a whole search;
  /// 0: every search within its step. 4e7 (docs/NOTES.md, "A step's time bounded": the step p95 under 50 ms
  /// where freiburg-campus and fhw took 60-96 ms; their travel to localised grows by a step or three).
  int search_budget = 40'000'000;
  /// The global search looks for candidates with more than this share of the best one's inliers only
  /// (Localizer::hypotheses' min_share), in [0, 1). 0.7 (docs/NOTES.md, "A step's time bounded": the second
  /// candidate cost two thirds of a search; the same localised starts, wrong steps and kidnappings on every
  /// building, a few more steps claimed on intel, fhw and seattle).
  double search_min_share = 0.7;
  /// The newborn are weighed on this many earlier local maps too (step 3 above), in [0, 20] (1 / 2 / 3 tried: 2
  /// gave intel harsh, a tuning log, 28 of 29 starts where 1 gave 27; 3 brought wrong steps back on
  /// infinite-corridor then, docs/NOTES.md, "Rivals found later"; since the corridor rule, 3 gives the same figures
  /// on the tuning logs and 0 wrong steps everywhere, with more starts localised on freiburg-campus and
  /// infinite-corridor: "Three local maps back").
  int weighed_back = 3;
};

/// Throws InputError naming the field.
void validate(const TrackerConfig& config);

/// The log of how much more the steps both hypotheses lived through weighed `a` than `b`: a and b hold what
/// each step multiplied a hypothesis's weight by (log, oldest first, the last entry this step's), so the
/// shorter one's span is compared with the same steps of the longer.
double shared_evidence_log_ratio(std::span<const double> a, std::span<const double> b);

enum class TrackStatus { kSearching, kLocalised, kLost };
/// "searching", "localised", "lost".
const char* to_string(TrackStatus status);

struct TrackHypothesis {
  Pose2 T_map_query;        ///< the local map's pose in the building map
  double probability = 0;   ///< this step's same-place probability there
  double share = 0;         ///< its share of the weight (the none weight included), in [0, 1]
  int age = 0;              ///< steps it has been carried
};

struct TrackStep {
  TrackStatus status = TrackStatus::kSearching;
  /// localised: the declared hypothesis (T_map_query, its share is the declared probability); otherwise the
  /// heaviest one, when there is any
  bool has_pose = false;
  TrackHypothesis best;
  std::vector<TrackHypothesis> hypotheses;  ///< heaviest first
  double none_share = 1;    ///< the "none of these" weight's share
  bool searched = false;    ///< the global search ran this step
  bool evidence = true;     ///< the local map was weighed (see min_seen)
  double time_ms = 0;       ///< this step [ms]
};

class Tracker {
 public:
  /// Keeps a reference to the localizer (it must outlive the tracker). Throws InputError for a bad config.
  Tracker(const Localizer& localizer, const TrackerConfig& config = {});

  /// One local map: its points and laser origins in its own frame (canonical when the localizer's dMM is) and
  /// its frame in the odometry frame. Throws InputError for an empty local map or non-finite values.
  TrackStep step(const Points2& points, const Points2& origins, const Pose2& T_odom_map);

  /// Forget everything (a new run).
  void reset();

 private:
  struct Hypothesis {
    int id = 0;  ///< stays with the hypothesis through merges and sorting
    Pose2 T_map_query;
    double log_weight = 0;
    double probability = 0;
    double seen = 0;  ///< this step's query seen share there (core/matching/verification.h)
    bool moved = false;  ///< this step's match moved it by more than claim_shift
    int age = 0;
    /// the step whose local map the search that found it began on: it is declared only after a search begun on
    /// a later local map has ended (step 4); -1: the pose the robot was lost at, compared with searches before
    std::ptrdiff_t found = 0;
    /// what each step since its birth multiplied its weight by (log; the birth search's probability first, at
    /// most kHistory steps): the evidence it and a rival born later both saw
    std::vector<double> history;
  };
  static constexpr std::size_t kHistory = 256;
  bool ahead_of_rivals(const Hypothesis& h) const;
  /// a search begun on a later local map than the one `h` was found on has ended (step 4)
  bool confirmed(const Hypothesis& h) const { return searched_on_ > h.found; }
  std::vector<Verified> verify_carried(const Localizer::VerifyQuery& prepared, const std::vector<Pose2>& poses,
                                       bool track_window) const;
  double weight_factor(const Verified& v) const;
  void normalise();
  void merge_and_drop();
  bool update_status(bool evidence);
  const Hypothesis* find(int id) const;
  TrackStep report(bool searched, bool evidence, double time_ms) const;

  const Localizer& localizer_;
  TrackerConfig config_;
  std::vector<Hypothesis> hypotheses_;
  double none_log_weight_ = 0;
  bool has_last_ = false;
  Pose2 T_odom_last_;
  TrackStatus status_ = TrackStatus::kSearching;
  int next_id_ = 0;
  int declared_ = -1;         ///< id of the declared hypothesis (localised)
  int dominant_ = -1;         ///< id of the heaviest one while it holds declare_share ...
  int dominant_steps_ = 0;    ///< ... on this many consecutive steps
  int weak_steps_ = 0;        ///< consecutive steps the declared one fell below lost_probability
  bool blind_ = false;  ///< the declared one fits badly or left the map's seen cells: no claim until it fits
  int steps_since_search_ = 0;  ///< steps since the last global search
  struct Previous {
    Localizer::VerifyQuery prepared;  ///< its local map, prepared for verification
    Pose2 motion;                     ///< the odometry's motion from it to the next step
  };
  std::vector<Previous> previous_;  ///< the last weighed_back steps' local maps, oldest first
  /// Where the declared hypothesis was when the robot was lost, carried on by the odometry since, until it fits a
  /// later local map or a pose is declared (docs/NOTES.md, "Lost without being carried").
  std::optional<Pose2> lost_pose_;
  std::unique_ptr<Localizer::HypothesisSearch> pending_;  ///< a global search under way (search_budget)
  std::size_t pending_step_ = 0;  ///< the step whose local map it searches ...
  Pose2 T_odom_pending_;          ///< ... and that step's T_odom_map
  std::size_t steps_ = 0;         ///< steps since the last reset
  /// the step whose local map the last finished search began on (-1: none yet)
  std::ptrdiff_t searched_on_ = -1;
};

}  // namespace partslam
