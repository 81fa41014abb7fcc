#include "core/matching/localizer.h"

#include <algorithm>
#include <cstdio>
#include <cmath>

#include "core/error.h"
#include "core/maps/manhattan.h"
#include "core/matching/distinctiveness.h"
#include "core/maps/scan.h"
#include "core/timing.h"

namespace partslam {

DmmConfig localizer_dmm_config() {
  DmmConfig config = dmm_config_for_dictionary();
  config.canonical_turns = 8;
  return config;
}

void validate(const LocalizerConfig& c) {
  validate(c.dmm);
  validate(c.verify);
  if (!(c.elsewhere.distance >= 0.0 && c.elsewhere.distance <= 100.0))
    throw InputError("localizer: elsewhere_distance must be in [0, 100] m");
  if (!(c.candidate_distance > 0.0 && c.candidate_distance <= c.elsewhere.distance))
    throw InputError("localizer: candidate_distance must be in (0, elsewhere_distance]");
  if (!(c.elsewhere.angle >= 0.0 && c.elsewhere.angle <= std::numbers::pi))
    throw InputError("localizer: elsewhere_angle must be in [0, pi] rad");
  if (c.candidates < 2 || c.candidates > 100) throw InputError("localizer: candidates must be in [2, 100]");
  if (!(c.free_weight >= 0.0 && c.free_weight <= 100.0)) throw InputError("localizer: free_weight must be in [0, 100]");
  if (!(c.neighbourhood >= 0.0 && c.neighbourhood <= 100.0))
    throw InputError("localizer: neighbourhood must be in [0, 100] m");
  if (c.verified < 1 || c.verified > 100) throw InputError("localizer: verified must be in [1, 100]");
  if (!(c.restart_distance >= 0.0 && c.restart_distance <= 10.0))
    throw InputError("localizer: restart_distance must be in [0, 10] m");
  if (!(c.wall_direction_share >= 0.0 && c.wall_direction_share <= 1.0))
    throw InputError("localizer: wall_direction_share must be in [0, 1]");
  if (!(c.wall_direction_length >= 0.0 && c.wall_direction_length <= 1e6))
    throw InputError("localizer: wall_direction_length must be in [0, 1e6] m");
}

namespace {

// Centres of the map's free cells, one per verification cell at most (every k-th cell along each axis when
// the map's cells are finer).
Points2 free_points(const GridMap& map, double resolution) {
  const int step = std::max(1, static_cast<int>(std::lround(resolution / map.resolution)));
  Points2 out;
  for (int row = 0; row < map.height; row += step)
    for (int column = 0; column < map.width; column += step)
      if (map.at(column, row) == CellState::kFree) out.push_back(map.cell_centre(column, row));
  return out;
}

}  // namespace

Localizer::Localizer(const GridMap& map, const LocalizerConfig& config)
    : Localizer(occupied_points(map), free_points(map, config.verify.resolution), config) {
  free_space_ = map;
}

Localizer::Localizer(const Points2& map_points, const LocalizerConfig& config)
    : Localizer(map_points, Points2{}, config) {}

Localizer::Localizer(const Points2& map_points, const Points2& free, const LocalizerConfig& config)
    : config_(config) {
  validate(config_);
  if (map_points.empty()) throw InputError("localizer: the building map has no occupied cell");
  const auto t0 = Clock::now();
  for (const Vec2& p : map_points) {
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() > kMaxCoordinate)
      throw InputError("localizer: building map points must be finite and within " + std::to_string(kMaxCoordinate) + " m");
  }
  if (config_.dmm.canonical) T_canonical_map_ = {0.0, 0.0, manhattan_angle(map_points)};
  const Points2 canonical = transform(T_canonical_map_, map_points);
  if (config_.dmm.canonical && config_.wall_direction_share > 0.0) {
    WallDirectionConfig walls;
    walls.min_share = config_.wall_direction_share;
    walls.min_length = config_.wall_direction_length;
    config_.dmm.extra_directions = wall_directions(canonical, walls);
  }
  map_ = prepare_map(canonical, config_.dmm);
  verify_ = VerifyMap::with_free_space(map_points, free, config_.verify);
  prepare_ms_ = ms_since(t0);
}

