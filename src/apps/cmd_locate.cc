// partslam locate --map map.yaml --query-log LOG (a stretch, apps/query_options.h | --every M) | --query-points FILE:
// global localisation in a building map (core/matching/localizer.h). The map is a ROS map_server map (map.yaml + PGM,
// thresholds, negate and origin honoured); the local map is built from a stretch of a log as submaps are, or read
// from a point file. Prints, per local map, its pose in the map frame, where that puts the robot (the first scan of
// the stretch) or the point file's frame, the inlier share, the confidence (score minus the best other candidate's;
// >= 0.2 was never wrong on fr079, docs/NOTES.md "Locate"), the verified same-place probability at the refined pose
// and the time; --json writes the same; --plot draws it. --every M locates a local map every M of travel along the
// whole log, with a progress bar. --config FILE.yaml sets the local map's and the localizer's settings
// (io/formats/config_file.h, LocateConfig; flags given override it), --print-config shows them all.
// Tested by: apps/cli_locate_test.cc
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "apps/commands.h"
#include "apps/config_options.h"
#include "apps/json_text.h"
#include "apps/progress_bar.h"
#include "apps/query_options.h"
#include "core/error.h"
#include "core/maps/grid_map.h"
#include "core/matching/localizer.h"
#include "core/matching/tracker.h"
#include "core/timing.h"
#include "io/files/atomic_file.h"
#include "io/formats/config_file.h"
#include "io/formats/map_server.h"
#include "io/formats/result_mcap.h"
#include "plot/answer_image.h"

