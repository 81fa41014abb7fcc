// The paper's evaluation (docs/DESIGN.md, "Metrics"; paper §"Experiments"): every method ranks the database of
// every task; the rank of the relevant map gives ANR and recall within the top 1 / 1 % / 5 % / 10 % of N; time
// per map pair, time per query and bits per stored map are measured on the same tasks. In stages:
//   1. describe_maps   offline: CPD parts of every map against the dictionary (when a method needs parts)
//   2. run_tasks       one method (a Ranker from core/ranking/ranking.h, prepared on every map) over a range of tasks
//   3. summarize       the method's figures from the task outcomes
// evaluate() runs the three for every method on the same tasks.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/parts/cpd.h"
#include "core/ranking/method_spec.h"
#include "core/evaluation/metrics.h"
#include "core/parts/part_codec.h"
#include "core/ranking/ranking.h"
#include "core/evaluation/tasks.h"
#include "core/work_split.h"

namespace partslam {

struct EvalConfig {
  TaskConfig tasks;
  RankingConfig ranking;         ///< method parameters (dMM, RANSAC, hMM query parts, origin gate)
  CpdConfig cpd;                 ///< parts (max_parts is raised to what the methods need)
  CodecConfig codec;             ///< storage of stored descriptors (dictionary_extent is filled in)
  int num_threads = 1;           ///< OpenMP threads over maps and tasks; results do not depend on it
  PoseTolerance pose_tolerance;      ///< relative pose check (0.5 m, 0.2 rad)
};

/// Throws InputError naming the offending field.
void validate(const EvalConfig& config);

/// Stage 1 output: what the offline description of every map produced.
struct DescribedMaps {
  std::vector<std::vector<Part>> parts;  ///< per map, best AS first; empty when no method needs parts
  std::vector<double> cpd_ms;            ///< per map [ms]
  std::optional<CodecConfig> codec;      ///< storage of descriptors against this dictionary
  double cpd_ms_per_map = 0;
};

/// CPD of every map against the dictionary, seeded by Submap::id (as `partslam describe` does), keeping up to
/// max_parts parts; over a split, each process describes its slice (discover_parts_split). Throws InputError
/// when the dictionary is empty.
DescribedMaps describe_maps(const Submaps& maps, const Points2& dictionary_points, const CpdConfig& cpd,
                            const CodecConfig& codec, int num_threads, const Progress& progress = {},
                            const WorkSplit& split = local_work());

/// discover_parts_many over a WorkSplit: each process finds the parts of its slice of the maps, and every process
/// gets every map's parts and CPD time, in order (the statistics stay with the process that ran them).
std::vector<CpdResult> discover_parts_split(const std::vector<const Points2*>& maps,
                                            const std::vector<std::uint64_t>& map_keys,
                                            const PreparedDictionary& dictionary, const CpdConfig& cpd,
                                            int num_threads, const Progress& progress, const WorkSplit& split);

/// The maps as rankers see them (points, and parts when described).
std::vector<MapView> map_views(const Submaps& maps, const DescribedMaps& described);

/// What one task contributes to a method's figures.
struct TaskOutcome {
  double rank = 0;          ///< tied rank of the relevant map (1 = best)
  std::size_t db_size = 0;  ///< N of the task
  int pose = -1;            ///< -1: no pose for the relevant map; 0: wrong; 1: within tolerance
  bool pose_fine = false;   ///< the relevant map's pose within 0.1 m / 1 degree
  double true_overlap = 0;  ///< the relevant pair's true overlap (tasks.h)
  /// Calibrated methods: the candidates it gave a probability, binned by it (kCalibrationBins equal-width bins):
  /// the sum of their probabilities, how many were the same place at that pose (the relevant map posed within
  /// tolerance), how many there were. A plain record (it travels between processes).
  static constexpr int kCalibrationBins = 10;
  std::array<double, kCalibrationBins> bin_probability{}, bin_same{}, bin_pairs{};
  double match_ms = 0;      ///< online matching of the whole task database [ms]
  double prep_ms = 0;       ///< the query's own preparation, its CPD included [ms]
};

/// Stage 2: a prepared ranker (prepare()d on map_views(maps, described)) over some tasks. `reuse` (may be null):
/// verified dMM answers shared with earlier calls on the same maps and ranking config (RankOptions::reuse); the
/// outcomes are the same with or without it.
std::vector<TaskOutcome> run_tasks(const Ranker& ranker, const MethodSpec& method, const Submaps& maps,
                                   const DescribedMaps& described, std::span<const Task> tasks,
                                   const EvalConfig& config, const Progress& progress = {},
                                   VerifiedPairs* reuse = nullptr);

struct MethodResult {
  MethodSpec method;
  RankSummary summary;
  std::vector<double> normalized_ranks;  ///< per task, rank / N in (0, 1]
  double ms_per_pair = 0;     ///< online matching time per database map [ms]
  double ms_query_prep = 0;   ///< the query's own preparation (its CPD, its rotated point sets) [ms]
  double ms_per_query = 0;    ///< ms_query_prep + matching the whole task database [ms]
  double bits_per_map = 0;    ///< storage per stored map [bits]
  /// Methods that return a pose (dMM, rerank when the relevant map is reranked): how many relevant pairs were
  /// posed, and the share whose T_map_query is within pose_tolerance of the truth (from the maps' poses).
  std::size_t poses_checked = 0;
  double pose_within_tolerance = 0;
  /// The same over the relevant pairs with >= 30 % true overlap, and the share of those within 0.1 m / 1 deg.
  std::size_t poses_checked_overlap30 = 0;
  double pose_within_tolerance_overlap30 = 0;
  double pose_fine_overlap30 = 0;
  /// Calibrated methods: expected calibration error of their probabilities over every pair they scored (10
  /// equal-width bins), and each bin's (mean probability, observed share of same place, pairs).
  std::optional<double> calibration_error;
  std::vector<std::array<double, 3>> reliability;
};

/// The ceiling of the tasks: their databases ranked by the true overlap at the true pose.
RankSummary oracle_ranks(const Submaps& maps, std::span<const Task> tasks, int num_threads = 1);

/// Stage 3: the figures of one method from its task outcomes.
MethodResult summarize(const MethodSpec& method, std::span<const TaskOutcome> outcomes, double bits_per_map);

struct EvalReport {
  std::size_t maps = 0;            ///< submaps of the input
  double mean_points = 0;          ///< mean points per submap
  std::size_t relevant_pairs = 0;  ///< relevant pairs found (tasks are sampled from them)
  double low_overlap_share = 0;    ///< share of relevant pairs whose true overlap is below 30 % (the ceiling)
  std::size_t tasks = 0;
  /// Maps in the smallest and the largest task database: N, or fewer where fewer maps lie farther than 2R
  /// from a query (ANR and the recalls divide by each task's own size).
  std::size_t smallest_database = 0, largest_database = 0;
  /// The ceiling: ranking every task's database by the true overlap at the true pose (tasks.h, true_overlap).
  RankSummary oracle;
  double cpd_ms_per_map = 0;       ///< offline CPD per map [ms] (0 when no method uses parts)
  std::vector<MethodResult> methods;
};

/// Progress callback: stage name, items done, items in the stage.
using EvalProgress = Progress;

/// Runs every method on the same tasks. Throws InputError when the maps yield no relevant pair or the
/// dictionary is empty while a method needs parts.
/// With a split over several processes, each describes its slice of the maps and runs its slice of the tasks; the
/// results are gathered, so the report equals one process's (timings apart). Every process prepares every map.
/// `reuse`: verified dMM answers shared with other evaluations of the same maps and config.ranking (e.g. the
/// same maps at another radius); null: shared among this call's methods only. The report is the same either way.
EvalReport evaluate(const Submaps& maps, const Points2& dictionary_points, const std::vector<MethodSpec>& methods,
                    const EvalConfig& config, const EvalProgress& progress = {},
                    const WorkSplit& split = local_work(), VerifiedPairs* reuse = nullptr);

}  // namespace partslam
