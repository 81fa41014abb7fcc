// The one way to rank (docs/DESIGN.md, "Schemes"): a query map against a prepared set of stored maps, for any
// method spec. Every method is a Ranker:
//   offline  prepare(maps)             whatever the method stores per map (grids, packed descriptors, ...)
//   online   rank(query, candidates)   one score per candidate (higher = more likely the same place), the
//                                      relative pose where the method computes one, and timings.
// `partslam eval`, `partslam match`, the benchmarks and the bindings all rank through make_ranker().
//
// Adding a method: write its ranker in one file (a class deriving from Ranker and a MethodEntry function that
// parses its spec and makes it), then add that function to the table in ranking.cc. Nothing else dispatches
// on the method.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "core/matching/dmm.h"
#include "core/matching/dmm_ransac.h"
#include "core/matching/method_spec.h"
#include "core/parallel.h"
#include "core/parts/part.h"
#include "core/parts/part_codec.h"

namespace partslam {

/// What the library holds of one map: its points in the canonical frame and, for methods that need them
/// (MethodSpec::needs_parts), its parts from CPD, best first. A stored map's parts are either the full list
/// (evaluation: they then go through RankingConfig::codec) or what a database holds (already decoded).
struct MapView {
  const Points2* points = nullptr;
  const std::vector<Part>* parts = nullptr;
};

struct RankingConfig {
  DmmConfig dmm;             ///< dMM and the dMM stage of rerank
  DmmRansacConfig ransac;    ///< dMM-RANSAC
  /// Storage of part descriptors: when set, stored maps' (and iMM queries') top-K parts are encoded and decoded
  /// through it, so ranking sees what a database would hold; unset: the parts given are already the stored ones.
  std::optional<CodecConfig> codec;
  int hmm_query_parts = 100;   ///< parts of an hMM query (its best ones)
  double origin_gate = kDefaultOriginGate;  ///< descriptor matcher's origin gate [m]; 0 = the paper
  double bits_per_point = 14;  ///< storage of a raw map point (7 + 7 bits at 0.1 m in a 12.8 m crop)
};

/// Throws InputError naming the offending field.
void validate(const RankingConfig& config);

struct RankOptions {
  int num_threads = 1;  ///< threads over candidates (results do not depend on it)
  /// dMM only: > 0 lets a serial dMM drop candidates that provably cannot enter the top k (their score is then
  /// 0 and `exact` false); 0 scores every candidate exactly (what evaluation needs).
  int top_k = 0;
};

struct Ranking {
  std::vector<double> scores;                    ///< one per candidate, higher = more likely the same place
  std::vector<std::optional<DmmResult>> direct;  ///< per candidate where a direct match ran (pose, inliers)
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

/// One registered method: how its spec is parsed and its ranker made.
struct MethodEntry {
  std::string_view name;    ///< first field of the spec
  std::string_view syntax;  ///< for help and errors, e.g. "imm:K[:maxmax|summax|smw]"
  /// Fills spec (all but name) from the fields after the name; throws InputError naming `text`.
  void (*parse)(const std::string& text, const std::vector<std::string>& args, MethodSpec& spec);
  std::unique_ptr<Ranker> (*make)(const MethodSpec& spec, const RankingConfig& config);
};

/// Every method, in the order `--help` lists them.
const std::vector<MethodEntry>& method_registry();
/// The entry named `name`, or nullptr.
const MethodEntry* find_method(std::string_view name);
/// "dmm, dmm-ransac, ...": every method's syntax, for help texts.
std::string method_syntax_list();

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

}  // namespace partslam
