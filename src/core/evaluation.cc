#include "core/evaluation.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <numeric>

#include "core/descriptor_database.h"
#include "core/descriptor_layout.h"
#include "core/error.h"

namespace partslam {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

// Runs body(i) for i in [0, n) on num_threads threads, reporting progress from whichever thread finishes an item.
template <typename Body>
void parallel_for(std::size_t n, int num_threads, const std::string& stage, const EvalProgress& progress,
                  Body&& body) {
  std::atomic<std::size_t> done{0};
  const long count = static_cast<long>(n);
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, num_threads))
  for (long i = 0; i < count; ++i) {
    body(static_cast<std::size_t>(i));
    const std::size_t d = ++done;
    if (progress) {
#pragma omp critical(partslam_eval_progress)
      progress(stage, d, n);
    }
  }
}

// What one task contributes to a method's figures.
struct TaskOutcome {
  double rank = 0;
  int pose = -1;        // -1: no pose for the relevant map; 0: wrong; 1: within tolerance
  double match_ms = 0;  // online matching of the whole task database
  double prep_ms = 0;   // the query's own preparation
};

// Scores of the task database from a whole-database descriptor scoring (all maps), timed.
struct DescriptorScores {
  std::vector<double> scores;
  double ms = 0;
  std::size_t database_size = 0;
};

}  // namespace

