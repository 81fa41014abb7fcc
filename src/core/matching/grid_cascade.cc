#include "core/matching/grid_cascade.h"

// GCC 12 reports its own AVX-512 headers' placeholder operands (_mm512_undefined_*) as uninitialised when
// they are inlined; the kernels below read no uninitialised value (the portable path checks them in
// grid_cascade_test).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <string>

#include "core/error.h"
#include "core/timing.h"

namespace partslam {

namespace {

constexpr int kBins = 257;  // the turns stage's score bins: floor(128 s) + 128, clamped to [0, 256]

}  // namespace

// The query's grids on a set of poses, as the kernels read them.
struct GridCascade::Poses {
  std::vector<std::uint64_t> w0, w1;
  std::vector<int> count;
  void add(const GridBits& g) {
    w0.push_back(g.words[0]);
    w1.push_back(g.words[1]);
    count.push_back(g.count());
  }
};

namespace {
using Poses = GridCascade::Poses;

// Best Jaccard (as both / either) of each of 8 maps over the poses: the pose order and the strict comparison
// of grid_similarity, so the fraction is the one the scan finds.
void best8_portable(const std::uint64_t* w0, const std::uint64_t* w1, const Poses& p, int* both,
                    int* either) {
  for (int j = 0; j < 8; ++j) {
    const int nb = std::popcount(w0[j]) + std::popcount(w1[j]);
    int bb = 0, be = 1;
    for (std::size_t v = 0; v < p.count.size(); ++v) {
      const int c = std::popcount(w0[j] & p.w0[v]) + std::popcount(w1[j] & p.w1[v]), e = p.count[v] + nb - c;
      if (c * be > bb * e) bb = c, be = e;
    }
    both[j] = bb;
    either[j] = be;
  }
}

__attribute__((target("avx512f,avx512vpopcntdq"))) void best8_avx512(const std::uint64_t* w0,
                                                                     const std::uint64_t* w1, const Poses& p,
                                                                     int* both, int* either) {
  const __m512i g0 = _mm512_loadu_si512(w0), g1 = _mm512_loadu_si512(w1);
  const __m512i nb = _mm512_add_epi64(_mm512_popcnt_epi64(g0), _mm512_popcnt_epi64(g1));
  __m512i bb = _mm512_setzero_si512(), be = _mm512_set1_epi64(1);
  for (std::size_t v = 0; v < p.count.size(); ++v) {
    const __m512i c = _mm512_add_epi64(
        _mm512_popcnt_epi64(_mm512_and_si512(g0, _mm512_set1_epi64(static_cast<long long>(p.w0[v])))),
        _mm512_popcnt_epi64(_mm512_and_si512(g1, _mm512_set1_epi64(static_cast<long long>(p.w1[v])))));
    const __m512i e = _mm512_sub_epi64(_mm512_add_epi64(nb, _mm512_set1_epi64(p.count[v])), c);
    // c * be > bb * e on small non-negative values (32 x 32 -> 64-bit products)
    const __mmask8 m = _mm512_cmpgt_epi64_mask(_mm512_mul_epu32(c, be), _mm512_mul_epu32(bb, e));
    bb = _mm512_mask_mov_epi64(bb, m, c);
    be = _mm512_mask_mov_epi64(be, m, e);
  }
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(both), _mm512_cvtepi64_epi32(bb));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(either), _mm512_cvtepi64_epi32(be));
}

// The turns stage: each map's best Jaccard over a few poses in single precision, c / max(either, 1), minus
// its mu term, in bins floor(128 s) + 128 clamped to [0, 256]; 16 maps (two blocks) at a time. The AVX-512
// kernel performs the same IEEE operations in the same order, so both paths give the same bins.
void bins16_portable(const std::uint64_t* w0, const std::uint64_t* w1, const std::uint8_t* level,
                     const Poses& p, const float* mu_term, std::uint16_t* out) {
  for (int j = 0; j < 16; ++j) {
    // two blocks: maps 0..7 of the first, 8..15 of the second (words 16 apart)
    const std::uint64_t g0 = w0[j < 8 ? j : j + 8], g1 = w1[j < 8 ? j : j + 8];
    const int nb = std::popcount(g0) + std::popcount(g1);
    float best = 0.0F;
    for (std::size_t v = 0; v < p.count.size(); ++v) {
      const int c = std::popcount(g0 & p.w0[v]) + std::popcount(g1 & p.w1[v]);
      const int e = std::max(p.count[v] + nb - c, 1);
      best = std::max(best, static_cast<float>(c) / static_cast<float>(e));
    }
    const float bin = std::floor((best - mu_term[level[j]]) * 128.0F) + 128.0F;
    out[j] = static_cast<std::uint16_t>(std::clamp(bin, 0.0F, static_cast<float>(kBins - 1)));
  }
}

