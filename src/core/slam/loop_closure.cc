#include "core/slam/loop_closure.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/matching/distinctiveness.h"
#include "core/ranking/ranking.h"
#include "core/matching/scan_matcher.h"
#include "core/slam/submap_graph.h"

namespace partslam {
namespace {

constexpr double kContextResolution = 0.1;  // context maps are downsampled to one point per cell [m]
constexpr PoseTolerance kConsistent{0.5, 0.1};  // a hypothesis the optimised graph agrees with

// Map i with the submaps within `context` of travel around it, in its frame, one point per cell.
Points2 context_points(const Submaps& maps, std::size_t i, double context) {
  Points2 all = maps[i].points;
  const Pose2 T_map_world = maps[i].T_world_map.inverse();
  for (std::size_t j = 0; j < maps.size(); ++j) {
    if (j == i || std::abs(maps[j].travel - maps[i].travel) > context) continue;
    const Points2 p = transform(T_map_world * maps[j].T_world_map, maps[j].points);
    all.insert(all.end(), p.begin(), p.end());
  }
  return voxel_downsample(all, kContextResolution);
}

// The drift gate between query q and match m: a true match lies within `translation` [m] and `turn` [rad] of the
// stored relative pose `prior`, bounds that grow with the travel between the two. `off` when it is turned off.
struct DriftGate {
  bool off = false;
  Pose2 prior;
  double translation = 0, turn = 0;
};

DriftGate drift_gate(const Submaps& maps, std::size_t q, std::size_t m, const LoopClosureConfig& c) {
  const double gap = std::abs(maps[q].travel - maps[m].travel);
  return {c.drift_offset == 0 && c.drift_rate == 0, maps[m].T_world_map.inverse() * maps[q].T_world_map,
          c.drift_offset + c.drift_rate * gap, c.drift_turn + c.drift_turn_rate * gap};
}

// False when the hypothesis lies outside the drift gate around the stored relative pose.
bool within_drift(const Submaps& maps, std::size_t q, std::size_t m, const Pose2& T_match_query,
                  const LoopClosureConfig& c) {
  const DriftGate g = drift_gate(maps, q, m, c);
  return g.off || ((g.prior.translation() - T_match_query.translation()).norm() <= g.translation &&
                   std::abs(wrap_angle(g.prior.theta - T_match_query.theta)) <= g.turn);
}

// False when no pose dMM can return (translations within its window) passes the drift gate.
bool may_pass_drift(const Submaps& maps, std::size_t q, std::size_t m, const DmmConfig& dmm,
                    const LoopClosureConfig& c) {
  const DriftGate g = drift_gate(maps, q, m, c);
  return g.off || dmm.linear_window <= 0 ||  // no gate, or no window
         g.prior.translation().norm() <= g.translation + std::sqrt(2.0) * dmm.linear_window;
}

// The hypotheses of one query from its ranking: every candidate dMM verified within the drift gate, then in
// context.
std::vector<LoopClosure> hypotheses(const Submaps& maps, std::size_t q, const std::vector<std::size_t>& candidates,
                                    const Ranking& r, const LoopClosureConfig& c) {
  std::vector<LoopClosure> out;
  for (std::size_t j = 0; j < candidates.size(); ++j) {
    if (!r.direct.at(j) || r.direct[j]->inlier_fraction < c.min_score) continue;
    if (!within_drift(maps, q, candidates[j], r.direct[j]->T_map_query, c)) continue;
    const double p = j < r.probability.size() && r.probability[j] ? *r.probability[j] : -1.0;
    out.push_back({q, candidates[j], r.direct[j]->T_map_query, r.direct[j]->inlier_fraction, 0.0, 0.0, p});
  }
  std::stable_sort(out.begin(), out.end(), [](const LoopClosure& a, const LoopClosure& b) { return a.score > b.score; });
  if (c.context > 0 && !out.empty()) {
    ScanMatcherConfig verify;
    verify.angular_window = 0.1;
    const LikelihoodField field(context_points(maps, q, c.context), verify.resolution, verify.sigma);
    for (LoopClosure& h : out) {  // the match's context placed in the query's frame, refined around dMM's pose
      const ScanMatch m = match_scan(field, context_points(maps, h.match, c.context), h.T_match_query.inverse(), verify);
      h.T_match_query = m.pose.inverse();
      h.context_score = m.score;
    }
  }
  std::vector<double> values;
  for (const LoopClosure& h : out) values.push_back(c.context > 0 ? h.context_score : h.score);
  const OtherPlace& other = c.other_place;
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i].confidence = distinctiveness(values, i, [&](std::size_t j) {
      return other.apart(maps[out[j].match].T_world_map.translation(), maps[out[i].match].T_world_map.translation());
    });
  }
  return out;
}

// Two checks, each taking 1 of confidence from the hypotheses that fail it (one that fails both ranks below one
// that fails either). First, a hypothesis of positive confidence must belong to the largest pairwise-consistent
// group (closure_consistency.h). Then a pose graph of the stored frames (consecutive submaps joined by their stored
// relative pose) and every hypothesis of positive confidence left (Cauchy loss) is optimised: a hypothesis whose
// pose the optimised frames disagree with by more than 0.5 m or 0.1 rad fails; with graph_pose one that passed
// both takes the optimised relative pose.
void judge_agreement(const Submaps& maps, std::vector<LoopClosure>& closures, const LoopClosureConfig& c) {
  if (c.consistency.enabled) {
    std::vector<std::size_t> positive;
    std::vector<LoopClosure> group;
    for (std::size_t k = 0; k < closures.size(); ++k)
      if (closures[k].confidence > 0) positive.push_back(k), group.push_back(closures[k]);
    const std::vector<bool> kept = consistent_closures(maps, group, c.consistency, c.num_threads);
    for (std::size_t k = 0; k < positive.size(); ++k)
      if (!kept[k]) closures[positive[k]].in_group = false, closures[positive[k]].confidence -= 1.0;
  }
  if (!c.graph_check || maps.size() < 2) return;
  std::vector<LoopClosure> graph;
  for (const LoopClosure& l : closures)
    if (l.confidence > 0) graph.push_back(l);
  const std::vector<Pose2> solved = optimize_submap_graph(maps, graph);
  for (LoopClosure& l : closures) {
    const Pose2 T = solved[l.match].inverse() * solved[l.query];
    if (!kConsistent.accepts(T, l.T_match_query)) l.graph_agrees = false, l.confidence -= 1.0;
    else if (l.in_group && c.graph_pose) l.T_match_query = T;
  }
}

}  // namespace

