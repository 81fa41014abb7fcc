// How sure an answer is: by how much it beats the best answer that puts the query in another place. This margin
// is the confidence of every decision built on a match: `locate`, `match` and loop closures.
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

}  // namespace partslam