// Two 8-lane 64-bit counts as 16 32-bit lanes.
__attribute__((target("avx512f"), always_inline)) inline __m512i lanes16(__m512i low, __m512i high) {
  return _mm512_inserti64x4(_mm512_castsi256_si512(_mm512_cvtepi64_epi32(low)), _mm512_cvtepi64_epi32(high),
                            1);
}

__attribute__((target("avx512f,avx512vpopcntdq"))) void bins16_avx512(const std::uint64_t* w0,
                                                                      const std::uint64_t* w1,
                                                                      const std::uint8_t* level,
                                                                      const Poses& p, const float* mu_term,
                                                                      std::uint16_t* out) {
  const __m512i a0 = _mm512_loadu_si512(w0), a1 = _mm512_loadu_si512(w1);            // maps 0..7
  const __m512i b0 = _mm512_loadu_si512(w0 + 16), b1 = _mm512_loadu_si512(w1 + 16);  // maps 8..15
  const __m512i nb = lanes16(_mm512_add_epi64(_mm512_popcnt_epi64(a0), _mm512_popcnt_epi64(a1)),
                             _mm512_add_epi64(_mm512_popcnt_epi64(b0), _mm512_popcnt_epi64(b1)));
  __m512 best = _mm512_setzero_ps();
  for (std::size_t v = 0; v < p.count.size(); ++v) {
    const __m512i q0 = _mm512_set1_epi64(static_cast<long long>(p.w0[v]));
    const __m512i q1 = _mm512_set1_epi64(static_cast<long long>(p.w1[v]));
    const __m512i c = lanes16(_mm512_add_epi64(_mm512_popcnt_epi64(_mm512_and_si512(a0, q0)),
                                               _mm512_popcnt_epi64(_mm512_and_si512(a1, q1))),
                              _mm512_add_epi64(_mm512_popcnt_epi64(_mm512_and_si512(b0, q0)),
                                               _mm512_popcnt_epi64(_mm512_and_si512(b1, q1))));
    const __m512i e = _mm512_max_epi32(
        _mm512_sub_epi32(_mm512_add_epi32(nb, _mm512_set1_epi32(p.count[v])), c), _mm512_set1_epi32(1));
    best = _mm512_max_ps(best, _mm512_div_ps(_mm512_cvtepi32_ps(c), _mm512_cvtepi32_ps(e)));
  }
  const __m512 m = _mm512_i32gather_ps(
      _mm512_cvtepu8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(level))), mu_term, 4);
  __m512 bin = _mm512_roundscale_ps(_mm512_mul_ps(_mm512_sub_ps(best, m), _mm512_set1_ps(128.0F)),
                                    _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
  bin = _mm512_add_ps(bin, _mm512_set1_ps(128.0F));
  bin = _mm512_min_ps(_mm512_max_ps(bin, _mm512_setzero_ps()), _mm512_set1_ps(kBins - 1));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm512_cvtepi32_epi16(_mm512_cvttps_epi32(bin)));
}

bool cpu_has_avx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vpopcntdq");
}

// Better: higher score, then lower index.
bool better(const GridMatch& a, const GridMatch& b) {
  return a.score != b.score ? a.score > b.score : a.index < b.index;
}

// The n best of `matches` (all when fewer), best first when `sorted`.
void keep_best(std::vector<GridMatch>& matches, std::size_t n, bool sorted) {
  if (matches.size() > n) {
    std::nth_element(matches.begin(), matches.begin() + static_cast<std::ptrdiff_t>(n), matches.end(),
                     better);
    matches.resize(n);
  }
  if (sorted) std::sort(matches.begin(), matches.end(), better);
}

std::size_t keep_count(double share, std::size_t least, std::size_t n) {
  return std::max(least, static_cast<std::size_t>(std::ceil(share * static_cast<double>(n))));
}

}  // namespace

void validate(const GridCascadeConfig& c) {
  if (!(c.turns_keep > 0 && c.turns_keep <= 1))
    throw InputError("grid cascade: turns_keep must be in (0, 1]");
  if (!(c.coarse_keep > 0 && c.coarse_keep <= 1))
    throw InputError("grid cascade: coarse_keep must be in (0, 1]");
  if (c.turns_min < 1) throw InputError("grid cascade: turns_min must be >= 1");
  if (c.coarse_min < 1) throw InputError("grid cascade: coarse_min must be >= 1");
  if (c.coarse_reach < 0 || c.coarse_reach > 11)
    throw InputError("grid cascade: coarse_reach must be in [0, 11]");
}

