// One query map against a database: the query entry point of `partslam match` and of any caller that ranks
// stored maps for one map. It ranks the candidates with any registered method (under mpirun each process
// prepares and ranks its slice of the candidates and the best rows are merged in the serial order), keeps the
// best rows, and says how sure the answer is against the best answer in another place (another dataset, or a
// frame more than OtherPlace::distance away: core/matching/distinctiveness.h): for a verified dMM (`dmm`,
// rerank over it) the probability that the best row is the same place and that one is not; for other methods
// with a direct match the best inlier share minus that one's.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "core/maps/submap.h"
#include "core/work_split.h"
#include "core/matching/distinctiveness.h"
#include "core/ranking/ranking.h"

namespace partslam {

/// A stored map as a candidate: what the ranker reads, and its place.
struct QueryCandidate {
  MapView view;
  int dataset = 0;    ///< maps of different datasets are different places (their world frames differ)
  Pose2 T_world_map;  ///< its frame in its dataset's world frame
};

/// One row of the answer. A plain record: it travels between processes as bytes.
struct QueryRow {
  std::size_t candidate = 0;            ///< index into the candidates
  int tier = 0;                         ///< Ranking::tiers (rerank: 1 for its reordered top R)
  double score = 0;                     ///< the method's score
  std::optional<double> stage_score;    ///< a succinct method's score (its own, or rerank's first stage)
  std::optional<DmmResult> pose;        ///< the direct match, where one ran
  std::optional<double> probability;    ///< the verified same-place probability, where the match was verified
  std::optional<double> runner_up;      ///< there: the probability of the map's most probable other pose
};

struct QueryAnswer {
  std::vector<QueryRow> rows;        ///< best first, at most QueryRankOptions::top
  std::optional<double> confidence;  ///< how sure the best row is; none when the method gives no pose
  bool calibrated = false;           ///< confidence is a probability (decision_probability), else a margin
  double prepare_ms = 0;             ///< preparing this process's candidates (offline work) [ms]
  double prep_ms = 0;                ///< the query's own preparation [ms]
  double match_ms = 0;               ///< ranking this process's candidates [ms]
  std::size_t ranked_here = 0;       ///< candidates this process ranked
};

struct QueryRankOptions {
  std::size_t top = 10;   ///< rows kept (>= 1)
  int num_threads = 1;    ///< threads (results do not depend on it)
  OtherPlace other_place;
};

/// A stored map chosen as a candidate: its dataset (index into the datasets given) and its index there.
struct ChosenMap {
  std::size_t dataset = 0, map = 0;
};

/// The stored maps a stored or new query map is ranked against, in the order given: every map of `datasets` but
/// the query itself (the same id) and, in the query's own dataset (`own`, none for a new local map), the maps
/// anchored within min_gap of travel of it (the same pass, not a revisit), which `too_recent` counts.
struct CandidateChoice {
  std::vector<ChosenMap> maps;
  std::size_t too_recent = 0;
};
CandidateChoice choose_candidates(const Submap& query, std::span<const Submaps* const> datasets,
                                  std::optional<std::size_t> own, double min_gap);

/// Ranks the candidates for the query (same answer for any threads and processes). Throws InputError when the
/// method cannot be split between processes (MethodTraits::shardable) and split has more than one, or when
/// there is no candidate.
QueryAnswer rank_query(const MethodSpec& method, const RankingConfig& config,
                       std::span<const QueryCandidate> candidates, const MapView& query,
                       const QueryRankOptions& options, const WorkSplit& split = WorkSplit{});

}  // namespace partslam