namespace partslam::apps {
namespace {


struct LocateOptions {
  std::string map;
  std::string config_file;  ///< --config
  QueryOptions query;
  std::optional<double> every;  ///< --every M: given (even as 0 or less) or not
  bool track = false;           ///< --track: the tracker over the log's local maps (core/matching/tracker.h)
  TrackerConfig tracker;
  SubmapConfig submap;
  LocalizerConfig localizer;
  std::string json;
  std::string plot;
  std::string mcap;
  bool quiet = false;
};

struct Located {
  std::string label;
  Localization result;
  Pose2 T_map_source;            // the log's world frame or the point file's frame, in the map
  std::optional<Pose2> robot;    // the stretch's first laser pose in the map (logs)
  std::optional<Pose2> robot_in_log;  // the same pose in the log's own frame (logs)
  double stamp = 0;              // the log time of the stretch's first scan (logs)
  Points2 points_in_map;         // the local map's points where they were found (kept for --plot)
};

void print(const Located& l) {
  const Localization& r = l.result;
  const std::string why = not_confident_because(r);
  const std::string low = why.empty() ? "" : " (low: " + why + ")";
  const Pose2& p = l.robot ? *l.robot : l.T_map_source;
  std::printf("%s\n  %s in the map: x %.2f m, y %.2f m, theta %.1f deg; inliers %.1f %%, %d on free space; "
              "confidence %.3f%s; same-place probability %.3f%s; %.1f ms\n",
              l.label.c_str(), l.robot ? "robot" : "points' frame", p.x, p.y, p.theta * kDegreesPerRadian,
              100 * r.inlier_fraction, r.free_conflicts, r.confidence, low.c_str(),
              r.probability, r.calibrated ? "" : " (bare points: no laser origins)", r.time_ms);
}

nlohmann::json located_json(const Located& l) {
  const Localization& r = l.result;
  nlohmann::json j = {
      {"query", l.label},
      {"T_map_query", pose_json(r.T_map_query)},
      {"T_map_source", pose_json(l.T_map_source)},
      {"inliers", r.inliers},
      {"inlier_fraction", r.inlier_fraction},
      {"terms",
       {{"query_occupied", r.terms.query.occupied},
        {"query_free", r.terms.query.free},
        {"query_seen", r.terms.query.seen},
        {"map_occupied", r.terms.map.occupied},
        {"map_free", r.terms.map.free},
        {"map_seen", r.terms.map.seen},
        {"query_fit", r.terms.query_fit},
        {"map_fit", r.terms.map_fit},
        {"query_corner", r.terms.query.corner},
        {"map_corner", r.terms.map.corner},
        {"query_corner_fit", r.terms.query_corner_fit},
        {"map_corner_fit", r.terms.map_corner_fit}}},
      {"T_map_lattice", pose_json(r.T_map_lattice)},
      {"free_conflicts", r.free_conflicts},
      {"score", r.score},
      {"probability", r.probability},
      {"calibrated", r.calibrated},
      {"confidence", r.confidence},
      {"confident", is_confident(r)},
      {"not_confident_because", not_confident_because(r)},
      {"elsewhere", {{"score", r.elsewhere_score}, {"T_map_query", pose_json(r.T_map_elsewhere)}}},
      {"candidates", r.candidates},
      {"time_ms", r.time_ms}};
  if (l.robot) j["robot_pose"] = pose_json(*l.robot);
  return j;
}

Located locate_one(const Localizer& localizer, const Submap& query, const Scans& scans, std::string label,
                   bool keep_points) {
  Located l;
  l.label = std::move(label);
  l.result = localizer.locate(query.points, query.origins);
  if (keep_points) l.points_in_map = plot::transformed(query.points, l.result.T_map_query);
  l.T_map_source = l.result.T_map_query * query.T_world_map.inverse();
  if (!scans.empty()) {
    l.robot_in_log = scans[static_cast<std::size_t>(query.anchor_scan)].T_world_laser;
    l.stamp = scans[static_cast<std::size_t>(query.anchor_scan)].timestamp;
    l.robot = l.T_map_source * *l.robot_in_log;
  }
  return l;
}

// --plot: the building map with the local map's points where they were found (green when confident, orange
// when not), or, for --every, the located robot poses joined in travel order and coloured so.
void write_plot(const LocateOptions& o, const GridMap& map, const std::vector<Located>& located) {
  plot::Panel panel;
  panel.map = &map;
  char title[400];
  if (located.size() == 1) {
    const Located& l = located.front();
    const Pose2& p = l.robot ? *l.robot : l.T_map_source;
    const bool confident = is_confident(l.result);
    std::snprintf(title, sizeof title, "%s at x %.2f m, y %.2f m, %.1f deg; inliers %.0f %%; confidence %.2f (%s)",
                  l.robot ? "robot" : "points' frame", p.x, p.y, p.theta * kDegreesPerRadian,
                  100 * l.result.inlier_fraction, l.result.confidence, confident ? "confident" : "low");
    panel.layers.push_back({l.points_in_map, confident ? plot::kGood : plot::kDoubtful, 1.5});
    panel.path = {p.translation()};  // the robot (or the points' frame) as a dot
  } else {
    std::size_t confident = 0, breaks = 0;
    for (std::size_t i = 0; i < located.size(); ++i) {
      const Located& l = located[i];
      const Pose2& p = l.robot ? *l.robot : l.T_map_source;
      panel.path.push_back(p.translation());
      const bool sure = is_confident(l.result);
      panel.path_colours.push_back(sure ? plot::kGood : plot::kDoubtful);
      confident += sure;
      // A line only where two consecutive answers moved as the log did: a wrong answer stands alone.
      const Located* before = i > 0 ? &located[i - 1] : nullptr;
      const bool joined = before != nullptr && l.robot && before->robot &&
                          answers_agree(*before->robot, *l.robot, *before->robot_in_log, *l.robot_in_log);
      panel.path_joined.push_back(joined);
      breaks += i > 0 && !joined;
    }
    std::snprintf(title, sizeof title, "%zu local maps every %.1f m: %zu confident, %zu low; %zu breaks in the line",
                  located.size(), o.every.value_or(0.0), confident, located.size() - confident, breaks);
  }
  panel.title = title;
  panel.legend = located.size() == 1 ? "the local map's points; the dot: the robot"
                                     : "green: confident; orange: low; a line: two answers that moved as the log did";
  plot::write_panels_png(o.plot, {panel});
  std::printf("wrote %s\n", o.plot.c_str());
}

// The combination of options, checked before any work.
void check_options(const LocateOptions& o) {
  if (!o.query.given()) throw InputError("locate: give --query-log LOG or --query-points FILE");
  if (o.every && (!(*o.every > 0) || !std::isfinite(*o.every)))
    throw InputError("--every must be a positive number of metres, got " + std::to_string(*o.every));
  check_query_options(o.query, /*with_every=*/o.every.has_value() || o.track);
  if (o.every && (o.query.log.empty() || o.query.stretch.given()))
    throw InputError("--every goes with --query-log alone (it sweeps the whole log)");
  if (o.track && (o.query.log.empty() || o.query.stretch.given()))
    throw InputError("--track goes with --query-log alone (it follows the whole log)");
  validate(o.tracker);
  validate(o.submap);
  validate(o.localizer);
  io::check_outputs({{"--json", o.json}, {"--plot", o.plot}, {"--mcap", o.mcap}},
                    {{"--map", o.map}, {"--query-log", o.query.log}, {"--query-points", o.query.points}});
}

// A local map every M of travel along the whole log (--every), handed to `use` in travel order with its label;
// a progress bar named `what`.
template <typename Use>
void for_each_local_map(const LocateOptions& o, const Scans& scans, double every, const char* what, Use&& use) {
  const std::vector<double> s = travel_distances(scans);
  if (!s.empty() && s.back() / every > 100000) {
    char why[200];
    std::snprintf(why, sizeof why, "--every %g m: %.3g local maps along %.1f m of travel (at most 100000; take a "
                  "larger --every)", every, s.back() / every, s.back());
    throw InputError(why);
  }
  ProgressBar bar(!o.quiet);
  const auto total = static_cast<std::size_t>(s.empty() ? 0.0 : std::floor(s.back() / every)) + 1;
  std::size_t skipped = 0, done = 0;
  for (double from = 0; !s.empty() && from + o.submap.window_length <= s.back(); from += every) {
    bar(what, done++, total);
    Submap query;
    try {
      query = build_local_map(scans, from, from + o.submap.window_length, o.submap);
    } catch (const InputError&) {
      ++skipped;  // too few points in this stretch
      continue;
    }
    char label[160];
    std::snprintf(label, sizeof label, "%.1f .. %.1f m of travel, log time %.3f .. %.3f s", from,
                  from + o.submap.window_length, query.scan_timestamps.front(), query.scan_timestamps.back());
    use(query, std::string(label));
  }
  if (skipped) std::printf("%zu stretches had too few points for a local map\n", skipped);
}

// --every M: a local map every M of travel along the whole log, located one after the other.
std::vector<Located> locate_every(const LocateOptions& o, const Localizer& localizer, const Scans& scans) {
  std::vector<Located> located;
  for_each_local_map(o, scans, *o.every, "locate", [&](const Submap& query, std::string label) {
    located.push_back(locate_one(localizer, query, scans, std::move(label), !o.plot.empty()));
  });
  return located;
}

// --track: one tracker step per local map (--every M, 2 m by default), its motion from the log's own poses.
struct Tracked {
  std::string label;
  double from_time = 0, to_time = 0;  // the local map's log time span [s]
  TrackStep step;
  std::optional<Pose2> T_map_source, robot;  // when the step has a pose (the declared or the heaviest)
  std::optional<Pose2> robot_now;            // ... and the robot at the local map's last scan (where it is now)
  double now_stamp = 0;                      // that scan's log time [s]
  std::vector<Pose2> hypothesis_robots;      // every hypothesis's robot pose, heaviest first
  double stamp = 0;                          // the anchor scan's log time [s]
  Pose2 robot_in_log;                        // the anchor scan's pose in the log's own frame
};

std::vector<Tracked> track_log(const LocateOptions& o, const Localizer& localizer, const Scans& scans) {
  Tracker tracker(localizer, o.tracker);
  std::vector<Tracked> out;
  for_each_local_map(o, scans, o.every.value_or(2.0), "track", [&](const Submap& query, std::string label) {
    Tracked t;
    t.label = std::move(label);
    t.from_time = query.scan_timestamps.front(), t.to_time = query.scan_timestamps.back();
    t.step = tracker.step(query.points, query.origins, query.T_world_map);
    const Scan& anchor = scans[static_cast<std::size_t>(query.anchor_scan)];
    t.stamp = anchor.timestamp;
    t.robot_in_log = anchor.T_world_laser;
    const auto robot_of = [&](const Pose2& T_map_query) { return T_map_query * query.T_world_map.inverse() * anchor.T_world_laser; };
    std::size_t last = static_cast<std::size_t>(query.anchor_scan);  // the local map's last scan
    while (last + 1 < scans.size() && scans[last].timestamp < query.scan_timestamps.back()) ++last;
    t.now_stamp = scans[last].timestamp;
    if (t.step.has_pose) {
      t.T_map_source = t.step.best.T_map_query * query.T_world_map.inverse();
      t.robot = robot_of(t.step.best.T_map_query);
      t.robot_now = *t.T_map_source * scans[last].T_world_laser;
    }
    for (const TrackHypothesis& h : t.step.hypotheses) t.hypothesis_robots.push_back(robot_of(h.T_map_query));
    out.push_back(std::move(t));
  });
  return out;
}

void print_tracked(const std::vector<Tracked>& tracked, bool scan_matched) {
  std::vector<double> times;
  std::size_t localised = 0, lost = 0;
  std::optional<std::size_t> first;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    const Tracked& t = tracked[i];
    const TrackStep& s = t.step;
    times.push_back(s.time_ms);
    const bool is_localised = s.status == TrackStatus::kLocalised;
    localised += is_localised;
    lost += s.status == TrackStatus::kLost && (i == 0 || tracked[i - 1].step.status != TrackStatus::kLost);
    if (is_localised && !first) first = i;
    std::printf("%s\n  %s", t.label.c_str(), to_string(s.status));
    if (t.robot)
      std::printf("; %s robot x %.2f m, y %.2f m, theta %.1f deg, probability %.3f", is_localised ? "" : "likeliest:",
                  t.robot->x, t.robot->y, t.robot->theta * kDegreesPerRadian, s.best.share);
    std::printf("; %zu hypotheses%s%s; %.1f ms\n", s.hypotheses.size(), s.searched ? ", searched" : "",
                s.evidence ? "" : ", no evidence (the map never saw this place)", s.time_ms);
  }
  if (tracked.empty()) return;
  std::sort(times.begin(), times.end());
  std::printf("%zu steps, %zu localised (first at step %s), lost %zu times; time per step: median %.1f ms, "
              "max %.1f ms\n",
              tracked.size(), localised, first ? std::to_string(*first + 1).c_str() : "none", lost,
              times[times.size() / 2], times.back());
  // A raw log's odometry bends a 2 m local map (fr079's bag: 34 of 196 steps localised, 190 of 200 with
  // --scan-match).
  if (!scan_matched && 2 * localised < tracked.size())
    std::fprintf(stderr,
                 "hint: fewer than half the steps were localised; the local maps were built on the log's own poses: "
                 "for a raw log (poses from odometry) add --scan-match\n");
}

nlohmann::json tracked_json(const Tracked& t) {
  const TrackStep& s = t.step;
  nlohmann::json j = {{"query", t.label},
                      {"log_time", {{"from", t.from_time}, {"to", t.to_time}}},
                      {"status", to_string(s.status)},
                      {"searched", s.searched},
                      {"evidence", s.evidence},
                      {"none_share", s.none_share},
                      {"time_ms", s.time_ms}};
  if (s.has_pose) {
    j["T_map_query"] = pose_json(s.best.T_map_query);
    j["T_map_source"] = pose_json(*t.T_map_source);
    j["robot_pose"] = pose_json(*t.robot);
    j["robot_pose_time"] = t.stamp;  // robot_pose is the local map's first scan's, as locate --every writes it
    j["robot_pose_now"] = pose_json(*t.robot_now);
    j["robot_pose_now_time"] = t.now_stamp;
    j["probability"] = s.best.share;  // the declared (or heaviest) hypothesis's share of the weight
    j["same_place_probability"] = s.best.probability;
  }
  j["hypotheses"] = nlohmann::json::array();
  for (std::size_t k = 0; k < s.hypotheses.size(); ++k) {
    const TrackHypothesis& h = s.hypotheses[k];
    j["hypotheses"].push_back({{"T_map_query", pose_json(h.T_map_query)},
                               {"robot_pose", pose_json(t.hypothesis_robots[k])},
                               {"share", h.share},
                               {"same_place_probability", h.probability},
                               {"age", h.age}});
  }
  return j;
}

// --track --plot: the robot's path coloured by status (green localised, orange searching, red lost), joined where
// consecutive steps both have a pose; every step's hypotheses as faint dots.
void write_track_plot(const LocateOptions& o, const GridMap& map, const std::vector<Tracked>& tracked) {
  plot::Panel panel;
  panel.map = &map;
  plot::PointLayer hypotheses{{}, {0.55, 0.55, 0.85}, 1.0};
  std::size_t localised = 0;
  const Tracked* before = nullptr;  // the last step with a pose
  for (const Tracked& t : tracked) {
    for (const Pose2& h : t.hypothesis_robots) hypotheses.points.push_back(h.translation());
    if (!t.robot) {
      before = nullptr;
      continue;
    }
    // A line only where two consecutive poses moved as the log did.
    const bool joined = before != nullptr && answers_agree(*before->robot, *t.robot, before->robot_in_log, t.robot_in_log);
    before = &t;
    panel.path.push_back(t.robot->translation());
    const TrackStatus status = t.step.status;
    localised += status == TrackStatus::kLocalised;
    panel.path_colours.push_back(status == TrackStatus::kLocalised ? plot::kGood
                                 : status == TrackStatus::kLost   ? plot::Rgb{0.85, 0.1, 0.1}
                                                                  : plot::kDoubtful);
    panel.path_joined.push_back(joined);
  }
  if (!hypotheses.points.empty()) panel.layers.push_back(hypotheses);
  char title[200];
  std::snprintf(title, sizeof title, "tracked: %zu steps every %.1f m, %zu localised", tracked.size(), o.every.value_or(2.0),
                localised);
  panel.title = title;
  panel.legend = "green: localised; orange: searching (the likeliest); red: lost; faint: hypotheses; a line: moved as the log did";
  plot::write_panels_png(o.plot, {panel});
  std::printf("wrote %s\n", o.plot.c_str());
}

// Every localisation, and for several the confident count and the time per local map.
void print_all(const std::vector<Located>& located) {
  std::vector<double> times;
  std::size_t confident = 0;
  for (const Located& l : located) {
    print(l);
    times.push_back(l.result.time_ms);
    confident += is_confident(l.result);
  }
  if (located.size() > 1) {
    std::sort(times.begin(), times.end());
    std::printf("%zu local maps, %zu confident (>= %.1f, probability >= %.3f); time per local map: median %.1f ms, "
                "max %.1f ms\n",
                located.size(), confident, ConfidenceRule{}.min_margin, ConfidenceRule{}.min_probability, times[times.size() / 2],
                times.back());
  }
}

void run_locate(const LocateOptions& o) {
  check_options(o);
  auto t0 = Clock::now();
  const GridMap map = io::read_map_yaml(o.map);
  const Localizer localizer(map, o.localizer);
  std::printf("map %s: %d x %d cells at %.3f m; prepared in %.0f ms (read %.0f ms)\n", o.map.c_str(), map.width,
              map.height, map.resolution, localizer.prepare_ms(), ms_since(t0) - localizer.prepare_ms());
  std::vector<double> wings;
  for (const double d : localizer.wing_directions()) wings.push_back(d * kDegreesPerRadian);
  if (!wings.empty()) {
    std::printf("walls off the map's axes, searched too:");
    for (const double d : wings) std::printf(" %+.0f deg", d);
    std::printf("\n");
  }
  const QueryLog log = o.query.log.empty() ? QueryLog{} : load_query_log(o.query, {}, o.submap.window_length);
  if (o.track) {
    const std::vector<Tracked> tracked = track_log(o, localizer, log.scans);
    print_tracked(tracked, o.query.scan_match);
    if (!o.plot.empty() && !tracked.empty()) write_track_plot(o, map, tracked);
    if (!o.mcap.empty() && !tracked.empty()) {
      std::vector<io::LocatedPose> poses;
      for (const Tracked& t : tracked)
        if (t.robot) poses.push_back({t.stamp, *t.robot, t.step.status == TrackStatus::kLocalised});
      io::write_located_mcap(o.mcap, map, poses);
      std::printf("wrote %s\n", o.mcap.c_str());
    }
    if (!o.json.empty()) {
      nlohmann::json out = {{"map", o.map}, {"prepare_ms", localizer.prepare_ms()}, {"every", o.every.value_or(2.0)},
                            {"warnings", log.warnings}};
      out["tracked"] = nlohmann::json::array();
      for (const Tracked& t : tracked) out["tracked"].push_back(tracked_json(t));
      io::write_atomically(o.json, [&](std::ostream& f) { f << json_text(out); });
    }
    return;
  }
  std::vector<Located> located;
  if (o.every) {
    located = locate_every(o, localizer, log.scans);
  } else {
    std::string label;
    const Submap query = build_query(o.query, log, o.submap, label);
    located.push_back(locate_one(localizer, query, log.scans, label, !o.plot.empty()));
  }
  print_all(located);
  if (!o.plot.empty() && !located.empty()) write_plot(o, map, located);
  if (!o.mcap.empty() && !located.empty()) {
    std::vector<io::LocatedPose> poses;
    for (const Located& l : located) poses.push_back({l.stamp, l.robot ? *l.robot : l.T_map_source, is_confident(l.result)});
    io::write_located_mcap(o.mcap, map, poses);
    std::printf("wrote %s\n", o.mcap.c_str());
  }
  if (!o.json.empty()) {
    nlohmann::json out = {{"map", o.map}, {"prepare_ms", localizer.prepare_ms()}, {"confident_at", ConfidenceRule{}.min_margin},
                          {"confident_probability_at", ConfidenceRule{}.min_probability},
                          {"wing_directions_deg", wings},
                          {"warnings", log.warnings}};
    out["located"] = nlohmann::json::array();
    for (const Located& l : located) out["located"].push_back(located_json(l));
    io::write_atomically(o.json, [&](std::ostream& f) { f << json_text(out); });
  }
}

}  // namespace

