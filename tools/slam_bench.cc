// slam_bench: one run of the SLAM generalisation bench (scripts/slam-bench.sh, `make slam-bench`; docs/NOTES.md
// "SLAM bench"). Prints one JSON object: the relation errors of `slam` (core/slam/slam.h, its defaults; also
// split into relations within one visit, scans at most 10 s apart, and between visits), of the log's odometry and
// of the front end alone, the closures offered to the back end, how many are wrong against the truth and how many
// of those it used, the verdict and the time.
//
//   slam_bench twin CORRECTED_LOG LEVEL SEED [INJECT]
//       the drifted twin (core/evaluation/drifted_twin.h) of a corrected log at LEVEL (mild, harsh) and SEED;
//       the corrected poses are the truth, the relations are built from them.
//   slam_bench sim SCENARIO LEVEL SEED [INJECT]
//       a simulated building that stresses the front end (core/sim/simulator.h), exact poses as the truth, the
//       odometry drifted at LEVEL: "corridors" (a 120 m ring of long bare corridors), "hall" (a 10 m wide ring
//       round a large open hall), "long-range" (an 80 m x 60 m building seen by a 60 m laser).
//   slam_bench raw RAW_LOG TWIN_LOG [RELATIONS] [INJECT]
//       a raw log; its scans associated by content with the corrected TWIN_LOG (a subset may do) give the truth of
//       the closures, and the relations (from the file when given, else built from the twin; with both, the
//       twin's own poses and slam's result judged by relations built from the twin are printed too:
//       "twin_reference", "slam_against_twin"). TWIN_LOG "-": no twin (the relations file is then needed;
//       closures and front-end steps are not judged).
// Ablations (docs/NOTES.md "SLAM bench") override front-end settings from the environment: FE_MAX_RANGE,
// FE_SIGMA, FE_FINE (fine_sigma), FE_DEGENERATE (degenerate_ratio), FE_HALF_RATIO and FE_HALF_SLACK
// (half_constrained_ratio, _slack), FE_LINEAR, FE_ANGULAR, FE_MIN_SCORE, FE_KEY (key_translation),
// LOOPS_CONSISTENCY_MAX_CHAIN, _LONG_CHAIN, _LONG_FACTOR (loops.consistency.max_chain, ...), NEIGHBOUR_ROUNDS
// (neighbours.rounds: 0 turns the neighbour refinement off), SIM_REFERENCE_JITTER=M,DEG (sim: the odometry drifted
// from a jittered reference, as a twin's; see sim_bench); SLAM_BENCH_CLOSURES=1
// adds every judged closure's gap and disagreement with the front end; SLAM_BENCH_PLACES=1 adds the map checks'
// places (x, y, revisiting and crossing beams of each place with at least 100 revisiting beams: two thirds of a
// line's size, so the committed bench leaves them out).
// INJECT: wrong closures added to the accepted ones, as a fraction of their count (0.5 = 50 % extra), each
// between two submaps whose true frames are more than 5 m apart, with a pose within 1 m / 0.3 rad of identity.
// A trailing "f" (0.1f) forces them in: the back end sets no closure aside and its loss is quadratic (no Cauchy),
// so the map is made wrong on purpose
// (what the verdict must then say is calibrated on these runs).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/evaluation/drifted_twin.h"
#include "core/evaluation/relation_check.h"
#include "core/evaluation/trajectory_check.h"
#include "core/random.h"
#include "core/maps/submap.h"
#include "core/sim/simulator.h"
#include "core/slam/slam.h"
#include "io/logs/relations.h"
#include "io/logs/scan_source.h"

using namespace partslam;

