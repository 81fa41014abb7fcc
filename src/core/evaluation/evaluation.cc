#include "core/evaluation/evaluation.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "core/parts/descriptor_layout.h"
#include "core/error.h"

namespace partslam {

void validate(const EvalConfig& config) {
  validate(config.tasks);
  validate(config.ranking);
  if (config.num_threads < 1 || config.num_threads > 1024) throw InputError("eval: threads must be in [1, 1024]");
  if (!config.pose_tolerance.valid()) throw InputError("eval: pose_tolerance must be finite and >= 0");
}

DescribedMaps describe_maps(const Submaps& maps, const Points2& dictionary_points, const CpdConfig& cpd,
                            const CodecConfig& codec, int num_threads, const Progress& progress,
                            const WorkSplit& split) {
  if (dictionary_points.empty()) throw InputError("eval: the dictionary map is empty");
  DescribedMaps d;
  const PreparedDictionary dictionary = prepare_dictionary(dictionary_points, cpd);
  d.codec = dictionary_codec_config(dictionary_points, codec);
  std::vector<const Points2*> points;
  std::vector<std::uint64_t> keys;
  for (const Submap& m : maps) points.push_back(&m.points), keys.push_back(static_cast<std::uint64_t>(m.id));
  std::vector<CpdResult> results = discover_parts_split(points, keys, dictionary, cpd, num_threads, progress, split);
  for (CpdResult& r : results) d.parts.push_back(std::move(r.parts)), d.cpd_ms.push_back(r.ms);
  if (!maps.empty())
    d.cpd_ms_per_map = std::accumulate(d.cpd_ms.begin(), d.cpd_ms.end(), 0.0) / static_cast<double>(maps.size());
  return d;
}

std::vector<MapView> map_views(const Submaps& maps, const DescribedMaps& described) {
  std::vector<MapView> views(maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i) {
    views[i].points = &maps[i].points;
    views[i].origins = &maps[i].origins;
    if (i < described.parts.size()) views[i].parts = &described.parts[i];
  }
  return views;
}

std::vector<TaskOutcome> run_tasks(const Ranker& ranker, const MethodSpec& method, const Submaps& maps,
                                   const DescribedMaps& described, std::span<const Task> tasks,
                                   const EvalConfig& config, const Progress& progress, VerifiedPairs* reuse) {
  const std::vector<MapView> views = map_views(maps, described);
  const PoseTolerance fine{0.1, std::numbers::pi / 180};
  std::vector<TaskOutcome> outcomes(tasks.size());
  parallel_for(
      tasks.size(), config.num_threads,
      [&](std::size_t t) {
        const Task& task = tasks[t];
        const std::size_t relevant = static_cast<std::size_t>(
            std::find(task.database.begin(), task.database.end(), task.relevant) - task.database.begin());
        const Ranking r = ranker.rank(views.at(task.query), task.database, {1, 0, reuse, task.query});
        TaskOutcome& out = outcomes[t];
        out.rank = tied_rank(r, relevant);
        out.db_size = task.database.size();
        out.match_ms = r.match_ms;
        out.prep_ms = r.prep_ms + (method.traits.needs_parts ? described.cpd_ms.at(task.query) : 0.0);
        out.true_overlap = true_overlap(maps[task.query], maps[task.relevant]);
        if (!r.direct.empty() && r.direct[relevant]) {
          // Is T_map_query of the relevant pair within tolerance of the truth T_map_world * T_world_query?
          const Pose2 truth = maps[task.relevant].T_world_map.inverse() * maps[task.query].T_world_map;
          out.pose = config.pose_tolerance.accepts(truth, r.direct[relevant]->T_map_query);
          out.pose_fine = fine.accepts(truth, r.direct[relevant]->T_map_query);
        }
        for (std::size_t j = 0; j < r.probability.size(); ++j) {
          if (!r.probability[j]) continue;
          const double p = *r.probability[j];
          const int bins = TaskOutcome::kCalibrationBins;
          const auto b = static_cast<std::size_t>(std::clamp(static_cast<int>(p * bins), 0, bins - 1));
          out.bin_probability[b] += p, out.bin_same[b] += j == relevant && out.pose == 1, out.bin_pairs[b] += 1;
        }
      },
      method.label, progress);
  return outcomes;
}

MethodResult summarize(const MethodSpec& method, std::span<const TaskOutcome> outcomes, double bits_per_map) {
  MethodResult result;
  result.method = method;
  result.bits_per_map = bits_per_map;
  std::vector<double> ranks;
  std::vector<std::size_t> sizes;
  double match_ms = 0, prep_ms = 0, pairs = 0, posed_ok = 0, posed_ok30 = 0, posed_fine30 = 0;
  constexpr int kBins = TaskOutcome::kCalibrationBins;
  std::array<double, kBins> bin_p{}, bin_y{}, bin_n{};
  double calibrated_pairs = 0;
  for (const TaskOutcome& o : outcomes) {
    if (o.pose >= 0) ++result.poses_checked, posed_ok += o.pose;
    if (o.pose >= 0 && o.true_overlap >= 0.3)
      ++result.poses_checked_overlap30, posed_ok30 += o.pose, posed_fine30 += o.pose_fine;
    for (std::size_t b = 0; b < kBins; ++b) {
      bin_p[b] += o.bin_probability[b], bin_y[b] += o.bin_same[b], bin_n[b] += o.bin_pairs[b];
      calibrated_pairs += o.bin_pairs[b];
    }
    ranks.push_back(o.rank);
    sizes.push_back(o.db_size);
    result.normalized_ranks.push_back(o.rank / static_cast<double>(o.db_size));
    match_ms += o.match_ms;
    prep_ms += o.prep_ms;
    pairs += static_cast<double>(o.db_size);
  }
  result.summary = summarize_ranks(ranks, sizes);
  if (result.poses_checked > 0) result.pose_within_tolerance = posed_ok / static_cast<double>(result.poses_checked);
  if (result.poses_checked_overlap30 > 0) {
    result.pose_within_tolerance_overlap30 = posed_ok30 / static_cast<double>(result.poses_checked_overlap30);
    result.pose_fine_overlap30 = posed_fine30 / static_cast<double>(result.poses_checked_overlap30);
  }
  if (calibrated_pairs > 0) {
    double ece = 0;
    for (std::size_t b = 0; b < kBins; ++b) {
      if (bin_n[b] == 0) continue;
      ece += std::abs(bin_p[b] - bin_y[b]) / calibrated_pairs;
      result.reliability.push_back({bin_p[b] / bin_n[b], bin_y[b] / bin_n[b], bin_n[b]});
    }
    result.calibration_error = ece;
  }
  if (!outcomes.empty()) {
    const double n = static_cast<double>(outcomes.size());
    result.ms_per_pair = match_ms / pairs;
    result.ms_query_prep = prep_ms / n;
    result.ms_per_query = (prep_ms + match_ms) / n;
  }
  return result;
}

namespace {

// A map's CPD as it travels over a WorkSplit (discover_parts_split): its time and how many parts it has; the
// parts themselves (plain records) travel in a gather of their own, in the same order.
struct CpdRecord {
  double ms = 0;
  std::size_t parts = 0;
};

// The outcomes of every task, each process running its slice.
std::vector<TaskOutcome> run_split(const Ranker& ranker, const MethodSpec& method, const Submaps& maps,
                                   const DescribedMaps& described, std::span<const Task> tasks,
                                   const EvalConfig& config, const Progress& progress, const WorkSplit& split,
                                   VerifiedPairs& reuse) {
  if (split.size() == 1) return run_tasks(ranker, method, maps, described, tasks, config, progress, &reuse);
  const auto [begin, end] = split.slice(tasks.size());
  const std::vector<TaskOutcome> local =
      run_tasks(ranker, method, maps, described, tasks.subspan(begin, end - begin), config, progress, &reuse);
  std::vector<TaskOutcome> out = all_gather<TaskOutcome>(split, local);
  if (out.size() != tasks.size()) throw InputError("eval: the processes ran different tasks");
  return out;
}

}  // namespace

std::vector<CpdResult> discover_parts_split(const std::vector<const Points2*>& maps,
                                            const std::vector<std::uint64_t>& map_keys,
                                            const PreparedDictionary& dictionary, const CpdConfig& cpd,
                                            int num_threads, const Progress& progress, const WorkSplit& split) {
  if (split.size() == 1) return discover_parts_many(maps, map_keys, dictionary, cpd, num_threads, progress);
  if (map_keys.size() != maps.size()) throw InputError("cpd: one key per map is needed");
  const auto [begin, end] = split.slice(maps.size());
  const auto b = static_cast<std::ptrdiff_t>(begin), e = static_cast<std::ptrdiff_t>(end);
  const std::vector<CpdResult> local =
      discover_parts_many({maps.begin() + b, maps.begin() + e}, {map_keys.begin() + b, map_keys.begin() + e},
                          dictionary, cpd, num_threads, progress);
  std::vector<CpdRecord> records;
  std::vector<Part> parts;
  for (const CpdResult& r : local) {
    records.push_back({r.ms, r.parts.size()});
    parts.insert(parts.end(), r.parts.begin(), r.parts.end());
  }
  const std::vector<CpdRecord> all = all_gather<CpdRecord>(split, records);
  const std::vector<Part> all_parts = all_gather<Part>(split, parts);
  std::vector<CpdResult> out;
  std::size_t at = 0;
  for (const CpdRecord& record : all) {
    if (record.parts > all_parts.size() - at) throw InputError("cpd: the processes sent too few parts");
    CpdResult r;
    r.ms = record.ms;
    const auto b = all_parts.begin() + static_cast<std::ptrdiff_t>(at);
    r.parts.assign(b, b + static_cast<std::ptrdiff_t>(record.parts));
    at += record.parts;
    out.push_back(std::move(r));
  }
  if (out.size() != maps.size()) throw InputError("cpd: the processes described different maps");
  return out;
}

RankSummary oracle_ranks(const Submaps& maps, std::span<const Task> tasks, int num_threads) {
  std::vector<double> ranks(tasks.size());
  std::vector<std::size_t> sizes(tasks.size());
  parallel_for(tasks.size(), num_threads, [&](std::size_t t) {
    const Task& task = tasks[t];
    Ranking r;
    std::size_t relevant = 0;
    for (std::size_t j = 0; j < task.database.size(); ++j) {
      r.scores.push_back(true_overlap(maps[task.query], maps[task.database[j]]));
      if (task.database[j] == task.relevant) relevant = j;
    }
    ranks[t] = tied_rank(r, relevant);
    sizes[t] = task.database.size();
  });
  return summarize_ranks(ranks, sizes);
}

EvalReport evaluate(const Submaps& maps, const Points2& dictionary_points, const std::vector<MethodSpec>& methods,
                    const EvalConfig& config, const EvalProgress& progress, const WorkSplit& split,
                    VerifiedPairs* reuse) {
  validate(config);
  if (methods.empty()) throw InputError("eval: no method given");

  EvalReport report;
  report.maps = maps.size();
  for (const Submap& m : maps) report.mean_points += static_cast<double>(m.points.size());
  if (!maps.empty()) report.mean_points /= static_cast<double>(maps.size());
  const std::vector<RelevantPair> pairs = relevant_pairs(maps, config.tasks);
  report.relevant_pairs = pairs.size();
  report.low_overlap_share = low_overlap_share(maps, pairs, 0.3, config.num_threads);
  const std::vector<Task> tasks = make_tasks(maps, config.tasks);
  if (tasks.empty()) {
    throw InputError("eval: no relevant pair among " + std::to_string(maps.size()) + " maps (R = " +
                     std::to_string(config.tasks.radius) + " m, G = " + std::to_string(config.tasks.min_travel_gap) +
                     " m): the log has no loop closure");
  }
  report.tasks = tasks.size();
  const auto [smallest, largest] =
      std::minmax_element(tasks.begin(), tasks.end(),
                          [](const Task& a, const Task& b) { return a.database.size() < b.database.size(); });
  report.smallest_database = smallest->database.size();
  report.largest_database = largest->database.size();
  report.oracle = oracle_ranks(maps, tasks, config.num_threads);

  bool need_parts = false, need_hmm_query = false;
  for (const MethodSpec& m : methods) {
    need_parts |= m.traits.needs_parts;
    need_hmm_query |= m.traits.query_parts == QueryParts::kList;
  }
  DescribedMaps described;
  RankingConfig ranking = config.ranking;
  if (need_parts) {
    CpdConfig cpd = config.cpd;
    cpd.max_parts = std::max(max_parts(methods), need_hmm_query ? config.ranking.parts.hmm_query_parts : 0);
    described = describe_maps(maps, dictionary_points, cpd, config.codec, config.num_threads, progress, split);
    report.cpd_ms_per_map = described.cpd_ms_per_map;
    ranking.parts.codec = described.codec;
  }
  const std::vector<MapView> views = map_views(maps, described);
  VerifiedPairs own;  // dmm and every rerank share one set of verified pairs (core/ranking/verified_pairs.h)
  VerifiedPairs& verified = reuse != nullptr ? *reuse : own;
  for (const MethodSpec& method : methods) {
    const std::unique_ptr<Ranker> ranker = make_ranker(method, ranking);
    ranker->prepare(views, config.num_threads, progress);
    const std::vector<TaskOutcome> outcomes =
        run_split(*ranker, method, maps, described, tasks, config, progress, split, verified);
    report.methods.push_back(summarize(method, outcomes, ranker->bits_per_map()));
  }
  return report;
}

}  // namespace partslam
