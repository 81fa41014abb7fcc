#include "core/ranking/query.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "core/error.h"
#include "core/timing.h"

namespace partslam {
namespace {

// The answer's order: the ranking's (compare_rank; the stage score is the succinct stage's, rerank's tie-break),
// then the candidates' order (a serial ranking's stable order).
bool row_above(const QueryRow& a, const QueryRow& b) {
  const int c = compare_rank({a.tier, a.score, a.stage_score.value_or(0.0)},
                             {b.tier, b.score, b.stage_score.value_or(0.0)});
  return c != 0 ? c > 0 : a.candidate < b.candidate;
}

// This process's ranking as rows (candidates [first, first + n)), best first.
std::vector<QueryRow> rows_of(const Ranking& r, std::size_t first) {
  std::vector<QueryRow> rows(r.scores.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    QueryRow& row = rows[i];
    row.candidate = first + i;
    row.tier = r.tiers.empty() ? 0 : r.tiers[i];
    row.score = r.scores[i];
    if (!r.direct.empty()) row.pose = r.direct[i];
    if (!r.probability.empty()) row.probability = r.probability[i];
    if (!r.runner_up.empty()) row.runner_up = r.runner_up[i];
    if (!r.shortlist_scores.empty()) {
      row.stage_score = r.shortlist_scores[i];
    } else if (r.direct.empty()) {
      row.stage_score = r.scores[i];
    }
  }
  std::sort(rows.begin(), rows.end(), row_above);
  return rows;
}

// The best value among this process's candidates that are in another place than `best`: their verified
// probability (calibrated), else their inlier share: the rows it ranked with an exact direct match, and the
// ones a top-k ranking only bounded (scored again here, exactly, for their best one).
double best_elsewhere_here(const std::vector<QueryRow>& scored, std::span<const QueryCandidate> candidates,
                           const QueryCandidate& best, std::size_t first, const Ranker& ranker,
                           const MapView& query, const QueryRankOptions& o, bool calibrated) {
  const auto elsewhere = [&](const QueryCandidate& c) {
    return c.dataset != best.dataset || o.other_place.apart(c.T_world_map.translation(), best.T_world_map.translation());
  };
  double out = 0.0;
  std::vector<std::size_t> bounded;  // positions in this process's slice
  for (const QueryRow& r : scored) {
    if (!r.pose || !elsewhere(candidates[r.candidate])) continue;
    if (calibrated) {
      if (r.probability) out = std::max(out, *r.probability);  // rows rerank left unverified say nothing
    } else if (r.pose->exact) {
      out = std::max(out, r.pose->inlier_fraction);
    } else {
      bounded.push_back(r.candidate - first);
    }
  }
  if (!bounded.empty()) {
    std::sort(bounded.begin(), bounded.end());
    for (const auto& d : ranker.rank(query, bounded, {o.num_threads, 1}).direct)
      if (d && d->exact) out = std::max(out, d->inlier_fraction);
  }
  return out;
}

}  // namespace

QueryAnswer rank_query(const MethodSpec& method, const RankingConfig& config,
                       std::span<const QueryCandidate> candidates, const MapView& query,
                       const QueryRankOptions& o, const WorkSplit& split) {
  if (o.top < 1) throw InputError("query: top must be >= 1");
  if (candidates.empty()) throw InputError("query: no stored map to rank");
  if (split.size() > 1 && !method.traits.shardable)
    throw InputError("method '" + method.spec + "' cannot be split between processes (it learns from all stored "
                     "maps or shortlists among them); run it in one process");
  QueryAnswer answer;
  const auto [first, last] = split.slice(candidates.size());
  std::vector<MapView> mine;
  for (std::size_t i = first; i < last; ++i) mine.push_back(candidates[i].view);
  auto t0 = Clock::now();
  const std::unique_ptr<Ranker> ranker = make_ranker(method, config);
  ranker->prepare(mine, o.num_threads);
  answer.prepare_ms = ms_since(t0);
  std::vector<std::size_t> everyone(mine.size());
  std::iota(everyone.begin(), everyone.end(), std::size_t{0});
  const Ranking ranking = ranker->rank(query, everyone, {o.num_threads, static_cast<int>(o.top)});
  answer.prep_ms = ranking.prep_ms;
  answer.match_ms = ranking.match_ms;
  answer.ranked_here = mine.size();
  const std::vector<QueryRow> scored = rows_of(ranking, first);
  // Every process's best rows, merged in the serial order.
  const std::span<const QueryRow> sent(scored.data(), std::min(o.top, scored.size()));
  answer.rows = all_gather<QueryRow>(split, sent);
  std::sort(answer.rows.begin(), answer.rows.end(), row_above);
  answer.rows.resize(std::min(o.top, answer.rows.size()));
  if (answer.rows.empty() || !answer.rows.front().pose) return answer;
  const QueryRow& best = answer.rows.front();
  answer.calibrated = best.probability.has_value();
  const double here =
      best_elsewhere_here(scored, candidates, candidates[best.candidate], first, *ranker, query, o, answer.calibrated);
  std::vector<double> values = {answer.calibrated ? *best.probability : best.pose->inlier_fraction};
  for (double e : all_gather<double>(split, {&here, 1})) values.push_back(e);
  const auto everyone_elsewhere = [](std::size_t) { return true; };
  answer.confidence = answer.calibrated ? decision_probability(values, 0, everyone_elsewhere)
                                        : distinctiveness(values, 0, everyone_elsewhere);
  return answer;
}

CandidateChoice choose_candidates(const Submap& query, std::span<const Submaps* const> datasets,
                                  std::optional<std::size_t> own, double min_gap) {
  CandidateChoice out;
  for (std::size_t d = 0; d < datasets.size(); ++d) {
    for (std::size_t i = 0; i < datasets[d]->size(); ++i) {
      const Submap& m = (*datasets[d])[i];
      if (m.id == query.id) continue;
      if (own == d && std::abs(m.travel - query.travel) < min_gap) {
        ++out.too_recent;
        continue;
      }
      out.maps.push_back({d, i});
    }
  }
  return out;
}

}  // namespace partslam