GridCascade::GridCascade(std::span<const GridBits> grids, std::span<const double> mu, const GridConfig& grid,
                         const GridCascadeConfig& config)
    : grid_(grid), config_(config), size_(grids.size()) {
  validate(grid_);
  validate(config_);
  if (!mu.empty() && mu.size() != grids.size())
    throw InputError("grid cascade: " + std::to_string(mu.size()) + " hubness values for " +
                     std::to_string(grids.size()) + " grids");
  if (grid_.hub_bits > 8) throw InputError("grid cascade: hub_bits must be <= 8 (a byte a map)");
  levels_ = std::ldexp(1.0, grid_.hub_bits) - 1;
  simd_ = config_.use_simd && cpu_has_avx512();
  // The turns stage's kernels read two adjacent blocks as one run of words (word 0 of their maps at 0..7 and
  // 16..23, word 1 at 8..15 and 24..31).
  static_assert(sizeof(Block) == 16 * sizeof(std::uint64_t));
  blocks_.resize((size_ + 15) / 16 * 2);  // an even count: the turns stage reads two blocks at a time
  level_.resize(blocks_.size() * 8);
  for (std::size_t i = 0; i < size_; ++i) {
    blocks_[i / 8].w0[i % 8] = grids[i].words[0];
    blocks_[i / 8].w1[i % 8] = grids[i].words[1];
    const double m = mu.empty() ? 0.0 : mu[i];
    const double level = std::round(m * levels_);
    if (!(level >= 0 && level <= levels_) || level / levels_ != m)
      throw InputError("grid cascade: hubness of map " + std::to_string(i) +
                       " is not on the hub_bits lattice");
    level_[i] = static_cast<std::uint8_t>(level);
  }
  for (std::size_t l = 0; l < mu_term_.size(); ++l) {
    mu_term_[l] = grid_.hub_weight * (static_cast<double>(l) / levels_);
    mu_term_f_[l] = static_cast<float>(mu_term_[l]);
  }
}

GridCascade::Keep GridCascade::keep(std::size_t k, std::size_t n) const {
  Keep out;
  out.coarse = std::max(keep_count(config_.coarse_keep, config_.coarse_min, n), k);
  out.turns = std::max(keep_count(config_.turns_keep, config_.turns_min, n), out.coarse);
  return out;
}

std::size_t GridCascade::memory_bytes() const { return blocks_.size() * sizeof(Block) + level_.size(); }

// The scores of the listed maps over a set of poses, 8 at a time.
std::vector<GridMatch> GridCascade::score(const std::vector<std::uint32_t>& maps, const Poses& poses) const {
  std::vector<GridMatch> out(maps.size());
  std::array<std::uint64_t, 8> w0{}, w1{};
  std::array<int, 8> both{}, either{};
  for (std::size_t j = 0; j < maps.size(); j += 8) {
    const std::size_t m = std::min<std::size_t>(8, maps.size() - j);
    for (std::size_t i = 0; i < 8; ++i) {
      const std::uint32_t id = maps[j + std::min(i, m - 1)];
      w0[i] = blocks_[id / 8].w0[id % 8];
      w1[i] = blocks_[id / 8].w1[id % 8];
    }
    (simd_ ? best8_avx512 : best8_portable)(w0.data(), w1.data(), poses, both.data(), either.data());
    for (std::size_t i = 0; i < m; ++i) {
      const std::uint32_t id = maps[j + i];
      out[j + i] = {id, static_cast<double>(both[i]) / either[i] - mu_term_[level_[id]]};
    }
  }
  return out;
}

std::vector<double> GridCascade::scores(const std::vector<GridBits>& query) const {
  check_query(query);
  Poses all;
  for (const GridBits& g : query) all.add(g);
  std::vector<std::uint32_t> maps(size_);
  std::iota(maps.begin(), maps.end(), std::uint32_t{0});
  std::vector<double> out(size_);
  for (const GridMatch& m : score(maps, all)) out[m.index] = m.score;
  return out;
}

void GridCascade::check_query(const std::vector<GridBits>& query) const {
  const int side = 2 * grid_.max_shift * grid_.substeps + 1;
  if (query.size() != static_cast<std::size_t>(4 * side * side))
    throw InputError("grid cascade: " + std::to_string(query.size()) + " query grids, expected " +
                     std::to_string(4 * side * side) +
                     " (make_query_grids under the cascade's configuration)");
}