// Query points at T_map_query on cells the map saw free that are not inliers (no occupied cell of the dMM grid
// within its dilation).
int Localizer::free_conflicts(const Points2& query_points, const Pose2& T_map_query) const {
  if (!free_space_ || config_.free_weight == 0.0) return 0;
  const GridMap& m = *free_space_;
  const Pose2 T_cells_query = m.origin.inverse() * T_map_query;
  const Pose2 T_canonical_query = T_canonical_map_ * T_map_query;
  int conflicts = 0;
  for (const Vec2& p : query_points) {
    if (map_.grid.at(T_canonical_query * p)) continue;
    const Vec2 c = T_cells_query * p / m.resolution;
    const double column = std::floor(c.x()), row = std::floor(c.y());
    if (column < 0 || row < 0 || column >= m.width || row >= m.height) continue;
    conflicts += m.at(static_cast<int>(column), static_cast<int>(row)) == CellState::kFree;
  }
  return conflicts;
}

double Localizer::score_at(const Points2& query_points, const Pose2& T_map_query) const {
  if (query_points.empty()) return 0.0;
  const Pose2 T_canonical_query = T_canonical_map_ * T_map_query;
  int inliers = 0;
  for (const Vec2& p : query_points) inliers += map_.grid.at(T_canonical_query * p);
  const double points = inliers - config_.free_weight * free_conflicts(query_points, T_map_query);
  return points / static_cast<double>(query_points.size());
}

Localizer::VerifyQuery Localizer::verify_query(const Points2& query_points, const Points2& query_origins) const {
  VerifyQuery q{VerifyMap(query_points, query_origins, config_.verify), query_points.front(), query_points.front(), {}};
  for (const Points2* set : {&query_points, &query_origins})
    for (const Vec2& p : *set) q.lo = q.lo.cwiseMin(p), q.hi = q.hi.cwiseMax(p);
  q.field = verify_field(q.map);
  return q;
}

Verified Localizer::verify(const VerifyQuery& query, const Pose2& T_map_query) const {
  return verify(query, T_map_query, config_.verify);
}

Verified Localizer::verify(const VerifyQuery& query, const Pose2& T_map_query, const VerifyConfig& config,
                           Verified* at_pose) const {
  Vec2 a = T_map_query * query.lo, b = a;
  for (const Vec2& c : {query.lo, Vec2(query.hi.x(), query.lo.y()), query.hi, Vec2(query.lo.x(), query.hi.y())})
    a = a.cwiseMin(T_map_query * c), b = b.cwiseMax(T_map_query * c);
  const VerifyMap around = verify_.cropped(a.array() - config_.neighbourhood, b.array() + config_.neighbourhood);
  return verify_match(query.map, query.field, around, T_map_query, config, at_pose);
}

Verified Localizer::verify(const Points2& query_points, const Points2& query_origins, const Pose2& T_map_query) const {
  return verify(verify_query(query_points, query_origins), T_map_query);
}

std::vector<Verified> Localizer::verify_all(const Points2& query_points, const Points2& query_origins,
                                       std::span<const Pose2> poses, const VerifyConfig& config,
                                       std::vector<Verified>* at_poses) const {
  if (query_points.empty()) throw InputError("localizer: the local map has no point");
  return verify_all(verify_query(query_points, query_origins), poses, config, at_poses);
}

std::vector<Verified> Localizer::verify_all(const VerifyQuery& query, std::span<const Pose2> poses,
                                            const VerifyConfig& config, std::vector<Verified>* at_poses) const {
  validate(config);
  std::vector<Verified> out;
  if (at_poses != nullptr) at_poses->assign(poses.size(), {});
  for (std::size_t i = 0; i < poses.size(); ++i)
    out.push_back(verify(query, poses[i], config, at_poses != nullptr ? &(*at_poses)[i] : nullptr));
  return out;
}

std::vector<Verified> Localizer::hypotheses(const Points2& query_points, const Points2& query_origins,
                                            int count, int verified, double min_share) const {
  if (query_points.empty()) throw InputError("localizer: the local map has no point");
  return hypotheses(query_points, verify_query(query_points, query_origins), count, verified, min_share);
}

std::vector<Verified> Localizer::hypotheses(const Points2& query_points, const VerifyQuery& verify_local,
                                            int count, int verified, double min_share) const {
  HypothesisSearch search(*this, query_points, verify_local, count, verified, min_share);
  search.advance(0);
  return search.result();
}

