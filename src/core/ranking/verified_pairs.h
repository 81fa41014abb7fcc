// Verified dMM answers kept for reuse within one evaluation (core/evaluation/evaluation.h). `partslam eval`
// ranks the same query against the same stored map many times: a query that is the query of several tasks
// meets many of the same stored maps again, and every rerank method verifies a shortlist that `dmm` verified
// in full before it. verify_dmm is deterministic (the same query, map and configs give the same poses and
// probabilities, bit for bit), so the second time is the first's answer. Each answer keeps the time it took to
// compute, and a ranker that reuses one charges that time again: the figures eval reports per query stay what
// a user pays to rank that query (docs/NOTES.md, "Evaluation reuses verified pairs").
// Valid for one RankingConfig and one list of stored maps: `evaluate` makes one per call.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "core/matching/dmm.h"

namespace partslam {

struct VerifiedPair {
  DmmResult direct;        ///< as the dmm ranker reports it (its pose the verified one)
  double probability = 0;  ///< Verified::probability at that pose
  double runner_up = 0;    ///< VerifiedDmm::runner_up
  double ms = 0;           ///< what computing it took [ms]
};

/// Thread-safe: rankers look pairs up and add them from parallel tasks.
class VerifiedPairs {
 public:
  /// The answer for query `query` (an index into the evaluation's maps) against stored map `map`, if kept.
  std::optional<VerifiedPair> find(std::size_t query, std::size_t map) const;
  /// Keeps an answer; the first one kept for a pair stays (every answer for a pair is the same).
  void insert(std::size_t query, std::size_t map, const VerifiedPair& pair);
  std::size_t size() const;
  /// How many find() calls found an answer.
  std::size_t hits() const;

 private:
  static std::uint64_t key(std::size_t query, std::size_t map);
  mutable std::mutex mutex_;
  std::unordered_map<std::uint64_t, VerifiedPair> pairs_;
  mutable std::size_t hits_ = 0;
};

}  // namespace partslam
