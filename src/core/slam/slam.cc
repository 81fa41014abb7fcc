#include "core/slam/slam.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <iomanip>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/maps/manhattan.h"
#include "core/timing.h"

namespace partslam {
namespace {

// "a second front end (fine field F m) parts from the first by up to T deg / S m over W m of travel": the words the
// verdict's reason and its checked sentence share for the second opinion.
std::string second_opinion_parting(const FrontEndAgreement& a, const SecondOpinionConfig& c) {
  std::ostringstream out;
  out << std::fixed << "a second front end (fine field " << std::setprecision(2) << c.fine_sigma
      << " m) parts from the first by up to " << std::setprecision(1) << a.max_turn * kDegreesPerRadian
      << " deg / " << std::setprecision(2) << a.max_shift << " m over " << std::setprecision(0) << c.window
      << " m of travel";
  return out.str();
}

// "limits T deg / S m": the second opinion's limits, as the same two sentences give them.
std::string second_opinion_limits(const SecondOpinionConfig& c) {
  std::ostringstream out;
  out << std::fixed << "limits " << std::setprecision(0) << c.max_turn * kDegreesPerRadian << " deg / "
      << std::setprecision(1) << c.max_shift << " m";
  return out.str();
}

// a + t (b - a) on SE(2) parameters, the angle along the short way.
Pose2 interpolate(const Pose2& a, const Pose2& b, double t) {
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), wrap_angle(a.theta + t * wrap_angle(b.theta - a.theta))};
}

}  // namespace

Scans corrected_scans(const Scans& scans, const Submaps& old_maps, const Submaps& new_maps) {
  if (old_maps.size() != new_maps.size() || old_maps.empty())
    throw InputError("corrected scans: the same non-empty submaps before and after are needed");
  std::vector<Pose2> correction;
  for (std::size_t k = 0; k < old_maps.size(); ++k)
    correction.push_back(new_maps[k].T_world_map * old_maps[k].T_world_map.inverse());
  const std::vector<double> s = travel_distances(scans);
  Scans out = scans;
  std::size_t k = 0;  // the last anchor at or before scan i
  for (std::size_t i = 0; i < scans.size(); ++i) {
    while (k + 1 < old_maps.size() && static_cast<std::size_t>(old_maps[k + 1].anchor_scan) <= i) ++k;
    Pose2 C = correction[k];
    const auto anchor = static_cast<std::size_t>(old_maps[k].anchor_scan);
    if (i >= anchor && k + 1 < old_maps.size()) {
      const auto next = static_cast<std::size_t>(old_maps[k + 1].anchor_scan);
      const double span = s.at(next) - s.at(anchor);
      const double t = span > 0 ? std::clamp((s[i] - s[anchor]) / span, 0.0, 1.0) : 0.0;
      C = interpolate(correction[k], correction[k + 1], t);
    }
    out[i].T_world_laser = C * scans[i].T_world_laser;
  }
  return out;
}

void validate(const SlamConfig& c) {
  validate_nested("slam config", "front_end", [&] { validate(c.front_end); });
  validate_nested("slam config", "submaps", [&] { validate(c.submaps); });
  validate_nested("slam config", "loops", [&] { validate(c.loops); });
  if (!std::isfinite(c.min_confidence))
    throw InputError("slam config: min_confidence must be finite, got " + std::to_string(c.min_confidence));
  validate_nested("slam config", "refinement", [&] { validate(c.refinement); });
  validate_nested("slam config", "back_end", [&] { validate(c.back_end); });
  validate_nested("slam config", "map_check", [&] { validate(c.map_check); });
  validate_nested("slam config", "neighbours", [&] { validate(c.neighbours); });
  validate_nested("slam config", "second_opinion", [&] { validate(c.second_opinion); });
  if (c.second_opinion.enabled && c.second_opinion.fine_sigma == c.front_end.fine_sigma)
    throw InputError("slam config: second_opinion.fine_sigma must differ from front_end.fine_sigma (both " +
                     std::to_string(c.front_end.fine_sigma) + "): the same setting twice is no second opinion");
  if (!(c.max_degenerate_share >= 0 && c.max_degenerate_share <= 1))
    throw InputError("slam config: max_degenerate_share must be in [0, 1], got " +
                     std::to_string(c.max_degenerate_share));
}

double degenerate_share(const FrontEndStats& s) {
  return s.scans > 1 ? static_cast<double>(s.degenerate) / static_cast<double>(s.scans - 1) : 0.0;
}

