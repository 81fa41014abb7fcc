// The succinct matcher's top k over a large database (grid_descriptor.h; measured in docs/NOTES.md, "The
// succinct matcher at fleet scale"). The score of stored map m for a query is
//   s(m) = max over the query's poses v of J(q_v, g_m)  -  hub_weight * mu_m        (J: Jaccard similarity)
// and a scan computes it for every stored map (4 turns x 17 x 17 translations: 1156 poses a map). The cascade
// computes it only for a short list, chosen in two cheaper stages:
//   1. turns: the score over the query's four turns unshifted (4 of the 1156 poses; single precision), in
//      bins of 1/128; the turns_keep share of the best go on (at least turns_min);
//   2. coarse: the score over the poses on whole cells within +-coarse_reach cells (100 of the 1156); the
//      coarse_keep share of the best go on (at least coarse_min);
//   3. full: the exact score over every pose, as the scan computes it, and the k best.
// A database no larger than a stage's keep skips that stage, so up to coarse_min maps the top k equals the
// scan's bit for bit. Above it the cascade can miss a map the scan ranks in its top k (and rank one above it
// that the scan would not): it is an approximation, measured against the scan in bench_dm (BM_Succinct*).
//
// Stored per map: the grid (16 bytes, in blocks of 8 maps for 8-wide popcounts) and mu's level (a byte): 17
// bytes. The kernels use AVX-512 (VPOPCNTDQ) when the CPU has it, chosen at run time; the portable path
// gives the same answers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/matching/grid_descriptor.h"

namespace partslam {

struct GridCascadeConfig {
  double turns_keep = 0.05;        ///< share of the stored maps the turns stage passes on
  std::size_t turns_min = 50'000;  ///< ... and at least this many
  double coarse_keep = 0.001;      ///< share of the stored maps the coarse stage passes on
  std::size_t coarse_min = 2'000;  ///< ... and at least this many
  int coarse_reach = 2;            ///< coarse poses: whole-cell translations within +-this many cells
  bool use_simd = true;            ///< AVX-512 kernels when the CPU has them (false: the portable path)
};

/// Throws InputError naming the offending field.
void validate(const GridCascadeConfig& config);

struct GridMatch {
  std::size_t index = 0;  ///< the stored map's index
  double score = 0;       ///< s(m), exactly what the scan computes
  bool operator==(const GridMatch&) const = default;
};

struct GridCascadeStats {
  std::size_t turns_kept = 0;   ///< maps the turns stage passed on (all when it was skipped)
  std::size_t coarse_kept = 0;  ///< maps the coarse stage passed on, scored over every pose
  double turns_ms = 0, coarse_ms = 0, full_ms = 0;
};

class GridCascade {
 public:
  struct Poses;  // the query's grids on a set of poses, as the kernels read them (grid_cascade.cc)

  /// grids[i] and mu[i] are stored map i's grid and hubness (mu empty: all 0); every mu must lie on the
  /// hub_bits lattice (grid_hubness's quantisation). Throws InputError on mismatched sizes or a bad
  /// configuration.
  GridCascade(std::span<const GridBits> grids, std::span<const double> mu, const GridConfig& grid,
              const GridCascadeConfig& config = {});

  /// The k best stored maps for a query (its make_query_grids under `grid`), best first (score descending,
  /// then index ascending), among the first `first_maps` stored maps (all by default; the stages keep their
  /// shares of those).
  std::vector<GridMatch> top_k(const std::vector<GridBits>& query, std::size_t k,
                               GridCascadeStats* stats = nullptr,
                               std::size_t first_maps = std::numeric_limits<std::size_t>::max()) const;

  /// Every stored map's score s(m) for a query (the scan without the selection), in index order.
  std::vector<double> scores(const std::vector<GridBits>& query) const;

  std::size_t size() const { return size_; }
  /// Bytes held for the stored maps (their grids and mu levels).
  std::size_t memory_bytes() const;
  /// Whether the AVX-512 kernels run (the CPU has them and the configuration allows them).
  bool simd() const { return simd_; }

 private:
  /// How many of n maps the coarse and the turns stage keep for a top k (a stage keeping them all is
  /// skipped).
  struct Keep {
    std::size_t coarse = 0, turns = 0;
  };
  Keep keep(std::size_t k, std::size_t n) const;

  /// Throws InputError unless the query has the 4 x side^2 grids of the cascade's configuration.
  void check_query(const std::vector<GridBits>& query) const;
  /// The listed maps' scores over a set of poses (grid_cascade.cc), in list order.
  std::vector<GridMatch> score(const std::vector<std::uint32_t>& maps, const Poses& poses) const;

  struct Block {  // 8 maps' grids, word 0 then word 1
    std::array<std::uint64_t, 8> w0{}, w1{};
  };
  GridConfig grid_;
  GridCascadeConfig config_;
  std::size_t size_ = 0;
  double levels_ = 1;  // mu = level / levels_
  bool simd_ = false;
  std::vector<Block> blocks_;
  std::vector<std::uint8_t> level_;     // mu's level (mu = level / levels_) of each map, a block's 8 together
  std::array<double, 256> mu_term_{};   // hub_weight * mu of each level
  std::array<float, 256> mu_term_f_{};  // ... in single precision (the turns stage)
};

/// The reference: every stored map's exact score, then the k best (score descending, then index ascending).
std::vector<GridMatch> scan_top_k(const std::vector<GridBits>& query, std::span<const GridBits> grids,
                                  std::span<const double> mu, double hub_weight, std::size_t k);

}  // namespace partslam
