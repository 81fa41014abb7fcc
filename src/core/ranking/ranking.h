// The one way to rank (docs/DESIGN.md, "Schemes"): a query map against a prepared set of stored maps, for any
// method spec. Every method is a Ranker:
//   offline  prepare(maps)             whatever the method stores per map (grids, packed descriptors, ...)
//   online   rank(query, candidates)   one score per candidate (higher = more likely the same place), the
//                                      relative pose where the method computes one, and timings.
// `partslam eval`, `partslam match`, loop closures, the benchmarks and the bindings all rank through
// make_ranker(); the methods are the registry's (core/ranking/registry.h).
#pragma once

#include <cstddef>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/matching/dmm.h"
#include "core/matching/dmm_ransac.h"
#include "core/matching/verification.h"
#include "core/parallel.h"
#include "core/parts/descriptor_database.h"
#include "core/parts/part.h"
#include "core/ranking/method_spec.h"
#include "core/ranking/registry.h"
#include "core/ranking/verified_pairs.h"

namespace partslam {

/// What the library holds of one map: its points in the canonical frame and, for methods that need them
/// (MethodTraits::needs_parts), its parts from CPD, best first. A stored map's parts are either the full list
/// (evaluation: they then go through PartsConfig::codec) or what a database holds (already decoded).
struct MapView {
  const Points2* points = nullptr;
  const std::vector<Part>* parts = nullptr;
  /// Where the laser was while the map was recorded (Submap::origins): the verified dMM casts its free space
  /// from them; none (nullptr or empty) for a map of bare points.
  const Points2* origins = nullptr;
};

/// dMM's search for ranking: canonical frames with eight rotation families (multiples of 45 degrees, as the
/// localizer's): a 2 m submap's own Manhattan alignment can be off by half a quarter turn from another
/// submap's of the same place, and four families never find that pose (docs/NOTES.md, "Eight rotation families
/// for the ranking's dMM" under "Verifying a match"). Each family is searched +- 10 degrees, not DmmConfig's 3: a
/// small map's alignment is often further off the building's axes than that (docs/NOTES.md, "A wider rotation
/// window for the ranking's dMM").
inline DmmConfig ranking_dmm_config() {
  DmmConfig config;
  config.canonical_turns = 8;
  config.angular_window = 10.0 * std::numbers::pi / 180;
  return config;
}

struct RankingConfig {
  DmmConfig dmm = ranking_dmm_config();  ///< dMM and the dMM stage of rerank
  VerifyConfig verify;         ///< dMM's verification of its poses (not dmm:eq1)
  bool verify_dmm = true;      ///< false: `dmm` and rerank's dMM stage score by Eq. 1 (as dmm:eq1)
  DmmRansacConfig ransac;      ///< dMM-RANSAC
  PartsConfig parts;           ///< iMM, hMM and their rerank
  double bits_per_point = 14;  ///< storage of a raw map point (7 + 7 bits at 0.1 m in a 12.8 m crop)
};

/// Throws InputError naming the offending field.
void validate(const RankingConfig& config);

struct RankOptions {
  int num_threads = 1;  ///< threads over candidates (results do not depend on it)
  /// dMM only: > 0 lets a serial dMM drop candidates that provably cannot enter the top k (their score is then
  /// 0 and `exact` false); 0 scores every candidate exactly (what evaluation needs).
  int top_k = 0;
  /// Verified dMM (`dmm` and rerank's dMM stage) only: answers kept from earlier calls of the same evaluation,
  /// looked up and added under (query_index, candidate); match_ms is then the sum of each pair's own time, the
  /// time kept with a reused answer included (core/ranking/verified_pairs.h). nullptr: every pair computed.
  VerifiedPairs* reuse = nullptr;
  std::size_t query_index = 0;  ///< the query's index among the stored maps, the key for `reuse`
};

/// What a candidate ranks by, in this order, higher first: its tier, its score, then the first stage's score (0
/// where there is none).
struct RankKey {
  int tier = 0;
  double score = 0.0;
  double stage_score = 0.0;
};
/// The ranking order, the one definition of it (Ranking's, and a query answer's rows, core/ranking/query.h): 1 when
/// a ranks above b, -1 when below, 0 when tied (then the candidates' order decides).
int compare_rank(const RankKey& a, const RankKey& b);

/// A ranking's order: compare_rank of its candidates' keys (tiers, scores, shortlist_scores), then the candidates'
/// order.
struct Ranking {
  std::vector<double> scores;                    ///< one per candidate, higher = more likely the same place
  /// rerank: 1 for the candidates it reordered by dMM (their score is then dMM's), 0 for the others (their
  /// score is the first stage's); empty: every candidate in tier 0.
  std::vector<int> tiers;
  std::vector<std::optional<DmmResult>> direct;  ///< per candidate where a direct match ran (pose, inliers)
  /// Per candidate where the match was verified: the probability that it is the same place at the direct
  /// match's pose (core/matching/verification.h); empty for methods that do not verify.
  std::vector<std::optional<double>> probability;
  /// The same where verified: the probability of the most probable other pose of that map (VerifiedDmm).
  std::vector<std::optional<double>> runner_up;
  std::vector<double> shortlist_scores;          ///< rerank: the first stage's scores; empty otherwise
  double prep_ms = 0;   ///< the query's own preparation (not its CPD) [ms]
  double match_ms = 0;  ///< matching the candidates [ms]
};

class Ranker {
 public:
  virtual ~Ranker() = default;
  /// Offline: prepares the stored maps; candidates of rank() index this list. Deterministic for any threads.
  virtual void prepare(std::span<const MapView> maps, int num_threads, const Progress& progress = {}) = 0;
  /// Storage per stored map [bits] (after prepare).
  virtual double bits_per_map() const = 0;
  /// Online: scores the candidates (indices into the prepared maps) for the query. Const and thread-safe.
  virtual Ranking rank(const MapView& query, std::span<const std::size_t> candidates,
                       const RankOptions& options = {}) const = 0;
};

/// For rankers whose stored form is built from a map's points: make(points) of every map, in parallel (each map
/// writes its own slot, so the result does not depend on num_threads). Throws InputError naming `method` and
/// the map when a map has no points or make refuses it.
template <typename Stored, typename Make>
std::vector<Stored> prepare_from_points(std::span<const MapView> maps, int num_threads, const Progress& progress,
                                        const std::string& method, const std::string& stage, Make make) {
  for (std::size_t i = 0; i < maps.size(); ++i)
    if (maps[i].points == nullptr) throw InputError(method + ": stored map " + std::to_string(i) + " has no points");
  std::vector<Stored> out(maps.size());
  parallel_for(
      maps.size(), num_threads,
      [&](std::size_t i) {
        try {
          out[i] = make(*maps[i].points);
        } catch (const InputError& e) {  // which map: the caller's list position
          throw InputError(method + ": stored map " + std::to_string(i) + ": " + e.what());
        }
      },
      stage, progress);
  return out;
}

/// The ranker of a parsed method. Throws InputError for an invalid config.
std::unique_ptr<Ranker> make_ranker(const MethodSpec& method, const RankingConfig& config);

/// Candidate positions sorted by score, best first; ties keep their order.
std::vector<std::size_t> ranking_order(const std::vector<double>& scores);
/// Candidate positions in the ranking's order (compare_rank, best first; ties keep their order).
std::vector<std::size_t> ranking_order(const Ranking& ranking);
/// Whether candidate a ranks above candidate b.
bool ranks_above(const Ranking& ranking, std::size_t a, std::size_t b);
/// The rank of candidate j (1 = best): 1 + the candidates above it + half of those tied with it.
double tied_rank(const Ranking& ranking, std::size_t j);

}  // namespace partslam