EvalReport evaluate(const Submaps& maps, const Points2& dictionary_points, const std::vector<MethodSpec>& methods,
                    const EvalConfig& config, const EvalProgress& progress) {
  validate(config.tasks);
  validate(config.dmm);
  validate(config.ransac);
  if (!(config.origin_gate >= 0) || !std::isfinite(config.origin_gate))
    throw InputError("eval: origin_gate must be a finite number >= 0 [m]");
  if (methods.empty()) throw InputError("eval: no method given");
  if (config.hmm_query_parts < 1) throw InputError("eval: hmm_query_parts must be >= 1");
  if (config.num_threads < 1 || config.num_threads > 1024) throw InputError("eval: threads must be in [1, 1024]");

  EvalReport report;
  report.maps = maps.size();
  for (const Submap& m : maps) report.mean_points += static_cast<double>(m.points.size());
  if (!maps.empty()) report.mean_points /= static_cast<double>(maps.size());
  report.relevant_pairs = relevant_pairs(maps, config.tasks).size();
  const std::vector<Task> tasks = make_tasks(maps, config.tasks);
  if (tasks.empty()) {
    throw InputError("eval: no relevant pair among " + std::to_string(maps.size()) + " maps (R = " +
                     std::to_string(config.tasks.radius) + " m, G = " + std::to_string(config.tasks.min_travel_gap) +
                     " m): the log has no loop closure");
  }
  report.tasks = tasks.size();

  bool need_parts = false, need_hmm_query = false, need_dmm = false, need_ransac = false;
  for (const MethodSpec& m : methods) {
    need_parts |= m.uses_descriptors();
    need_hmm_query |= m.scheme == SchemeKind::kHmm || m.scheme == SchemeKind::kRerank;
    need_dmm |= m.scheme == SchemeKind::kDmm || m.scheme == SchemeKind::kDmmExhaustive ||
                m.scheme == SchemeKind::kRerank;
    need_ransac |= m.scheme == SchemeKind::kDmmRansac;
  }

  // ---- offline: parts of every map (CPD against the dictionary), stored through the codec ----
  std::vector<std::vector<Part>> parts(maps.size());
  std::vector<double> cpd_ms(maps.size(), 0.0);
  CodecConfig codec = config.codec;
  if (need_parts) {
    if (dictionary_points.empty()) throw InputError("eval: the dictionary map is empty");
    CpdConfig cpd = config.cpd;
    cpd.max_parts = std::max(max_parts(methods), need_hmm_query ? config.hmm_query_parts : 0);
    const PreparedDictionary dictionary = prepare_dictionary(dictionary_points, cpd);
    codec = dictionary_codec_config(dictionary_points, codec);
    parallel_for(maps.size(), config.num_threads, "parts (CPD)", progress, [&](std::size_t i) {
      const auto t0 = Clock::now();
      parts[i] = discover_parts(maps[i].points, dictionary, cpd, static_cast<std::uint64_t>(i)).parts;
      cpd_ms[i] = ms_since(t0);
    });
    report.cpd_ms_per_map = std::accumulate(cpd_ms.begin(), cpd_ms.end(), 0.0) / static_cast<double>(maps.size());
  }
  auto stored_descriptor = [&](std::size_t map, int k) {
    return decode(encode(select_top_parts(parts[map], k), codec), codec);
  };

  // ---- offline: grids of every stored map ----
  std::vector<PreparedMap> grids(need_dmm ? maps.size() : 0);
  std::vector<PreparedRansacMap> ransac_maps(need_ransac ? maps.size() : 0);
  if (need_dmm) {
    parallel_for(maps.size(), config.num_threads, "grids", progress,
                 [&](std::size_t i) { grids[i] = prepare_map(maps[i].points, config.dmm); });
  }
  if (need_ransac) {
    parallel_for(maps.size(), config.num_threads, "ransac grids", progress,
                 [&](std::size_t i) { ransac_maps[i] = prepare_ransac_map(maps[i].points, config.ransac); });
  }

  // dMM scores of a task's maps (all of them, or a subset), timed.
  // Is T_map_query of the relevant pair within tolerance of the truth T_map_world * T_world_query?
  auto pose_ok = [&](const Task& task, const Pose2& T_map_query) {
    const Pose2 truth = maps[task.relevant].T_world_map.inverse() * maps[task.query].T_world_map;
    return (truth.translation() - T_map_query.translation()).norm() <= config.pose_tolerance_m &&
           std::abs(wrap_angle(truth.theta - T_map_query.theta)) <= config.pose_tolerance_rad;
  };
  auto dmm_scores = [&](const Task& task, const std::vector<std::size_t>& which, bool exhaustive, double& prep_ms,
                        double& match_ms, int& pose) {
    auto t0 = Clock::now();
    const PreparedQuery query = prepare_query(maps[task.query].points, config.dmm);
    prep_ms = ms_since(t0);
    std::vector<double> s(which.size());
    t0 = Clock::now();
    for (std::size_t j = 0; j < which.size(); ++j) {
      const PreparedMap& map = grids[task.database[which[j]]];
      const DmmResult r = exhaustive ? match_exhaustive(query, map, config.dmm) : match_dmm(query, map, config.dmm);
      s[j] = r.inliers;
      if (task.database[which[j]] == task.relevant) pose = pose_ok(task, r.T_map_query);
    }
    match_ms = ms_since(t0);
    return s;
  };

  for (const MethodSpec& method : methods) {
    MethodResult result;
    result.method = method;
    std::vector<TaskOutcome> outcomes(tasks.size());

    // Descriptor methods score the whole stored database per query, as a deployed system would.
    DescriptorDatabase database;
    std::vector<MapDescriptor> queries;
    if (method.uses_descriptors()) {
      std::vector<MapDescriptor> stored(maps.size());
      for (std::size_t i = 0; i < maps.size(); ++i) stored[i] = stored_descriptor(i, method.parts);
      DescriptorDatabaseConfig dbc;
      dbc.parts_per_map = method.parts;
      database = DescriptorDatabase(stored, dbc);
      queries.resize(maps.size());
      for (std::size_t i = 0; i < maps.size(); ++i) {
        queries[i] = method.scheme == SchemeKind::kImm ? stored[i]
                                                       : select_top_parts(parts[i], config.hmm_query_parts);
      }
      result.bits_per_map = packed_bits(method.parts, codec);
    }
    if (method.uses_points()) result.bits_per_map += config.bits_per_point * report.mean_points;

    auto descriptor_scores = [&](const Task& task) {
      DescriptorScores d;
      const auto t0 = Clock::now();
      ScoreOptions options;
      options.origin_gate = config.origin_gate;
      const std::vector<float> all = database.score_all(queries[task.query], method.matcher, options);
      d.ms = ms_since(t0);
      d.database_size = all.size();
      for (std::size_t m : task.database) d.scores.push_back(all[m]);
      return d;
    };

    parallel_for(tasks.size(), config.num_threads, method.label(), progress, [&](std::size_t t) {
      const Task& task = tasks[t];
      const std::size_t n = task.database.size();
      const std::size_t relevant =
          static_cast<std::size_t>(std::find(task.database.begin(), task.database.end(), task.relevant) -
                                   task.database.begin());
      TaskOutcome& out = outcomes[t];
      std::vector<double> scores;
      std::vector<std::size_t> all(n);
      std::iota(all.begin(), all.end(), 0);
      switch (method.scheme) {
        case SchemeKind::kDmm:
        case SchemeKind::kDmmExhaustive:
          scores = dmm_scores(task, all, method.scheme == SchemeKind::kDmmExhaustive, out.prep_ms, out.match_ms,
                              out.pose);
          break;
        case SchemeKind::kDmmRansac: {
          const auto t0 = Clock::now();
          for (std::size_t m : task.database) {
            const DmmResult r = match_dmm_ransac(maps[task.query].points, ransac_maps[m], config.ransac);
            scores.push_back(r.inliers);
            if (m == task.relevant) out.pose = pose_ok(task, r.T_map_query);
          }
          out.match_ms = ms_since(t0);
          break;
        }
        case SchemeKind::kImm:
        case SchemeKind::kHmm: {
          DescriptorScores d = descriptor_scores(task);
          scores = std::move(d.scores);
          out.match_ms = d.ms * static_cast<double>(n) / static_cast<double>(d.database_size);
          out.prep_ms = cpd_ms[task.query];
          break;
        }
        case SchemeKind::kRerank: {
          DescriptorScores d = descriptor_scores(task);
          scores = std::move(d.scores);
          std::vector<std::size_t> order = all;
          std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
          order.resize(std::min<std::size_t>(order.size(), static_cast<std::size_t>(method.rerank)));
          double dmm_prep = 0, dmm_match = 0;
          const std::vector<double> direct = dmm_scores(task, order, false, dmm_prep, dmm_match, out.pose);
          // The top R move above every other map, ordered by dMM; hMM breaks dMM ties.
          const double lift = 1e9;
          for (std::size_t j = 0; j < order.size(); ++j) scores[order[j]] = lift + direct[j] * 1e3 + scores[order[j]];
          out.match_ms = d.ms * static_cast<double>(n) / static_cast<double>(d.database_size) + dmm_match;
          out.prep_ms = cpd_ms[task.query] + dmm_prep;
          break;
        }
      }
      out.rank = tied_rank(scores, relevant);
    });

    std::vector<double> ranks;
    std::vector<std::size_t> sizes;
    double match_ms = 0, prep_ms = 0, pairs = 0, posed_ok = 0;
    for (std::size_t t = 0; t < tasks.size(); ++t) {
      if (outcomes[t].pose >= 0) ++result.poses_checked, posed_ok += outcomes[t].pose;
      ranks.push_back(outcomes[t].rank);
      sizes.push_back(tasks[t].database.size());
      result.normalized_ranks.push_back(outcomes[t].rank / static_cast<double>(tasks[t].database.size()));
      match_ms += outcomes[t].match_ms;
      prep_ms += outcomes[t].prep_ms;
      pairs += static_cast<double>(tasks[t].database.size());
    }
    result.summary = summarize_ranks(ranks, sizes);
    if (result.poses_checked > 0) result.pose_within_tolerance = posed_ok / static_cast<double>(result.poses_checked);
    result.ms_per_pair = match_ms / pairs;
    result.ms_query_prep = prep_ms / static_cast<double>(tasks.size());
    result.ms_per_query = (prep_ms + match_ms) / static_cast<double>(tasks.size());
    report.methods.push_back(std::move(result));
  }
  return report;
}

}  // namespace partslam