namespace {

// Every world-frame pose and position of r turned by T (the closures' relative poses are frame-free).
void turn_result(SlamResult& r, const Pose2& T) {
  for (Scan& s : r.scans) s.T_world_laser = T * s.T_world_laser, s.T_world_odom = T * s.T_world_odom;
  for (Pose2& p : r.front_end_poses) p = T * p;
  for (Submap& m : r.submaps) m.T_world_map = T * m.T_world_map;
  for (Pose2& p : r.stored_frames) p = T * p;
  for (Pose2& p : r.back_end.frames) p = T * p;
  for (MapCheck* m : {&r.map_check, &r.front_end_map_check}) {
    for (auto& place : m->places) place.centre = T * place.centre;
    m->worst_place = T * m->worst_place;
  }
}

// `to_log` turns the walls' frame the log was mapped in back into the log's own, for the places a reason names.
SlamResult run_slam_aligned(const Scans& raw, const SlamConfig& config, const Progress& progress,
                            const ClosureHook& hook, const Pose2& to_log = {});

}  // namespace

SlamResult run_slam(const Scans& log, const SlamConfig& config, const Progress& progress, const ClosureHook& hook) {
  validate(config);
  if (!config.align_to_walls) return run_slam_aligned(log, config, progress, hook);  // no copy; wall_axis 0
  const double wall_axis = log_wall_axis(log);
  const Pose2 onto_walls{0, 0, -wall_axis};
  Scans raw = log;
  for (Scan& s : raw) s.T_world_laser = onto_walls * s.T_world_laser, s.T_world_odom = onto_walls * s.T_world_odom;
  SlamResult r = run_slam_aligned(raw, config, progress, hook, onto_walls.inverse());
  turn_result(r, onto_walls.inverse());
  r.wall_axis = wall_axis;
  return r;
}

namespace {

SlamResult run_slam_aligned(const Scans& raw, const SlamConfig& config, const Progress& progress,
                            const ClosureHook& hook, const Pose2& to_log) {
  SlamResult r;
  // The second opinion's front end: on a thread of its own beside the first when the first has more than one,
  // else after it (deferred to its get()). The front end's answer does not depend on its threads.
  FrontEndConfig first = config.front_end;
  std::future<Scans> second;
  if (config.second_opinion.enabled) {
    FrontEndConfig other = config.front_end;
    other.fine_sigma = config.second_opinion.fine_sigma;
    other.matcher.num_threads = 1;
    const bool beside = first.matcher.num_threads > 1;
    if (beside) --first.matcher.num_threads;
    second = std::async(beside ? std::launch::async : std::launch::deferred, [&raw, other, &r] {
      const auto t = Clock::now();
      Scans scans = scan_match_log(raw, other).scans;
      r.second_opinion_s = ms_since(t) / 1e3;
      return scans;
    });
  }
  auto t0 = Clock::now();
  FrontEndResult fe = scan_match_log(raw, first, progress);
  r.front_end = fe.stats;
  r.front_end_s = ms_since(t0) / 1e3;
  const Submaps maps = build_submaps(fe.scans, config.submaps);
  if (maps.empty()) throw InputError("slam: no submap could be built (too little travel or too few points)");

  t0 = Clock::now();
  r.closures = find_loop_closures(maps, config.loops, progress);
  std::vector<LoopClosure> accepted;
  for (const LoopClosure& l : r.closures)
    if (l.confidence >= config.min_confidence) accepted.push_back(l);
  r.loops_s = ms_since(t0) / 1e3;
  t0 = Clock::now();
  accepted = refine_closures(fe.scans, maps, config.submaps.window_length, std::move(accepted), config.refinement);
  r.refine_s = ms_since(t0) / 1e3;
  if (hook) hook(maps, accepted);
  r.accepted = accepted.size();

  t0 = Clock::now();
  r.back_end = solve_back_end(maps, accepted, config.back_end);
  r.offered = std::move(accepted);
  const std::vector<Pose2>& optimised = r.back_end.frames;
  r.submaps = maps;
  for (const Submap& m : maps) r.stored_frames.push_back(m.T_world_map);
  for (const Scan& s : fe.scans) r.front_end_poses.push_back(s.T_world_laser);
  for (std::size_t k = 0; k < maps.size(); ++k) r.submaps[k].T_world_map = optimised[k];
  r.scans = corrected_scans(fe.scans, maps, r.submaps);
  r.graph_s = ms_since(t0) / 1e3;
  t0 = Clock::now();
  r.scans = refine_on_neighbours(r.scans, config.neighbours, config.front_end, &r.neighbours);
  r.neighbours_s = ms_since(t0) / 1e3;
  t0 = Clock::now();
  r.map_check = check_map(r.scans, config.map_check);
  r.front_end_map_check = check_map(fe.scans, config.map_check);
  r.check_s = ms_since(t0) / 1e3;
  if (second.valid()) {
    // Where the used closures attach (their submaps' anchor scans), unless the map written is the front end's.
    std::vector<std::size_t> pins;
    for (std::size_t k = 0; !r.back_end.front_end_written && k < r.offered.size() && k < r.back_end.used.size(); ++k)
      if (r.back_end.used[k])
        for (std::size_t m : {r.offered[k].query, r.offered[k].match})
          pins.push_back(static_cast<std::size_t>(maps.at(m).anchor_scan));
    r.second_opinion = compare_front_ends(fe.scans, second.get(), config.second_opinion, pins);
  }
  if (!r.map_check.passed && r.back_end.trusted()) {
    std::ostringstream why;
    const MapCheck& m = r.map_check;
    const Vec2 place = to_log * m.worst_place;  // where map.png and slam.json have it
    why << std::fixed << std::setprecision(1) << 100 * m.crossing_share
        << " % of the beams that revisit a place cross a wall another visit saw, " << 100 * m.worst_place_share
        << " % near (" << place.x() << ", " << place.y() << ") (limits "
        << 100 * config.map_check.max_crossing_share << " % and " << 100 * config.map_check.max_place_share
        << " % at a place): a place drawn twice, or turned";
    r.back_end.verdict = "doubtful";
    r.back_end.reason = why.str();
  }
  if (degenerate_share(r.front_end) > config.max_degenerate_share && r.back_end.trusted()) {
    std::ostringstream why;
    why << std::fixed << std::setprecision(0) << 100 * degenerate_share(r.front_end)
        << " % of the scans fix no position along a bare corridor (limit " << 100 * config.max_degenerate_share
        << " %): the map's lengths there are the odometry's";
    if (r.front_end.scaled > 0)
      why << std::setprecision(3) << " (times " << r.front_end.odometry_scale
          << ", its scale as measured where the scans fix both directions)";
    r.back_end.verdict = "doubtful";
    r.back_end.reason = why.str();
  }
  if (r.front_end.turns_against_odometry() && r.back_end.trusted()) {
    std::ostringstream why;
    why << std::fixed << std::setprecision(2) << "the scans turn against the odometry (slope "
        << r.front_end.turn_slope() << " over " << r.front_end.turning_steps
        << " turning steps)"
        << (config.front_end.mirror_check ? ", mirrored or not: the laser's mounting or the odometry's heading is wrong"
                                          : ": a laser mounted upside down (front_end.mirror_check, off here, reads "
                                            "it mirrored), or the odometry's heading is wrong");
    r.back_end.verdict = "doubtful";
    r.back_end.reason = why.str();
  }
  if (!r.second_opinion.passed && r.back_end.trusted()) {
    const FrontEndAgreement& a = r.second_opinion;
    const SecondOpinionConfig& c = config.second_opinion;
    std::ostringstream why;
    why << std::fixed << second_opinion_parting(a, c) << " that no loop closure ties, most from "
        << std::setprecision(1) << fe.scans[a.worst_first].timestamp - fe.scans.front().timestamp << " to "
        << fe.scans[a.worst_last].timestamp - fe.scans.front().timestamp << " s into the log ("
        << second_opinion_limits(c)
        << "): the scans do not fix the path there, and nothing says which of the two is right";
    r.back_end.verdict = "doubtful";
    r.back_end.reason = why.str();
  }
  return r;
}

}  // namespace

