// The paper's evaluation (DESIGN.md, "Metrics"; paper §"Experiments"): every method ranks the database of
// every task; the rank of the relevant map gives ANR, recall@1 and recall@1 %; time per map pair, time per
// query and bits per stored map are measured on the same tasks.
//   dMM / dMM-RANSAC / dMM-exhaustive: Eq. 1 between the query and each database map.
//   iMM:K   query and stored maps both as K parts, stored through the bit-packed codec (what a database holds).
//   hMM:K   query with up to hmm_query_parts parts at full precision (the local map is at hand), stored K parts.
//   rerank:R:K  hMM:K ranks; the top R are reordered by their dMM score.
// Offline work (CPD of every map, grids of stored maps) is timed separately from online work.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/cpd.h"
#include "core/dmm.h"
#include "core/dmm_ransac.h"
#include "core/method_spec.h"
#include "core/metrics.h"
#include "core/part_codec.h"
#include "core/tasks.h"

namespace partslam {

struct EvalConfig {
  TaskConfig tasks;
  DmmConfig dmm;                 ///< dMM and reranking
  DmmRansacConfig ransac;        ///< dMM-RANSAC
  CpdConfig cpd;                 ///< parts (max_parts is raised to what the methods need)
  CodecConfig codec;             ///< storage of stored descriptors (dictionary_extent is filled in)
  int hmm_query_parts = 100;     ///< parts of an hMM query
  double origin_gate = kDefaultOriginGate;     ///< descriptor matcher's origin gate [m] (descriptor_matcher.h); 0 = the paper
  double bits_per_point = 14;    ///< storage of a raw map point (7 + 7 bits at 0.1 m in a 12.8 m crop)
  int num_threads = 1;           ///< OpenMP threads over maps and tasks; results do not depend on it
  double pose_tolerance_m = 0.5;     ///< relative pose check: translation [m]
  double pose_tolerance_rad = 0.2;   ///< relative pose check: rotation [rad]
};

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
};

struct EvalReport {
  std::size_t maps = 0;            ///< submaps of the input
  double mean_points = 0;          ///< mean points per submap
  std::size_t relevant_pairs = 0;  ///< relevant pairs found (tasks are sampled from them)
  std::size_t tasks = 0;
  double cpd_ms_per_map = 0;       ///< offline CPD per map [ms] (0 when no method uses parts)
  std::vector<MethodResult> methods;
};

/// Progress callback: stage name, items done, items in the stage.
using EvalProgress = std::function<void(const std::string& stage, std::size_t done, std::size_t total)>;

/// Runs every method on the same tasks. Throws InputError when the maps yield no relevant pair or the
/// dictionary is empty while a method needs parts.
EvalReport evaluate(const Submaps& maps, const Points2& dictionary_points, const std::vector<MethodSpec>& methods,
                    const EvalConfig& config, const EvalProgress& progress = {});

}  // namespace partslam