std::vector<Verified> Localizer::distinct_verified(const VerifyQuery& query, const std::vector<Candidate>& found,
                                                   int count, int verified) const {
  const std::size_t chosen =
      std::min<std::size_t>(found.size(), static_cast<std::size_t>(verified >= 1 ? verified : config_.verified));
  std::vector<Verified> all;
  for (std::size_t i = 0; i < chosen; ++i) all.push_back(verify(query, found[i].T_map_query));
  std::stable_sort(all.begin(), all.end(),
                   [](const Verified& a, const Verified& b) { return a.probability > b.probability; });
  std::vector<Verified> out;
  for (const Verified& v : all) {
    if (out.size() >= static_cast<std::size_t>(std::max(count, 0))) break;
    const bool same = std::any_of(out.begin(), out.end(), [&](const Verified& o) {
      return PoseTolerance{config_.candidate_distance, config_.elsewhere.angle}.accepts(o.T_map_query,
                                                                                        v.T_map_query);
    });
    if (!same) out.push_back(v);
  }
  return out;
}

namespace {

const Points2& non_empty(const Points2& points) {
  if (points.empty()) throw InputError("localizer: the local map has no point");
  return points;
}

double checked_share(double min_share) {
  if (!(min_share >= 0.0 && min_share < 1.0)) throw InputError("localizer: min_share must be in [0, 1)");
  return min_share;
}

}  // namespace

Localizer::HypothesisSearch::HypothesisSearch(const Localizer& localizer, const Points2& query_points,
                                              VerifyQuery prepared, int count, int verified, double min_share)
    : localizer_(localizer),
      points_(non_empty(query_points)),
      prepared_(std::move(prepared)),
      count_(count),
      verified_(verified),
      query_(prepare_query(points_, localizer.config_.dmm)),
      candidates_(std::make_unique<Candidates>(localizer, query_, centroid(points_), checked_share(min_share))) {}

Localizer::HypothesisSearch::~HypothesisSearch() = default;

bool Localizer::HypothesisSearch::done() const { return candidates_->done; }

bool Localizer::HypothesisSearch::advance(std::int64_t budget) {
  if (done()) return true;
  if (!localizer_.search_candidates(points_, *candidates_, budget)) return false;
  // The call that ends the search verifies its candidates (search_candidates set done).
  result_ = localizer_.distinct_verified(prepared_, candidates_->found, count_, verified_);
  return true;
}

bool answers_agree(const Pose2& T_map_a, const Pose2& T_map_b, const Pose2& T_log_a, const Pose2& T_log_b,
                   const PoseTolerance& tolerance) {
  const Pose2 in_map = T_map_a.inverse() * T_map_b, in_log = T_log_a.inverse() * T_log_b;
  PoseTolerance allowed = tolerance;
  allowed.translation += 0.1 * in_log.translation().norm();
  return allowed.accepts(in_map, in_log);
}

std::string not_confident_because(const Localization& l, const ConfidenceRule& rule) {
  char text[160];
  std::string out;
  if (!(l.confidence >= rule.min_margin)) {
    std::snprintf(text, sizeof text, "margin %.3f < %g", l.confidence, rule.min_margin);
    out = text;
  }
  if (l.calibrated && !(l.probability >= rule.min_probability)) {
    std::snprintf(text, sizeof text, "same-place probability %.3f < %g", l.probability, rule.min_probability);
    out += (out.empty() ? "" : "; ") + std::string(text);
  }
  return out;
}

bool is_confident(const Localization& l, const ConfidenceRule& rule) {
  return rule.confident(l.confidence, l.calibrated ? std::optional(l.probability) : std::nullopt);
}

Localizer::Candidates::Candidates(const Localizer& localizer, const PreparedQuery& query, const Vec2& where,
                                  double share)
    : search(query, localizer.map_, localizer.config_.candidate_distance, localizer.config_.elsewhere.angle),
      centre(where),
      min_share(share) {}