std::vector<GridMatch> GridCascade::top_k(const std::vector<GridBits>& query, std::size_t k,
                                          GridCascadeStats* stats, std::size_t first_maps) const {
  check_query(query);
  const int reach = grid_.max_shift * grid_.substeps, side = 2 * reach + 1;
  GridCascadeStats st;
  const std::size_t n = std::min(size_, first_maps);
  const auto [coarse_n, turns_n] = keep(k, n);
  auto pose = [&](int turn, int row, int column) {
    return query[static_cast<std::size_t>((turn * side + row) * side + column)];
  };

  // 1. turns: the score over the query's four turns unshifted, in bins; the best bins go on, ties by index.
  auto t0 = Clock::now();
  std::vector<std::uint32_t> list;
  if (n > turns_n) {
    Poses turns;
    for (int turn = 0; turn < 4; ++turn) turns.add(pose(turn, reach, reach));
    std::vector<std::uint16_t> bin(level_.size());
    const auto kernel = simd_ ? bins16_avx512 : bins16_portable;
    for (std::size_t b = 0; b < (n + 15) / 16 * 2; b += 2)
      kernel(blocks_[b].w0.data(), blocks_[b].w1.data(), &level_[8 * b], turns, mu_term_f_.data(),
             &bin[8 * b]);
    // Four interleaved histograms: runs of equal bins do not wait on one counter.
    std::array<std::array<std::uint32_t, kBins>, 4> part{};
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
      for (std::size_t h = 0; h < 4; ++h) ++part[h][bin[i + h]];
    for (; i < n; ++i) ++part[0][bin[i]];
    std::size_t bar = kBins - 1, above = 0;
    auto at = [&](std::size_t b) { return std::size_t{part[0][b]} + part[1][b] + part[2][b] + part[3][b]; };
    while (above + at(bar) < turns_n) above += at(bar--);
    std::size_t at_bar = turns_n - above;
    list.resize(turns_n + 1);  // one spare slot: each map is written, and kept by moving on
    std::size_t kept = 0;
    for (std::size_t j = 0; j < n; ++j) {  // branch-free: most maps are dropped, at random
      const bool tie = bin[j] == bar && at_bar > 0;
      list[kept] = static_cast<std::uint32_t>(j);
      kept += bin[j] > bar || tie;
      at_bar -= tie;
    }
    list.resize(kept);
  } else {
    list.resize(n);
    std::iota(list.begin(), list.end(), std::uint32_t{0});
  }
  st.turns_kept = list.size();
  st.turns_ms = ms_since(t0);

  // 2. coarse poses: whole cells within +-coarse_reach, every turn.
  t0 = Clock::now();
  if (list.size() > coarse_n) {
    Poses coarse;
    const int r = std::min(config_.coarse_reach, grid_.max_shift);
    for (int turn = 0; turn < 4; ++turn)
      for (int row = -r; row <= r; ++row)
        for (int column = -r; column <= r; ++column)
          coarse.add(pose(turn, reach + row * grid_.substeps, reach + column * grid_.substeps));
    std::vector<GridMatch> kept = score(list, coarse);
    keep_best(kept, coarse_n, false);
    list.clear();
    for (const GridMatch& m : kept) list.push_back(static_cast<std::uint32_t>(m.index));
    std::sort(list.begin(), list.end());
  }
  st.coarse_kept = list.size();
  st.coarse_ms = ms_since(t0);

  // 3. every pose, exactly as the scan scores a map.
  t0 = Clock::now();
  Poses all;
  for (const GridBits& g : query) all.add(g);
  std::vector<GridMatch> top = score(list, all);
  keep_best(top, k, true);
  st.full_ms = ms_since(t0);
  if (stats != nullptr) *stats = st;
  return top;
}

std::vector<GridMatch> scan_top_k(const std::vector<GridBits>& query, std::span<const GridBits> grids,
                                  std::span<const double> mu, double hub_weight, std::size_t k) {
  const std::vector<int> counts = grid_counts(query);
  std::vector<GridMatch> all(grids.size());
  for (std::size_t i = 0; i < grids.size(); ++i)
    all[i] = {i, grid_similarity(query, counts, grids[i]) - hub_weight * (mu.empty() ? 0.0 : mu[i])};
  keep_best(all, k, true);
  return all;
}

}  // namespace partslam