namespace {

Scans with_poses(const Scans& scans, const std::vector<Pose2>& poses) {
  Scans out;
  out.reserve(scans.size());
  for (std::size_t i = 0; i < scans.size(); ++i) {
    Scan s;
    s.timestamp = scans[i].timestamp;
    s.T_world_laser = s.T_world_odom = poses[i];
    out.push_back(s);
  }
  return out;
}

// Per scan of `scans`, the index of the truth scan of the same timestamp (the truth is the raw scans re-posed).
std::vector<std::optional<std::size_t>> index_by_time(const Scans& scans, const Scans& truth) {
  std::vector<std::optional<std::size_t>> out(scans.size());
  std::size_t j = 0;
  for (std::size_t i = 0; i < scans.size(); ++i) {
    while (j < truth.size() && truth[j].timestamp < scans[i].timestamp) ++j;
    if (j < truth.size() && truth[j].timestamp == scans[i].timestamp) out[i] = j;
  }
  return out;
}

struct Bench {
  std::string name;
  Scans raw;     // what slam reads
  Scans truth;   // the true poses of the raw scans it has (same timestamps; a subset for raw logs)
  Relations relations;
  // A raw log's laser mount (io::ScanSource::T_base_laser): robot poses are judged by its relations file, as `slam
  // --relations` judges them, so the mount is taken off the laser's poses. Identity for relations built from laser
  // poses.
  Pose2 mount;
  bool retimed = false;
  // Poses other than the truth that a twin-like run is judged by too: a raw log's corrected twin (when a relations
  // file is the truth), or sim with SIM_REFERENCE_JITTER: the truth jittered, what the odometry is drifted from.
  Scans reference;
};

Bench twin_bench(const std::string& log, const std::string& level, std::uint64_t seed) {
  Bench b;
  b.truth = io::load_scan_source(log).scans;
  // Some corrected logs carry no time (orebro: every stamp 0); relations name scans by time, so those are
  // re-timed at 10 Hz.
  bool increasing = true;
  for (std::size_t i = 1; i < b.truth.size(); ++i) increasing = increasing && b.truth[i].timestamp > b.truth[i - 1].timestamp;
  if (!increasing)
    for (std::size_t i = 0; i < b.truth.size(); ++i) b.truth[i].timestamp = 0.1 * static_cast<double>(i);
  b.retimed = !increasing;
  b.raw = drifted_twin(b.truth, odometry_noise(level), seed);
  b.relations = bench_relations(b.truth);
  b.name = log;
  return b;
}

Bench sim_bench(const std::string& scenario, const std::string& level, std::uint64_t seed) {
  SimulatorConfig c;
  c.seed = seed;
  if (scenario == "corridors") {
    c.building.width = 120, c.building.height = 24;
    c.building.min_room_width = 10, c.building.max_room_width = 12;
    c.building.corridor_clutter = 0, c.building.clutter_per_room = 0;
  } else if (scenario == "hall") {
    c.building.width = 50, c.building.height = 40, c.building.corridor_width = 10, c.building.room_depth = 5;
  } else if (scenario == "long-range") {
    c.building.width = 80, c.building.height = 60;
    c.laser.max_range = 60;
  } else {
    throw InputError("unknown scenario '" + scenario + "' (corridors, hall, long-range)");
  }
  Bench b;
  b.truth = simulate(c).scans;
  for (Scan& s : b.truth) s.T_world_odom = s.T_world_laser;
  if (const char* v = std::getenv("SIM_REFERENCE_JITTER")) {
    // A drifted twin's truth is another mapper's poses, not the scans' true ones. "M,DEG": a reference made of the
    // true poses jittered by N(0, M) per axis and N(0, DEG) in heading, scan by scan; the odometry is drifted from
    // it, as a twin's is from its corrected log, while the scans stay where they were taken. slam is judged by
    // the truth as always and also by the reference ("slam_against_reference"), as a twin is.
    double metres = 0, degrees = 0;
    if (std::sscanf(v, "%lf,%lf", &metres, &degrees) != 2 || !(metres >= 0) || !(degrees >= 0))
      throw InputError(std::string("SIM_REFERENCE_JITTER '") + v + "': expected METRES,DEGREES, both >= 0");
    Rng rng(seed, 99);
    b.reference = b.truth;
    for (Scan& s : b.reference) {
      const Pose2 jitter{metres * rng.normal(), metres * rng.normal(), degrees * kDegree * rng.normal()};
      s.T_world_laser = s.T_world_laser * jitter;
      s.T_world_odom = s.T_world_laser;
    }
  }
  b.raw = drifted_twin(b.reference.empty() ? b.truth : b.reference, odometry_noise(level), seed);
  b.relations = bench_relations(b.truth);
  b.name = "sim:" + scenario;
  return b;
}

Bench raw_bench(const std::string& log, const std::string& twin_log, const std::string& relations) {
  Bench b;
  io::ScanSource source = io::load_scan_source(log);
  b.raw = std::move(source.scans);
  b.name = log;
  if (!relations.empty()) b.mount = source.T_base_laser.value_or(Pose2{});
  if (twin_log == "-") {  // no corrected twin (mit-csail): the relations alone judge the result, not the closures
    if (relations.empty()) throw InputError(log + ": without a twin the relations file is needed");
    b.relations = io::read_relations(relations);
    return b;
  }
  const Scans twin = io::load_scan_source(twin_log).scans;
  const auto index = associate_scans(b.raw, twin);
  for (std::size_t i = 0; i < b.raw.size(); ++i) {
    if (!index[i]) continue;
    Scan s;
    s.timestamp = b.raw[i].timestamp;
    s.T_world_laser = s.T_world_odom = twin[*index[i]].T_world_laser;
    b.truth.push_back(s);
  }
  if (b.truth.empty()) throw InputError(twin_log + ": no scan of " + log + " found in it");
  b.relations = relations.empty() ? bench_relations(b.truth) : io::read_relations(relations);
  if (!relations.empty()) b.reference = b.truth;
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (!((mode == "twin" && (argc == 5 || argc == 6)) || (mode == "sim" && (argc == 5 || argc == 6)) ||
        (mode == "raw" && argc >= 4 && argc <= 6))) {
    std::fprintf(stderr,
                 "usage: slam_bench twin CORRECTED_LOG LEVEL SEED [INJECT]\n"
                 "       slam_bench sim SCENARIO LEVEL SEED [INJECT]\n"
                 "       slam_bench raw RAW_LOG TWIN_LOG [RELATIONS] [INJECT]\n");
    return 2;
  }
  try {
    Bench b;
    double inject = 0.0;
    bool forced = false;
    // INJECT's number, and whether it ends in "f" (forced).
    const auto inject_of = [&forced](std::string text) {
      if (!text.empty() && text.back() == 'f') forced = true, text.pop_back();
      return std::atof(text.c_str());
    };
    nlohmann::json out;
    if (mode == "twin" || mode == "sim") {
      const std::uint64_t seed = std::strtoull(argv[4], nullptr, 10);
      b = mode == "twin" ? twin_bench(argv[2], argv[3], seed) : sim_bench(argv[2], argv[3], seed);
      if (argc == 6) inject = inject_of(argv[5]);
      out = {{"kind", mode}, {"level", argv[3]}, {"seed", std::atoi(argv[4])}};
    } else {
      // RELATIONS is a file name; a lone number after TWIN_LOG is INJECT.
      std::string relations = argc >= 5 ? argv[4] : "";
      if (argc == 5 && relations.find_first_not_of("0123456789.f") == std::string::npos)
        inject = inject_of(argv[4]), relations = "";
      if (argc == 6) inject = inject_of(argv[5]);
      b = raw_bench(argv[2], argv[3], relations);
      out = {{"kind", "raw"}, {"relations_file", relations}};
    }
    if (!(inject >= 0.0 && inject <= 10.0)) throw InputError("INJECT must be in [0, 10]");
    out["log"] = b.name;
    out["retimed"] = b.retimed;
    out["inject"] = inject;
    out["forced"] = forced;

    // The truth of a scan of the front end's output (same timestamps as the raw scans) and of a submap.
    std::size_t injected = 0;
    std::vector<std::optional<Pose2>> true_frames;
    SlamConfig config;
    // Exploration only: settings overridden from the environment (the bench itself runs the defaults).
    if (const char* v = std::getenv("FE_MAX_RANGE")) config.front_end.max_range = std::atof(v);
    if (const char* v = std::getenv("FE_LINEAR")) config.front_end.matcher.linear_window = std::atof(v);
    if (const char* v = std::getenv("FE_ANGULAR")) config.front_end.matcher.angular_window = std::atof(v);
    if (const char* v = std::getenv("FE_MIN_SCORE")) config.front_end.min_score = std::atof(v);
    if (const char* v = std::getenv("FE_DEGENERATE")) config.front_end.degenerate_ratio = std::atof(v);
    if (const char* v = std::getenv("FE_HALF_RATIO")) config.front_end.half_constrained_ratio = std::atof(v);
    if (const char* v = std::getenv("FE_HALF_SLACK")) config.front_end.half_constrained_slack = std::atof(v);
    if (const char* v = std::getenv("FE_SCALE_MEMORY")) config.front_end.scale_memory = std::atof(v);
    if (const char* v = std::getenv("FE_SCALE_RATIO")) config.front_end.scale_ratio = std::atof(v);
    if (const char* v = std::getenv("FE_SIGMA")) config.front_end.matcher.sigma = std::atof(v);
    if (const char* v = std::getenv("FE_FINE")) config.front_end.fine_sigma = std::atof(v);
    if (const char* v = std::getenv("FE_RES")) config.front_end.point_resolution = config.front_end.matcher.resolution = std::atof(v);
    if (const char* v = std::getenv("FE_KEY")) config.front_end.key_translation = std::atof(v);
    if (const char* v = std::getenv("FE_SECOND")) config.front_end.second_prediction = std::atof(v);
    if (const char* v = std::getenv("FE_MARGIN")) config.front_end.second_margin = std::atof(v);
    if (const char* v = std::getenv("FE_WIDE")) config.front_end.wide_score = std::atof(v);
    if (const char* v = std::getenv("LOOPS_VERIFY_DMM")) config.loops.verify_dmm = std::atoi(v) != 0;
    if (const char* v = std::getenv("LOOPS_GATE_CANDIDATES")) config.loops.gate_candidates = std::atoi(v) != 0;
    if (const char* v = std::getenv("LOOPS_CONSISTENCY")) config.loops.consistency.enabled = std::atoi(v) != 0;
    if (const char* v = std::getenv("LOOPS_CONSISTENCY_RATE")) config.loops.consistency.rate = std::atof(v);
    if (const char* v = std::getenv("LOOPS_CONSISTENCY_OFFSET")) config.loops.consistency.offset = std::atof(v);
    if (const char* v = std::getenv("LOOPS_CONSISTENCY_MAX_CHAIN")) config.loops.consistency.max_chain = std::atof(v);
    if (const char* v = std::getenv("LOOPS_CONSISTENCY_LONG_CHAIN")) config.loops.consistency.long_chain = std::atof(v);
    if (const char* v = std::getenv("LOOPS_CONSISTENCY_LONG_FACTOR"))
      config.loops.consistency.long_factor = std::atof(v);
    if (const char* v = std::getenv("NEIGHBOUR_ROUNDS")) config.neighbours.rounds = std::atoi(v);
    if (forced) {  // every closure kept, with a quadratic loss: the injected ones bend the map
      config.back_end.max_translation_residual = config.back_end.max_rotation_residual = 1e6;
      config.back_end.graph.robust_scale = 1e6;
    }
    const auto t0 = std::chrono::steady_clock::now();
    SlamResult r = run_slam(b.raw, config, {}, [&](const Submaps& maps, std::vector<LoopClosure>& accepted) {
      if (inject <= 0) return;
      Rng rng(12345, 7);
      const auto want = static_cast<std::size_t>(std::lround(inject * static_cast<double>(accepted.size())));
      std::size_t tries = 0;
      while (injected < want && tries++ < 100 * want + 1000) {
        const std::size_t q = rng.index(maps.size()), m = rng.index(maps.size());
        if (m >= q || maps[q].travel - maps[m].travel < 20.0) continue;
        // Non-matching: the front end's frames (drift within a few metres here) more than 10 m apart, so the
        // true ones are too on every bench input.
        if ((maps[q].T_world_map.translation() - maps[m].T_world_map.translation()).norm() < 10.0) continue;
        accepted.push_back({q, m, Pose2{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.3, 0.3)}, 1.0, 1.0, 1.0});
        ++injected;
      }
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const Scans front_end_estimate = with_poses(r.scans, r.front_end_poses);
    Submaps stored = r.submaps;
    for (std::size_t k = 0; k < stored.size(); ++k) stored[k].T_world_map = r.stored_frames[k];
    true_frames = reference_frames(stored, front_end_estimate, b.truth, index_by_time(front_end_estimate, b.truth));

    // Offered closures against the truth: wrong when more than 0.5 m or 5 degrees off; counted among those the
    // back end used and those it set aside (injected ones apart: they are wrong by construction).
    std::size_t judged = 0, wrong = 0, used_wrong = 0, aside_right = 0, injected_used = 0;
    // With SLAM_BENCH_CLOSURES set: per judged closure [travel gap m, disagreement with the front end's relative
    // pose m and rad, confidence, wrong] (for choosing gates; not in the bench's table).
    const bool detail = std::getenv("SLAM_BENCH_CLOSURES") != nullptr;
    nlohmann::json details = nlohmann::json::array();
    nlohmann::json wrong_list = nlohmann::json::array();
    const std::size_t real = r.offered.size() - injected;  // the hook appends the injected ones
    for (std::size_t k = 0; k < r.offered.size(); ++k) {
      const LoopClosure& l = r.offered[k];
      const bool used = r.back_end.used[k];
      if (k >= real) {
        injected_used += used;
        continue;
      }
      if (!true_frames[l.query] || !true_frames[l.match]) continue;
      const Pose2 T = true_frames[l.match]->inverse() * *true_frames[l.query];
      const bool bad = (T.translation() - l.T_match_query.translation()).norm() > 0.5 ||
                       std::abs(wrap_angle(T.theta - l.T_match_query.theta)) > 5.0 * kDegree;
      ++judged;
      wrong += bad;
      if (detail) {
        const Pose2 prior = r.stored_frames[l.match].inverse() * r.stored_frames[l.query];
        details.push_back({std::abs(r.submaps[l.query].travel - r.submaps[l.match].travel),
                           (prior.translation() - l.T_match_query.translation()).norm(),
                           std::abs(wrap_angle(prior.theta - l.T_match_query.theta)), l.confidence, bad ? 1 : 0,
                           (T.translation() - l.T_match_query.translation()).norm(),
                           std::abs(wrap_angle(T.theta - l.T_match_query.theta)),
                           ((r.submaps[l.match].T_world_map.inverse() * r.submaps[l.query].T_world_map).translation() -
                            T.translation()).norm(),
                           used ? 1 : 0});
      }
      if (bad)
        wrong_list.push_back(
            {{"query", l.query},
             {"match", l.match},
             {"used", used},
             {"confidence", l.confidence},
             {"error_m", (T.translation() - l.T_match_query.translation()).norm()},
             {"error_deg", std::abs(wrap_angle(T.theta - l.T_match_query.theta)) * kDegreesPerRadian},
             {"front_end_error_m",
              ((r.stored_frames[l.match].inverse() * r.stored_frames[l.query]).translation() -
               T.translation())
                  .norm()},
             {"solved_error_m",
              ((r.submaps[l.match].T_world_map.inverse() * r.submaps[l.query].T_world_map).translation() -
               T.translation())
                  .norm()}});
      used_wrong += bad && used;
      aside_right += !bad && !used;
    }
    // Where the front end loses track: steps whose increment differs from the truth's by > 0.1 m or 0.05 rad.
    nlohmann::json jumps = nlohmann::json::array();
    std::size_t jump_count = 0;
    {
      const auto index = index_by_time(front_end_estimate, b.truth);
      const std::vector<double> travel = travel_distances(front_end_estimate);
      for (std::size_t i = 1; i < front_end_estimate.size(); ++i) {
        if (!index[i] || !index[i - 1]) continue;
        const Pose2 est = r.front_end_poses[i - 1].inverse() * r.front_end_poses[i];
        const Pose2 tru = b.truth[*index[i - 1]].T_world_laser.inverse() * b.truth[*index[i]].T_world_laser;
        const double dt = (est.translation() - tru.translation()).norm(), da = std::abs(wrap_angle(est.theta - tru.theta));
        if (dt <= 0.1 && da <= 0.05) continue;
        if (++jump_count <= 10)
          jumps.push_back(
              {{"scan", i}, {"travel_m", travel[i]}, {"error_m", dt}, {"error_deg", da * kDegreesPerRadian}});
      }
    }
    out["front_end_jumps"] = {{"count", jump_count}, {"first", jumps}};
    out["front_end_degenerate"] = r.front_end.degenerate;
    out["front_end_half_constrained"] = r.front_end.half_constrained;
    out["front_end_scaled"] = r.front_end.scaled;
    out["front_end_odometry_scale"] = r.front_end.odometry_scale;
    out["front_end_heading_jumps"] = r.front_end.heading_jumps;
    out["front_end_weak_matches"] = r.front_end.weak_matches;
    out["front_end_weakest_score"] = r.front_end.weakest_score;
    out["front_end_wide"] = {r.front_end.wide_searches, r.front_end.wide_kept};
    out["front_end_turn_slope"] = r.front_end.turn_slope();
    out["front_end_turning_steps"] = r.front_end.turning_steps;
    Scans odometry = b.raw;
    for (Scan& s : odometry) s.T_world_laser = s.T_world_odom;
    out["scans"] = r.scans.size();
    out["submaps"] = r.submaps.size();
    out["slam"] = io::relations_error_json(relations_error(r.scans, b.relations, b.mount));
    out["odometry"] = io::relations_error_json(relations_error(odometry, b.relations, b.mount));
    if (!b.reference.empty()) {
      // How good a twin's truth is: the reference's own poses judged by the truth, and slam's result judged by
      // relations built from the reference, as a drifted twin's run is (docs/NOTES.md, "How good a twin's truth
      // is"); a raw log's reference is its corrected twin.
      const bool twin = mode == "raw";
      out[twin ? "twin_reference" : "reference"] =
          io::relations_error_json(relations_error(b.reference, b.relations, b.mount));
      out[twin ? "slam_against_twin" : "slam_against_reference"] =
          io::relations_error_json(relations_error(r.scans, bench_relations(b.reference)));
    }
    {  // slam's error on relations within one visit (scans at most 10 s apart) and between visits (the rest)
      Relations within, between;
      for (const Relation& rel : b.relations) (std::abs(rel.t2 - rel.t1) <= 10.0 ? within : between).push_back(rel);
      out["slam_within_visit"] = io::relations_error_json(relations_error(r.scans, within, b.mount));
      out["slam_between_visits"] = io::relations_error_json(relations_error(r.scans, between, b.mount));
      out["front_end_within_visit"] = io::relations_error_json(relations_error(front_end_estimate, within, b.mount));
      // With SLAM_BENCH_BETWEEN=FILE: one line per relation between visits (t1, t2, slam's error m and rad, the
      // front end's error m, the true x, y of both scans), to see where a map is off (not in the bench's table).
      if (const char* path = std::getenv("SLAM_BENCH_BETWEEN")) {
        std::FILE* f = std::fopen(path, "w");
        if (f == nullptr) throw InputError(std::string(path) + ": cannot be written (SLAM_BENCH_BETWEEN)");
        std::map<double, Pose2> truth_at;
        for (const Scan& s : b.truth) truth_at[s.timestamp] = s.T_world_laser;
        for (const Relation& rel : between) {
          const RelationsError e = relations_error(r.scans, Relations{rel}, b.mount);
          const RelationsError fe = relations_error(front_end_estimate, Relations{rel}, b.mount);
          auto a = truth_at.lower_bound(rel.t1 - 1e-6), c = truth_at.lower_bound(rel.t2 - 1e-6);
          std::fprintf(f, "%.3f %.3f %.4f %.4f %.4f %.3f %.3f %.3f %.3f\n", rel.t1, rel.t2, e.translation_mean,
                       e.rotation_mean, fe.translation_mean, a == truth_at.end() ? 0 : a->second.x,
                       a == truth_at.end() ? 0 : a->second.y, c == truth_at.end() ? 0 : c->second.x,
                       c == truth_at.end() ? 0 : c->second.y);
        }
        std::fclose(f);
      }
    }
    out["front_end"] = io::relations_error_json(relations_error(front_end_estimate, b.relations, b.mount));
    out["closures"] = {{"hypotheses", r.closures.size()}, {"accepted", real}, {"injected", injected},
                       {"judged", judged}, {"wrong", wrong}, {"used", r.back_end.used_count},
                       {"used_wrong", used_wrong}, {"set_aside_right", aside_right}, {"injected_used", injected_used}};
    out["wrong_closures"] = wrong_list;
    if (detail) out["closure_detail"] = details;
    out["graph"] = {{"rounds", r.back_end.rounds},
                    {"chain_bends", r.back_end.chain_bends},
                    {"max_chain_bend_m", r.back_end.max_chain_translation},
                    {"max_chain_bend_deg", r.back_end.max_chain_rotation * kDegreesPerRadian}};
    const bool with_places = std::getenv("SLAM_BENCH_PLACES") != nullptr;
    const auto check_json = [with_places](const MapCheck& m) {
      nlohmann::json j{{"scans", m.scans}, {"beams", m.beams}, {"revisiting", m.revisiting_beams},
                       {"crossing", m.crossing_beams}, {"share", m.crossing_share}, {"judged", m.judged},
                       {"passed", m.passed}, {"worst", {m.worst_place.x(), m.worst_place.y()}},
                       {"worst_crossings", m.worst_place_crossings}, {"worst_share", m.worst_place_share}};
      if (with_places) {
        nlohmann::json p = nlohmann::json::array();
        for (const MapCheck::Place& q : m.places)
          if (q.revisiting >= 100) p.push_back({q.centre.x(), q.centre.y(), q.revisiting, q.crossing});
        j["places"] = p;
      }
      return j;
    };
    out["map_check"] = check_json(r.map_check);
    out["front_end_map_check"] = check_json(r.front_end_map_check);
    out["second_opinion"] = {{"judged", r.second_opinion.judged},
                             {"passed", r.second_opinion.passed},
                             {"max_turn_deg", r.second_opinion.max_turn * kDegreesPerRadian},
                             {"max_shift_m", r.second_opinion.max_shift},
                             {"windows", r.second_opinion.windows},
                             {"pinned", r.second_opinion.pinned},
                             {"seconds", r.second_opinion_s}};
    out["check_seconds"] = r.check_s;
    out["verdict"] = r.back_end.verdict;
    out["reason"] = r.back_end.reason;
    out["seconds"] = seconds;
    std::cout << out.dump() << "\n";
  } catch (const std::exception& e) {
    std::fprintf(stderr, "slam_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
