// How sure an answer is, against the best answer that puts the query in another place: for a calibrated score
// (the verified dMM's probability, core/matching/verification.h) the probability that the best answer is right
// and that one is not; for a raw score (Eq. 1's inlier share) the margin between the two. This is the
// confidence of every decision built on a match: `locate`, `match` and loop closures.
#pragma once

#include <algorithm>
#include <cstddef>
#include <span>

#include "core/types.h"

namespace partslam {

/// What "another place" means for two stored map frames.
struct OtherPlace {
  double distance = 4.0;  ///< frames farther apart than this are another place [m]
  bool apart(const Vec2& a, const Vec2& b) const { return (a - b).norm() > distance; }
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

/// A calibrated decision at least this probable is reported as confident (`match`).
inline constexpr double kConfidentProbability = 0.5;

}  // namespace partslam