std::string verdict_checks(const SlamResult& r, const SlamConfig& c) {
  const BackEndResult& b = r.back_end;
  std::ostringstream out;
  out << std::fixed << b.used_count << " of " << b.used.size() << " closures offered agree with the solution (at least "
      << std::setprecision(0) << 100 * (1 - c.back_end.max_rejected_share)
      << " % must); they bend the front end's trajectory by up to " << std::setprecision(2)
      << b.max_chain_translation << " m / " << b.max_chain_rotation << " rad between consecutive submaps (limits "
      << c.back_end.max_chain_translation << " m / " << c.back_end.max_chain_rotation << " rad); "
      << std::setprecision(1) << 100 * r.map_check.crossing_share
      << " % of the beams that revisit a place cross a wall another visit saw (limit " << std::setprecision(0)
      << 100 * c.map_check.max_crossing_share << " %" << (r.map_check.judged ? "" : ", too few beams to judge")
      << "); " << 100 * degenerate_share(r.front_end) << " % of the scans fix no position along a bare corridor (limit "
      << 100 * c.max_degenerate_share << " %); the scans turn with the odometry at a slope of " << std::setprecision(2)
      << r.front_end.turn_slope() << " over " << r.front_end.turning_steps << " turning steps (at least 0 over "
      << kMinTurningSteps << (r.front_end.mirrored ? "; read mirrored: a laser mounted upside down)" : ")");
  const FrontEndAgreement& a = r.second_opinion;
  if (!c.second_opinion.enabled)
    out << "; no second front end (second_opinion.enabled off)";
  else if (!a.judged)
    out << "; a second front end: " << (a.pinned > 0 ? "loop closures tie every " : "too little travel for a ")
        << std::setprecision(0) << c.second_opinion.window << " m of travel to compare";
  else
    out << "; " << second_opinion_parting(a, c.second_opinion) << " (" << second_opinion_limits(c.second_opinion)
        << "; " << a.pinned << " of " << a.pinned + a.windows << " windows, tied by loop closures, not compared)";
  return out.str();
}

}  // namespace partslam
