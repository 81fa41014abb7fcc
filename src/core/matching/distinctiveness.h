// How sure an answer is, against the best answer that puts the query in another place: for a calibrated score
// (the verified dMM's probability, core/matching/verification.h) the probability that the best answer is right
// and that one is not; for a raw score (Eq. 1's inlier share) the margin between the two. This is the
// confidence of every decision built on a match: `locate`, `match` and loop closures.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <optional>
#include <span>

#include "core/types.h"

namespace partslam {

/// What "another place" means, for every decision that weighs an answer against the best one elsewhere: the
/// loop closures' and `match`'s confidence (two stored map frames) and `locate`'s (two poses of one local map).
struct OtherPlace {
  double distance = 4.0;  ///< at least this far apart is another place [m] ...
  double angle = std::numbers::pi;  ///< ... and, for two poses of one local map, so is a turn by more than this [rad]
  /// Two stored map frames, each in its own map's canonical orientation: only their positions compare.
  bool apart(const Vec2& a, const Vec2& b) const { return (a - b).norm() >= distance; }
  /// Two poses of one local map whose centre is `centre` in its own frame: where they put the centre, and the turn.
  bool apart(const Pose2& a, const Pose2& b, const Vec2& centre) const {
    return (a * centre - b * centre).norm() >= distance || std::abs(wrap_angle(a.theta - b.theta)) > angle;
  }
};

/// scores[best] minus the highest scores[j] over the j != best that elsewhere(j) says put the query in another
/// place; scores[best] itself when there is none.
template <typename Elsewhere>
double distinctiveness(std::span<const double> scores, std::size_t best, Elsewhere&& elsewhere) {
  bool any = false;
  double other = 0.0;
  for (std::size_t j = 0; j < scores.size(); ++j) {
    if (j == best || !elsewhere(j)) continue;
    other = any ? std::max(other, scores[j]) : scores[j];
    any = true;
  }
  return scores[best] - (any ? other : 0.0);
}

/// A decision's confidence from calibrated probabilities: probabilities[best] * (1 - the highest
/// probabilities[j] over the j != best that elsewhere(j) says put the query in another place), the chance that
/// the best answer is the same place and the best other place is not (as if independent);
/// probabilities[best] itself when there is no other place.
template <typename Elsewhere>
double decision_probability(std::span<const double> probabilities, std::size_t best, Elsewhere&& elsewhere) {
  double other = 0.0;
  for (std::size_t j = 0; j < probabilities.size(); ++j)
    if (j != best && elsewhere(j)) other = std::max(other, probabilities[j]);
  return probabilities[best] * (1.0 - other);
}

/// When an answer is reported as confident: the one rule of `match`, `locate` and the relocalisation bench. A
/// margin over the best other place says the answer is unique; where calibrated, a probability says it is the
/// place (on buildings other than the tuning ones, unique answers outside the map were common).
struct ConfidenceRule {
  /// A margin (Eq. 1's inlier share over the best other place's) at least this: chosen on fr079, the lowest with
  /// no wrong answer there (docs/NOTES.md, "Locate") ...
  double min_margin = 0.2;
  /// ... and, where the answer's own same-place probability is calibrated (free space on both sides), at least
  /// this: chosen on fr079, above every wrong or out-of-map answer's probability there (at most 0.023 then, 0.004
  /// with the corner-weighted terms; docs/NOTES.md, "Corner-weighted terms").
  double min_probability = 0.025;
  /// A calibrated decision (decision_probability) at least this probable.
  double min_decision = 0.5;

  /// An answer with its margin and, where calibrated, its same-place probability (`locate`).
  bool confident(double margin, std::optional<double> probability) const {
    return margin >= min_margin && (!probability || *probability >= min_probability);
  }
  /// A ranking's answer, whose confidence is a decision probability when calibrated, else a margin (`match`).
  bool confident_answer(double confidence, bool calibrated) const {
    return confidence >= (calibrated ? min_decision : min_margin);
  }
};

}  // namespace partslam