void validate(const LoopClosureConfig& c) {
  if (!(c.min_travel_gap >= 0.0) || !std::isfinite(c.min_travel_gap))
    throw InputError("loop closure config: min_travel_gap must be a finite number >= 0 [m]");
  if (!(c.other_place.distance > 0.0) || !std::isfinite(c.other_place.distance))
    throw InputError("loop closure config: other_place must be a positive finite number [m]");
  if (!(c.min_score >= 0.0 && c.min_score <= 1.0))
    throw InputError("loop closure config: min_score must be in [0, 1]");
  if (c.num_threads < 1 || c.num_threads > 1024)
    throw InputError("loop closure config: num_threads must be in [1, 1024], got " +
                     std::to_string(c.num_threads));
  if (!(c.context >= 0.0 && c.context <= 100.0))
    throw InputError("loop closure config: context must be in [0, 100] m");
  for (const double v : {c.drift_offset, c.drift_rate, c.drift_turn, c.drift_turn_rate})
    if (!(v >= 0.0) || !std::isfinite(v))
      throw InputError("loop closure config: drift_offset, drift_rate, drift_turn, drift_turn_rate must be finite and >= 0");
  validate_nested("loop closure config", "consistency", [&] { validate(c.consistency); });
  // The method is checked here, not when the closures are sought: `slam` would find a bad one only after its
  // front end, and a settings file's reader names its file for what validate throws.
  const MethodSpec method = parse_method_spec(c.method);
  if (!method.traits.gives_pose)
    throw InputError("loop closure config: method '" + c.method +
                     "' gives no dMM pose: use rerank:R[:SPEC] or dmm");
  if (method.traits.needs_parts)
    throw InputError("loop closure config: method '" + c.method +
                     "' needs CPD parts; use a point-based shortlist");
}

namespace {

// Every process's hypotheses, in query order (each query's as found); a LoopClosure is a plain record.
std::vector<LoopClosure> gather_hypotheses(const std::vector<LoopClosure>& mine, const WorkSplit& split) {
  std::vector<LoopClosure> out = all_gather<LoopClosure>(split, mine);
  std::stable_sort(out.begin(), out.end(), [](const LoopClosure& a, const LoopClosure& b) { return a.query < b.query; });
  return out;
}

}  // namespace

FailedChecks failed_checks(const std::vector<LoopClosure>& closures) {
  FailedChecks f;
  for (const LoopClosure& l : closures) f.outside_group += !l.in_group, f.at_odds_with_graph += !l.graph_agrees;
  return f;
}

std::vector<LoopClosure> find_loop_closures(const Submaps& maps, const LoopClosureConfig& config,
                                            const Progress& progress, const WorkSplit& split) {
  validate(config);
  const MethodSpec method = parse_method_spec(config.method);
  // Off by default: verifying dMM's candidates doubles the time of `slam` and the SLAM bench measured no gain
  // (docs/NOTES.md, "Verifying a match", loops).
  RankingConfig ranking;
  ranking.verify_dmm = config.verify_dmm;
  // DmmConfig's search (four rotation families, +- 3 degrees each), not the ranking's wider one: the SLAM bench
  // was measured with it (the drift gate bounds a closure's turn anyway).
  ranking.dmm = DmmConfig{};
  const std::unique_ptr<Ranker> ranker = make_ranker(method, ranking);
  std::vector<MapView> views;
  for (const Submap& m : maps) views.push_back({&m.points, nullptr, &m.origins});
  ranker->prepare(views, config.num_threads, progress);
  std::vector<std::vector<LoopClosure>> per_query(maps.size());
  std::vector<std::size_t> mine;  // this process's queries: every size-th one
  for (std::size_t q = static_cast<std::size_t>(split.rank()); q < maps.size(); q += static_cast<std::size_t>(split.size()))
    mine.push_back(q);
  parallel_for(
      mine.size(), config.num_threads,
      [&](std::size_t i) {
        const std::size_t q = mine[i];
        std::vector<std::size_t> candidates;
        for (std::size_t g = 0; g < q; ++g)
          if (maps[g].travel <= maps[q].travel - config.min_travel_gap &&
              (!config.gate_candidates || may_pass_drift(maps, q, g, ranking.dmm, config)))
            candidates.push_back(g);
        if (candidates.empty()) return;
        // A rerank's hypotheses are its top R: its first stage ranks only those (through the grid index when
        // the log has index_min_maps submaps or more); dMM alone matches every candidate.
        const Ranking r = ranker->rank(views[q], candidates, {1, method.traits.shortlist});
        per_query[q] = hypotheses(maps, q, candidates, r, config);
      },
      "loop closures", progress);
  std::vector<LoopClosure> out;
  for (auto& h : per_query) out.insert(out.end(), h.begin(), h.end());
  if (split.size() > 1) out = gather_hypotheses(out, split);
  judge_agreement(maps, out, config);
  return out;
}

}  // namespace partslam