void register_locate(CLI::App& app) {
  auto o = std::make_shared<LocateOptions>();
  CLI::App* cmd = app.add_subcommand("locate", "Find where a new local map lies in a building map (map_server)");
  cmd->add_option("--map", o->map, "the building map: a map_server map.yaml (PGM image)")->required();
  o->query.offers_every = true;
  add_query_options(*cmd, o->query);
  cmd->add_option("--every", o->every, "--query-log: locate a local map every this much travel along the log [m]");
  cmd->add_flag("--track", o->track,
                "--query-log: track the robot along the log (several hypotheses carried by its motion until one "
                "dominates; status searching / localised / lost per local map, every --every M, 2 m by default)");
  cmd->add_option("--hypotheses", o->tracker.hypotheses, "--track: distinct poses a global search adds")
      ->capture_default_str();
  cmd->add_option("--window", o->submap.window_length, "travel a local map covers [m]")->capture_default_str();
  cmd->add_option("--max-range", o->submap.max_range, "beams longer than this are not used [m]")->capture_default_str();
  cmd->add_option("--candidates", o->localizer.candidates, "distinct poses examined per local map")
      ->capture_default_str();
  cmd->add_option("--json", o->json, "write every localisation (pose, confidence, time) as JSON");
  cmd->add_option("--mcap", o->mcap,
                  "write the building map and every answer as ROS 2 messages (MCAP: /map, /located/path, /located "
                  "markers, green confident, orange low) for Foxglove");
  cmd->add_option("--plot", o->plot,
                  "draw the answer as a PNG: the local map's points on the building map where they were found "
                  "(--every: the located trajectory), green when confident, orange when not");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  add_config_options(*cmd, o->config_file, [] { return io::config_yaml(io::LocateConfig{}); });
  cmd->callback([o, cmd] {
    if (!o->config_file.empty()) {  // the file's settings, then the flags given
      io::LocateConfig f;
      io::read_config_file(o->config_file, f);
      if (given(*cmd, "--window")) f.submaps.window_length = o->submap.window_length;
      if (given(*cmd, "--max-range")) f.submaps.max_range = o->submap.max_range;
      if (given(*cmd, "--candidates")) f.localizer.candidates = o->localizer.candidates;
      if (given(*cmd, "--hypotheses")) f.tracker.hypotheses = o->tracker.hypotheses;
      o->submap = f.submaps;
      o->localizer = f.localizer;
      o->tracker = f.tracker;
    }
    run_locate(*o);
  });
}

}  // namespace partslam::apps