bool Localizer::search_candidates(const Points2& query_points, Candidates& state, std::int64_t budget) const {
  if (state.done) return true;
  const Pose2 T_map_canonical = T_canonical_map_.inverse();
  const double n = static_cast<double>(query_points.size());
  std::vector<Candidate>& found = state.found;
  // One best-first search yields the distinct candidates in turn.
  while (static_cast<int>(found.size()) < config_.candidates) {
    Candidate s;
    int bar = state.second > 0 ? static_cast<int>(std::floor(state.second)) : -1;
    if (!found.empty() && state.min_share > 0)  // found.front(): the search's first, the most inliers
      bar = std::max(bar, static_cast<int>(std::floor(state.min_share * found.front().dmm.inliers)));
    s.dmm = state.search.next(bar, budget);
    if (s.dmm.paused) return false;
    if (!found.empty() && (!s.dmm.exact || s.dmm.inliers == 0)) break;  // nothing left that could matter
    s.T_map_query = T_map_canonical * s.dmm.T_map_query;
    s.conflicts = free_conflicts(query_points, s.T_map_query);
    const double points = s.dmm.inliers - config_.free_weight * s.conflicts;
    s.score = points / n;
    s.place = std::all_of(found.begin(), found.end(), [&](const Candidate& f) {
      return config_.elsewhere.apart(f.T_map_query, s.T_map_query, state.centre);
    });
    if (!s.place) {
      // a place found before, seen a little off: its margin is over other places
    } else if (points > state.first) {
      state.second = state.first, state.first = points;
    } else if (points > state.second) {
      state.second = points;
    }
    found.push_back(s);
  }
  // Best rescored first; ties keep the search order (the higher dMM score).
  std::stable_sort(found.begin(), found.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  state.done = true;
  return true;
}

std::vector<Localizer::Candidate> Localizer::search_candidates(const Points2& query_points,
                                                               const PreparedQuery& query, const Vec2& centre) const {
  Candidates state(*this, query, centre);
  search_candidates(query_points, state, 0);
  return std::move(state.found);
}

Verified Localizer::verify_best(const VerifyQuery& query, const std::vector<Candidate>& found,
                                std::size_t& chosen) const {
  chosen = 0;
  Verified v = verify(query, found.front().T_map_query);
  const std::size_t verified = std::min<std::size_t>(found.size(), static_cast<std::size_t>(config_.verified));
  for (std::size_t i = 1; i < verified; ++i) {
    Verified other = verify(query, found[i].T_map_query);
    if (other.probability > v.probability) v = std::move(other), chosen = i;
  }
  // The answer verified again from starts around it: a candidate half a metre from the true pose does not
  // refine onto it.
  if (config_.restart_distance > 0) {
    const Pose2 at = v.T_map_query;
    const double r = config_.restart_distance;
    for (const Vec2& d : {Vec2(r, 0), Vec2(-r, 0), Vec2(0, r), Vec2(0, -r)}) {
      Verified other = verify(query, Pose2{at.x + d.x(), at.y + d.y(), at.theta});
      if (other.probability > v.probability) v = std::move(other);
    }
  }
  return v;
}

void Localizer::set_margin(const std::vector<Candidate>& found, std::size_t chosen, const Vec2& centre,
                           Localization& out) const {
  const Candidate& best = found[chosen];
  // The margin is over the other places: the candidates that are the best of their place (in the search's
  // order, as a search with candidate_distance = elsewhere.distance finds them) and lie elsewhere than the
  // answer (the candidates between are the same places seen a little off).
  const auto elsewhere = [&](std::size_t j) {
    return found[j].place && config_.elsewhere.apart(found[j].T_map_query, best.T_map_query, centre);
  };
  for (std::size_t j = 0; j < found.size(); ++j) {
    if (j == chosen || !elsewhere(j)) continue;
    out.elsewhere_score = found[j].score;  // the best-scoring other place (found is sorted by score)
    out.T_map_elsewhere = found[j].T_map_query;
    break;
  }
  // The margin is from the answer's place: the best score of the candidates there.
  std::vector<double> scores;
  for (const Candidate& f : found) scores.push_back(f.score);
  for (const Candidate& f : found)
    if (!config_.elsewhere.apart(f.T_map_query, best.T_map_query, centre))
      scores[chosen] = std::max(scores[chosen], f.score);
  out.confidence = std::max(0.0, distinctiveness(scores, chosen, elsewhere));
}

Localization Localizer::locate(const Points2& query_points, const Points2& query_origins) const {
  if (query_points.empty()) throw InputError("localizer: the local map has no point");
  const auto t0 = Clock::now();
  const PreparedQuery query = prepare_query(query_points, config_.dmm);
  const Vec2 centre = centroid(query_points);  // the local map's centre
  const std::vector<Candidate> found = search_candidates(query_points, query, centre);
  // The best few candidates verified against the building map around them (refined below the lattice, with
  // their same-place probability); the most probable is the answer.
  std::size_t chosen = 0;
  const VerifyQuery verify_local = verify_query(query_points, query_origins);  // its beams cast once
  const Verified v = verify_best(verify_local, found, chosen);
  Localization out;
  const Candidate& best = found[chosen];
  out.T_map_lattice = best.T_map_query;
  out.inliers = best.dmm.inliers;
  out.inlier_fraction = best.dmm.inlier_fraction;
  out.free_conflicts = best.conflicts;
  out.score = best.score;
  set_margin(found, chosen, centre, out);
  out.candidates = static_cast<int>(found.size());
  out.T_map_query = v.T_map_query;
  out.terms = v.terms;
  out.probability = v.probability;
  out.calibrated = v.terms.beams;
  out.time_ms = ms_since(t0);
  return out;
}

}  // namespace partslam
