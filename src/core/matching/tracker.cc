#include "core/matching/tracker.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/timing.h"

namespace partslam {

void validate(const TrackerConfig& c) {
  const auto in = [](double v, double lo, double hi) { return v >= lo && v <= hi; };  // false for NaN
  if (c.hypotheses < 1 || c.hypotheses > 100) throw InputError("tracker: hypotheses must be in [1, 100]");
  if (c.search_verified < 1 || c.search_verified > 100)
    throw InputError("tracker: search_verified must be in [1, 100]");
  if (c.max_hypotheses < 1 || c.max_hypotheses > 1000)
    throw InputError("tracker: max_hypotheses must be in [1, 1000]");
  if (!in(c.track_window, 0, 5)) throw InputError("tracker: track_window must be in [0, 5] m");
  if (!in(c.track_angle, 0, 1)) throw InputError("tracker: track_angle must be in [0, 1] rad");
  if (!in(c.merge_distance, 0, 100)) throw InputError("tracker: merge_distance must be in [0, 100] m");
  if (!in(c.merge_angle, 0, std::numbers::pi)) throw InputError("tracker: merge_angle must be in [0, pi] rad");
  if (!in(c.floor_probability, 1e-9, 1)) throw InputError("tracker: floor_probability must be in [1e-9, 1]");
  if (!in(c.other_probability, 1e-9, 1)) throw InputError("tracker: other_probability must be in [1e-9, 1]");
  if (!in(c.declare_share, 0.5, 1)) throw InputError("tracker: declare_share must be in [0.5, 1]");
  if (c.declare_steps < 1 || c.declare_steps > 1000) throw InputError("tracker: declare_steps must be in [1, 1000]");
  if (!in(c.lost_probability, 0, 1)) throw InputError("tracker: lost_probability must be in [0, 1]");
  if (c.lost_steps < 1 || c.lost_steps > 1000) throw InputError("tracker: lost_steps must be in [1, 1000]");
  if (!in(c.drop_share, 0, 1)) throw InputError("tracker: drop_share must be in [0, 1]");
  if (!in(c.min_seen, 0, 1)) throw InputError("tracker: min_seen must be in [0, 1]");
  if (!in(c.move_gain, 1, 1000)) throw InputError("tracker: move_gain must be in [1, 1000]");
  if (!in(c.declare_probability, 0, 1)) throw InputError("tracker: declare_probability must be in [0, 1]");
  if (!(c.corridor_ratio >= 0 && c.corridor_ratio < 1)) throw InputError("tracker: corridor_ratio must be in [0, 1)");
  if (!in(c.corridor_slack, 0, 5)) throw InputError("tracker: corridor_slack must be in [0, 5] m");
  if (c.search_every < 1 || c.search_every > 1000) throw InputError("tracker: search_every must be in [1, 1000]");
  if (c.search_budget < 0) throw InputError("tracker: search_budget must be >= 0");
  if (!(c.search_min_share >= 0 && c.search_min_share < 1))
    throw InputError("tracker: search_min_share must be in [0, 1)");
  if (c.weighed_back < 0 || c.weighed_back > 20) throw InputError("tracker: weighed_back must be in [0, 20]");
  if (!in(c.min_none_share, 0, 0.5)) throw InputError("tracker: min_none_share must be in [0, 0.5]");
  if (!c.claim_shift.valid()) throw InputError("tracker: claim_shift must be finite and >= 0");
}

double shared_evidence_log_ratio(std::span<const double> a, std::span<const double> b) {
  const std::size_t n = std::min(a.size(), b.size());
  double ratio = 0;
  for (std::size_t i = 1; i <= n; ++i) ratio += a[a.size() - i] - b[b.size() - i];
  return ratio;
}

const char* to_string(TrackStatus status) {
  switch (status) {
    case TrackStatus::kSearching: return "searching";
    case TrackStatus::kLocalised: return "localised";
    case TrackStatus::kLost: return "lost";
  }
  return "?";
}

Tracker::Tracker(const Localizer& localizer, const TrackerConfig& config) : localizer_(localizer), config_(config) {
  validate(config_);
}

void Tracker::reset() {
  hypotheses_.clear();
  none_log_weight_ = 0;
  has_last_ = false;
  status_ = TrackStatus::kSearching;
  declared_ = dominant_ = -1;
  dominant_steps_ = weak_steps_ = 0;
  blind_ = false;
  steps_since_search_ = 0;
  previous_.clear();
  lost_pose_.reset();
  pending_.reset();
  steps_ = 0;
  searched_on_ = -1;
}

const Tracker::Hypothesis* Tracker::find(int id) const {
  for (const Hypothesis& h : hypotheses_)
    if (h.id == id) return &h;
  return nullptr;
}

// Log weights shifted so that the weights and the none weight sum to 1.
void Tracker::normalise() {
  double top = none_log_weight_;
  for (const Hypothesis& h : hypotheses_) top = std::max(top, h.log_weight);
  double sum = std::exp(none_log_weight_ - top);
  for (const Hypothesis& h : hypotheses_) sum += std::exp(h.log_weight - top);
  const double shift = top + std::log(sum);
  none_log_weight_ -= shift;
  for (Hypothesis& h : hypotheses_) h.log_weight -= shift;
  // The none weight never falls below min_none_share: evidence from long ago does not make a hypothesis immune
  // to what the last few local maps say (a kidnapping).
  const double none = std::exp(none_log_weight_);
  if (none < config_.min_none_share && !hypotheses_.empty()) {
    const double scale = std::log((1 - config_.min_none_share) / (1 - none));
    for (Hypothesis& h : hypotheses_) h.log_weight += scale;
    none_log_weight_ = std::log(config_.min_none_share);
  }
}

// Heaviest first; a hypothesis within the merge tolerance of a heavier one adds its weight to it (the declared
// one's id goes with its weight); the light ones and those past max_hypotheses drop.
void Tracker::merge_and_drop() {
  std::stable_sort(hypotheses_.begin(), hypotheses_.end(),
                   [](const Hypothesis& a, const Hypothesis& b) { return a.log_weight > b.log_weight; });
  const PoseTolerance same{config_.merge_distance, config_.merge_angle};
  std::vector<Hypothesis> kept;
  for (const Hypothesis& h : hypotheses_) {
    auto into = std::find_if(kept.begin(), kept.end(),
                             [&](const Hypothesis& k) { return same.accepts(k.T_map_query, h.T_map_query); });
    if (into == kept.end()) {
      kept.push_back(h);
      continue;
    }
    const double a = into->log_weight, b = h.log_weight;  // a >= b
    into->log_weight = a + std::log1p(std::exp(b - a));
    into->age = std::max(into->age, h.age);
    if (h.id == declared_) declared_ = into->id;
    if (h.id == dominant_) dominant_ = into->id;
  }
  const double floor = kept.empty() ? 0.0 : kept.front().log_weight + std::log(std::max(config_.drop_share, 1e-300));
  std::vector<Hypothesis> out;
  for (const Hypothesis& h : kept) {
    const bool keep = h.id == declared_ || (h.log_weight >= floor &&
                                            out.size() < static_cast<std::size_t>(config_.max_hypotheses));
    if (keep) out.push_back(h);
  }
  hypotheses_ = std::move(out);
}

// Whether the steps since each other place's hypothesis was born weighed `h` above it by declare_share's
// odds: a rival found later started from the none weight's share, so its weight is smaller by when it was
// found, not by what the local maps said of it. Hypotheses within the localizer's "elsewhere" of `h` are the
// same place seen a little off, not rivals.
bool Tracker::ahead_of_rivals(const Hypothesis& h) const {
  const double odds = std::log(config_.declare_share / (1 - config_.declare_share));
  const OtherPlace& elsewhere = localizer_.config().elsewhere;
  const PoseTolerance same_place{elsewhere.distance, elsewhere.angle};
  for (const Hypothesis& r : hypotheses_) {
    if (r.id == h.id || same_place.accepts(h.T_map_query, r.T_map_query)) continue;
    if (!(shared_evidence_log_ratio(h.history, r.history) >= odds)) return false;
  }
  return true;
}

// Returns true when the robot was lost this step (every hypothesis dropped).
bool Tracker::update_status(bool evidence) {
  const Hypothesis* declared = find(declared_);
  // The declared pose given up, the other hypotheses kept: "lost" until one is declared (tracker.h, 4).
  const auto give_up = [&] { declared_ = -1, status_ = TrackStatus::kLost, blind_ = false; };
  if (status_ == TrackStatus::kLocalised || blind_) {
    if (declared == nullptr) {
      blind_ = false, declared_ = -1;
      if (status_ == TrackStatus::kLocalised) status_ = TrackStatus::kSearching;
    } else if (declared->seen < config_.min_seen) {
      // The declared place is not in the map (or the pose drifted off it): no claim until it is seen again;
      // given up once other hypotheses took declare_share's complement of the weight (a kidnapped robot whose
      // carried pose left the map while the search found where it is).
      if (std::exp(declared->log_weight) < config_.declare_share) {
        give_up();
      } else {
        if (status_ == TrackStatus::kLocalised) status_ = TrackStatus::kSearching;
        blind_ = true;
      }
    } else {
      weak_steps_ = declared->probability < config_.lost_probability ? weak_steps_ + 1 : 0;
      if (weak_steps_ >= config_.lost_steps) {
        status_ = TrackStatus::kLost;
        lost_pose_ = declared->T_map_query;  // weighed from the next step on (step() sets it after its check)
        hypotheses_.clear();
        previous_.clear();  // the local maps before are of where the robot was carried from
        none_log_weight_ = 0;
        declared_ = dominant_ = -1;
        dominant_steps_ = weak_steps_ = 0;
        blind_ = false;
        return true;
      }
      if (weak_steps_ > 0 || declared->moved) {
        // Fits badly here (a kidnapping's first step; lost if it goes on), or the match moved it further from
        // where the odometry carried it than the odometry errs in a step: no claim this step.
        if (status_ == TrackStatus::kLocalised) status_ = TrackStatus::kSearching;
        blind_ = true;
      } else if (blind_) {
        // It fits again: declared again if it still holds declare_share ahead of its rivals, else given up
        // (a kidnapping to where the carried pose still fits now and then: a corridor, an outdoor place alike to
        // where the robot was): "lost", its hypothesis and the others kept, until one is declared.
        if (std::exp(declared->log_weight) >= config_.declare_share && ahead_of_rivals(*declared)) {
          status_ = TrackStatus::kLocalised, blind_ = false;
        } else {
          give_up();
        }
      }
    }
  }
  // The heaviest hypothesis holding declare_share on consecutive steps with evidence is declared (again, or
  // instead of the one declared before).
  const Hypothesis* heaviest = hypotheses_.empty() ? nullptr : &hypotheses_.front();
  const auto fits = [&](const Hypothesis& h) {  // seen here, not fitting badly, where the odometry carried it
    return h.seen >= config_.min_seen && h.probability >= config_.lost_probability && !h.moved;
  };
  const auto qualifies = [&](const Hypothesis& h) {  // but for where its match moved it
    return h.seen >= config_.min_seen && std::exp(h.log_weight) >= config_.declare_share &&
           h.probability >= config_.declare_probability && ahead_of_rivals(h);
  };
  if (heaviest != nullptr && evidence && fits(*heaviest) && qualifies(*heaviest)) {
    dominant_steps_ = heaviest->id == dominant_ ? dominant_steps_ + 1 : 1;
    dominant_ = heaviest->id;
  } else if (evidence && !(heaviest != nullptr && heaviest->id == dominant_ && heaviest->moved && qualifies(*heaviest))) {
    // A step on which the dominant one only moved (the odometry erred more than claim_shift) neither counts nor
    // undoes its steps before (docs/NOTES.md, "A moved step holds the count").
    dominant_steps_ = 0, dominant_ = -1;
  }
  const bool dominates = heaviest != nullptr && heaviest->id == dominant_ && fits(*heaviest);
  if (dominates && dominant_steps_ >= config_.declare_steps && confirmed(*heaviest) &&
      (dominant_ != declared_ || status_ != TrackStatus::kLocalised)) {
    status_ = TrackStatus::kLocalised;
    declared_ = dominant_;
    weak_steps_ = 0;
    blind_ = false;
  }
  return false;
}

TrackStep Tracker::step(const Points2& points, const Points2& origins, const Pose2& T_odom_map) {
  const auto t0 = Clock::now();
  if (points.empty()) throw InputError("tracker: the local map has no point");
  if (!std::isfinite(T_odom_map.x) || !std::isfinite(T_odom_map.y) || !std::isfinite(T_odom_map.theta))
    throw InputError("tracker: the local map's odometry pose is not finite");
  const Pose2 motion = has_last_ ? T_odom_last_.inverse() * T_odom_map : Pose2{};
  T_odom_last_ = T_odom_map, has_last_ = true;
  if (!previous_.empty()) previous_.back().motion = motion;
  if (lost_pose_) *lost_pose_ = *lost_pose_ * motion;
  // The local map's beams cast once for every verification of this step (and the newborn's of later steps).
  Localizer::VerifyQuery prepared = localizer_.verify_query(points, origins);

  // 1-2. Carry and weigh.
  bool evidence = false, weighed = false;
  if (!hypotheses_.empty()) {
    std::vector<Pose2> carried;
    for (Hypothesis& h : hypotheses_) h.T_map_query = h.T_map_query * motion, ++h.age, carried.push_back(h.T_map_query);
    const std::vector<Verified> seen = verify_carried(prepared, carried, true);
    for (std::size_t i = 0; i < hypotheses_.size(); ++i) {
      Hypothesis& h = hypotheses_[i];
      h.moved = !config_.claim_shift.accepts(carried[i], seen[i].T_map_query);
      h.T_map_query = seen[i].T_map_query;
      h.probability = seen[i].probability;
      h.seen = seen[i].terms.query.seen;
      evidence = evidence || h.seen >= config_.min_seen;
      const double factor = weight_factor(seen[i]);
      h.log_weight += factor;
      h.history.push_back(factor);
      if (h.history.size() > kHistory) h.history.erase(h.history.begin());
    }
    none_log_weight_ += std::log(config_.other_probability), weighed = true;
    normalise();
  }

  // New hypotheses (the search's, or the pose the robot was lost at): each out of the none weight, weighed by
  // its probability; the none weight weighed too if no carried hypothesis did it this step.
  const auto adopt = [&](const std::vector<Verified>& found, std::ptrdiff_t found_on) {
    const PoseTolerance same{config_.merge_distance, config_.merge_angle};
    const double from = none_log_weight_;
    const std::size_t rivals = hypotheses_.size();
    for (const Verified& v : found) {
      evidence = evidence || v.terms.query.seen >= config_.min_seen;
      const bool known = std::any_of(hypotheses_.begin(), hypotheses_.end(),
                                     [&](const Hypothesis& h) { return same.accepts(h.T_map_query, v.T_map_query); });
      if (known) continue;
      Hypothesis h;
      h.id = next_id_++;
      h.found = found_on;
      h.T_map_query = v.T_map_query;
      h.probability = v.probability;
      h.seen = v.terms.query.seen;
      h.history = {std::log(std::max(v.probability, config_.floor_probability))};
      h.log_weight = from + h.history.front();
      hypotheses_.push_back(h);
    }
    // The newborn are weighed on the last weighed_back local maps too, where the odometry says they were
    // (refined within the localizer's window, as the search's candidates are), so that a rival carried since
    // then is compared with them on those steps as well, not on this one alone (tracker.h, 4).
    // Only those that fit this step within declare_share's odds of the best carried one: the others cannot
    // hold back a declaration on this step's evidence alone.
    double best_carried = 0;
    for (std::size_t i = 0; i < rivals; ++i) best_carried = std::max(best_carried, hypotheses_[i].probability);
    std::vector<std::size_t> close;
    for (std::size_t i = rivals; i < hypotheses_.size(); ++i)
      if (hypotheses_[i].probability * config_.declare_share >= best_carried * (1 - config_.declare_share))
        close.push_back(i);
    if (!close.empty()) {
      std::vector<Pose2> before;
      for (const std::size_t i : close) before.push_back(hypotheses_[i].T_map_query);
      for (std::size_t k = 0; k < previous_.size(); ++k) {
        const Previous& p = previous_[previous_.size() - 1 - k];
        for (Pose2& b : before) b = b * p.motion.inverse();
        const std::vector<Verified> then = verify_carried(p.prepared, before, false);
        for (std::size_t j = 0; j < close.size(); ++j)
          hypotheses_[close[j]].history.insert(hypotheses_[close[j]].history.begin(), weight_factor(then[j]));
      }
    }
    if (!weighed) none_log_weight_ += std::log(config_.other_probability), weighed = true;
    normalise();
    merge_and_drop();
    normalise();
  };
  // 3. The global search, its poses adopted as new hypotheses.
  // A search runs in slices of search_budget (tracker.h, 5): it starts on this step's local map, goes on over
  // the next steps, and its hypotheses, found for the local map it started on, are carried by the odometry
  // since then and weighed here as the carried ones are.
  bool searched = false;
  const auto begin_search = [&] {
    pending_ = std::make_unique<Localizer::HypothesisSearch>(localizer_, points, prepared, config_.hypotheses,
                                                            config_.search_verified, config_.search_min_share);
    pending_step_ = steps_;
    T_odom_pending_ = T_odom_map;
  };
  const auto search = [&] {
    searched = true;
    if (pending_ == nullptr) begin_search();
    if (!pending_->advance(config_.search_budget)) {
      merge_and_drop(), normalise();
      return;
    }
    std::vector<Verified> found = pending_->result();
    if (pending_step_ != steps_) {
      const Pose2 since = T_odom_pending_.inverse() * T_odom_map;
      std::vector<Pose2> carried;
      for (const Verified& v : found) carried.push_back(v.T_map_query * since);
      found = verify_carried(prepared, carried, true);
    }
    const std::size_t began = pending_step_;
    pending_.reset();
    steps_since_search_ = 0;
    searched_on_ = static_cast<std::ptrdiff_t>(began);
    adopt(found, static_cast<std::ptrdiff_t>(began));
  };
  // The pose the robot was lost at, carried on by the odometry, joins as soon as it fits a later local map well
  // enough to count towards a declaration (tracker.h, 4).
  if (lost_pose_ && status_ != TrackStatus::kLocalised) {
    const Verified v = verify_carried(prepared, {*lost_pose_}, true).front();
    if (v.terms.query.seen >= config_.min_seen && v.probability >= config_.declare_probability)
      adopt({v}, -1), lost_pose_.reset();
  }
  // While not localised: a search when there is no hypothesis, else every search_every steps (a global search
  // costs ten to a hundred times a carried step; in between, the carried hypotheses gather evidence).
  ++steps_since_search_;
  if (status_ == TrackStatus::kLocalised) pending_.reset(), lost_pose_.reset();  // no search while localised
  // A hypothesis that holds declare_share but was found on the last search's local map waits for a search begun
  // on a later one before it is declared: it has not been compared with what a global search finds from where
  // it now is (a local map mostly outside the map finds only look-alikes) (tracker.h, 4).
  const auto lighter = [](const Hypothesis& a, const Hypothesis& b) { return a.log_weight < b.log_weight; };
  const auto heaviest = std::max_element(hypotheses_.begin(), hypotheses_.end(), lighter);
  const bool unconfirmed = heaviest != hypotheses_.end() && std::exp(heaviest->log_weight) >= config_.declare_share &&
                           !confirmed(*heaviest);
  if (pending_ != nullptr ||
      (status_ != TrackStatus::kLocalised &&
       (hypotheses_.empty() || steps_since_search_ >= config_.search_every || unconfirmed)))
    search();
  else merge_and_drop(), normalise();
  // 4. The status; lost this step: the search starts again at once, on this step's local map (a search begun
  // before is of where the robot was carried from).
  if (update_status(evidence)) {
    const bool fresh = pending_ != nullptr && pending_step_ == steps_;
    if (!fresh) pending_.reset();
    if (!searched) weighed = false, search();
    else if (config_.search_budget > 0 && !fresh) begin_search();  // it goes on from the next step
  }
  ++steps_;
  previous_.push_back(Previous{std::move(prepared), Pose2{}});
  if (previous_.size() > static_cast<std::size_t>(config_.weighed_back)) previous_.erase(previous_.begin());
  return report(searched, evidence, ms_since(t0));
}

// Each pose refined within the track window (or the localizer's own, track_window false); a refinement that
// moves it further than claim_shift is kept only when it is move_gain times as probable as the pose itself:
// along a corridor (or where the local map is half outside the map) it fits about as well anywhere, and the
// odometry's pose is the better guess.
std::vector<Verified> Tracker::verify_carried(const Localizer::VerifyQuery& prepared,
                                              const std::vector<Pose2>& poses, bool track_window) const {
  VerifyConfig verify = localizer_.config().verify;
  if (track_window) {
    verify.refine_window = config_.track_window, verify.refine_angle = config_.track_angle;
    verify.keep_along_ratio = config_.corridor_ratio;
    verify.keep_along_slack = config_.corridor_slack;
  }
  std::vector<Verified> at_poses;
  std::vector<Verified> out = localizer_.verify_all(prepared, poses, verify, &at_poses);
  for (std::size_t i = 0; i < out.size(); ++i)
    if (!config_.claim_shift.accepts(poses[i], out[i].T_map_query) &&
        out[i].probability < config_.move_gain * at_poses[i].probability)
      out[i] = at_poses[i];
  return out;
}

// What a step multiplies a hypothesis's weight by (log): its probability (at least floor_probability),
// or, where the building map never saw the local map's place, other_probability (the local map says
// nothing of it).
double Tracker::weight_factor(const Verified& v) const {
  const bool weighs = v.terms.query.seen >= config_.min_seen;
  return std::log(weighs ? std::max(v.probability, config_.floor_probability) : config_.other_probability);
}

TrackStep Tracker::report(bool searched, bool evidence, double time_ms) const {
  TrackStep s;
  s.status = status_;
  s.searched = searched;
  s.evidence = evidence;
  s.time_ms = time_ms;
  s.none_share = std::exp(none_log_weight_);
  for (const Hypothesis& h : hypotheses_)
    s.hypotheses.push_back({h.T_map_query, h.probability, std::exp(h.log_weight), h.age});
  const Hypothesis* shown = status_ == TrackStatus::kLocalised ? find(declared_) : nullptr;
  if (shown == nullptr && !hypotheses_.empty()) shown = &hypotheses_.front();
  if (shown != nullptr) s.has_pose = true, s.best = {shown->T_map_query, shown->probability, std::exp(shown->log_weight), shown->age};
  return s;
}

}  // namespace partslam
