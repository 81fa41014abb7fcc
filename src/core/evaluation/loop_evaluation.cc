#include "core/evaluation/loop_evaluation.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/error.h"

namespace partslam {

void validate(const LoopTruthConfig& c) {
  const std::pair<double, const char*> positive[] = {{c.radius, "radius"},
                                                     {c.max_translation_error, "max_translation_error"},
                                                     {c.max_rotation_error, "max_rotation_error"}};
  for (const auto& [v, name] : positive)
    if (!(v > 0) || !std::isfinite(v))
      throw InputError(std::string("loop truth config: ") + name + " must be finite and > 0, got " + std::to_string(v));
  if (!(c.min_travel_gap >= 0) || !std::isfinite(c.min_travel_gap))
    throw InputError("loop truth config: min_travel_gap must be finite and >= 0, got " + std::to_string(c.min_travel_gap));
}

LoopEvaluation evaluate_loop_closures(const std::vector<LoopClosure>& closures, const Submaps& maps,
                                      const std::vector<std::optional<Pose2>>& truth, const LoopTruthConfig& c) {
  validate(c);
  if (truth.size() != maps.size()) throw InputError("loop evaluation: one true frame per map is needed");
  auto same_place = [&](std::size_t q, std::size_t g) {
    return truth[q] && truth[g] && maps[q].travel - maps[g].travel >= c.min_travel_gap &&
           (truth[q]->translation() - truth[g]->translation()).norm() <= c.radius;
  };
  LoopEvaluation e;
  for (std::size_t q = 0; q < maps.size(); ++q) {
    std::size_t pairs = 0;
    for (std::size_t g = 0; g < q; ++g) pairs += same_place(q, g);
    e.relevant_pairs += pairs;
    e.relevant_queries += pairs > 0;
  }
  // A hypothesis is correct when its pose is (whatever the distance of the two frames); recall counts the
  // correct ones between frames of the same place.
  struct Judged {
    double confidence;
    bool correct, relevant;
    std::size_t query;
  };
  std::vector<Judged> judged;
  e.verdicts.assign(closures.size(), -1);
  for (std::size_t i = 0; i < closures.size(); ++i) {
    const LoopClosure& h = closures[i];
    if (!truth.at(h.query) || !truth.at(h.match)) continue;
    const Pose2 T = truth[h.match]->inverse() * *truth[h.query];
    const bool correct = PoseTolerance{c.max_translation_error, c.max_rotation_error}.accepts(T, h.T_match_query);
    e.verdicts[i] = correct ? 1 : 0;
    judged.push_back({h.confidence, correct, correct && same_place(h.query, h.match), h.query});
  }
  e.hypotheses = judged.size();
  std::stable_sort(judged.begin(), judged.end(), [](const Judged& a, const Judged& b) { return a.confidence > b.confidence; });
  std::size_t tp = 0, found = 0;
  std::vector<bool> closed(maps.size(), false);
  std::size_t closed_queries = 0;
  bool perfect = true;
  for (std::size_t k = 0; k < judged.size(); ++k) {
    tp += judged[k].correct;
    found += judged[k].relevant;
    if (judged[k].relevant && !closed[judged[k].query]) closed[judged[k].query] = true, ++closed_queries;
    perfect = perfect && judged[k].correct;
    if (k + 1 < judged.size() && judged[k + 1].confidence == judged[k].confidence) continue;  // one point per threshold
    const double precision = static_cast<double>(tp) / static_cast<double>(k + 1);
    const double recall = e.relevant_pairs ? static_cast<double>(found) / static_cast<double>(e.relevant_pairs) : 0.0;
    e.curve.push_back({judged[k].confidence, precision, recall});
    if (precision + recall > 0) e.max_f1 = std::max(e.max_f1, 2 * precision * recall / (precision + recall));
    if (perfect) {
      e.recall_at_full_precision = recall;
      e.confidence_at_full_precision = judged[k].confidence;
      e.query_recall_at_full_precision =
          e.relevant_queries ? static_cast<double>(closed_queries) / static_cast<double>(e.relevant_queries) : 0.0;
    }
  }
  e.correct = tp;
  return e;
}

}  // namespace partslam
