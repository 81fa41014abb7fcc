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

__extension__ typedef unsigned __int128 u128;

constexpr int kLagReach = 3;         // signature lags |dx|, |dy| <= 3
constexpr int kSignatureBytes = 15;  // bytes 0..14 hold lags; byte 15 of a record is mu's level

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

// L1 distance between two signatures' lags.
int signature_distance(const GridSignature& a, const GridSignature& b) {
  int d = 0;
  for (int i = 0; i < kSignatureBytes; ++i)
    d += std::abs((a[i] & 15) - (b[i] & 15)) + std::abs((a[i] >> 4) - (b[i] >> 4));
  return d;
}

// The distances of n records (a multiple of 8) to the query's signatures (min over them).
void distances_portable(const GridSignature* r, std::size_t n, const std::array<GridSignature, 2>& q,
                        std::uint16_t* out) {
  for (std::size_t j = 0; j < n; ++j)
    out[j] =
        static_cast<std::uint16_t>(std::min(signature_distance(r[j], q[0]), signature_distance(r[j], q[1])));
}

// The 16 bytes at p in each 128-bit lane.
__attribute__((target("avx512f"), always_inline)) inline __m512i broadcast16(const void* p) {
  const __m512i x = _mm512_zextsi128_si512(_mm_loadu_si128(static_cast<const __m128i*>(p)));
  return _mm512_shuffle_i32x4(x, x, 0);
}

__attribute__((target("avx512f,avx512bw"), always_inline)) inline __m512i distances4_avx512(
    __m512i x, const __m512i* qlo, const __m512i* qhi) {
  const __m512i nibble = _mm512_set1_epi8(15);
  static constexpr std::array<std::uint8_t, 16> kLags{255, 255, 255, 255, 255, 255, 255, 255,
                                                      255, 255, 255, 255, 255, 255, 255, 0};
  const __m512i lags = broadcast16(kLags.data());
  x = _mm512_and_si512(x, lags);
  const __m512i lo = _mm512_and_si512(x, nibble), hi = _mm512_and_si512(_mm512_srli_epi16(x, 4), nibble);
  __m512i best = _mm512_set1_epi64(-1);
  for (int t = 0; t < 2; ++t) {
    __m512i s = _mm512_add_epi64(_mm512_sad_epu8(lo, qlo[t]), _mm512_sad_epu8(hi, qhi[t]));
    s = _mm512_add_epi64(s, _mm512_shuffle_epi32(s, _MM_PERM_BADC));  // both halves of a record
    best = _mm512_min_epu64(best, s);
  }
  return best;
}

__attribute__((target("avx512f,avx512bw"))) void distances_avx512(const GridSignature* r, std::size_t n,
                                                                  const std::array<GridSignature, 2>& q,
                                                                  std::uint16_t* out) {
  __m512i qlo[2], qhi[2];
  for (int t = 0; t < 2; ++t) {
    const __m512i x = broadcast16(q[t].data());
    qlo[t] = _mm512_and_si512(x, _mm512_set1_epi8(15));
    qhi[t] = _mm512_and_si512(_mm512_srli_epi16(x, 4), _mm512_set1_epi8(15));
  }
  const __m512i even = _mm512_set_epi64(14, 12, 10, 8, 6, 4, 2, 0);
  for (std::size_t j = 0; j < n; j += 8) {
    const __m512i a = distances4_avx512(_mm512_loadu_si512(r + j), qlo, qhi);
    const __m512i b = distances4_avx512(_mm512_loadu_si512(r + j + 4), qlo, qhi);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + j),
                     _mm512_cvtepi64_epi16(_mm512_permutex2var_epi64(a, even, b)));
  }
}

bool cpu_has_avx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vpopcntdq");
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
  if (!(c.signature_keep > 0 && c.signature_keep <= 1))
    throw InputError("grid cascade: signature_keep must be in (0, 1]");
  if (!(c.coarse_keep > 0 && c.coarse_keep <= 1))
    throw InputError("grid cascade: coarse_keep must be in (0, 1]");
  if (c.signature_min < 1) throw InputError("grid cascade: signature_min must be >= 1");
  if (c.coarse_min < 1) throw InputError("grid cascade: coarse_min must be >= 1");
  if (c.coarse_reach < 0 || c.coarse_reach > 11)
    throw InputError("grid cascade: coarse_reach must be in [0, 11]");
}

namespace {

// One signature lag: the bit shift that takes cell (x + dx, y + dy) to cell (x, y), and the cells (x, y)
// whose (x + dx, y + dy) lies on the grid (empty when none does, e.g. on grids narrower than the lag).
struct Lag {
  int shift = 0;
  u128 cells = 0;
};

// The 24 lags of a grid of S cells a side, in signature order (dy 0: dx 1..3; then dy 1..3: dx -3..3).
std::array<Lag, 24> lags_of(int side) {
  std::array<Lag, 24> out{};
  std::size_t lag = 0;
  for (int dy = 0; dy <= kLagReach; ++dy)
    for (int dx = -kLagReach; dx <= kLagReach; ++dx) {
      if (dy == 0 && dx <= 0) continue;
      Lag& l = out[lag++];
      l.shift = dx + side * dy;
      for (int y = 0; y + dy < side; ++y)
        for (int x = std::max(0, -dx); x < side && x + dx < side; ++x)
          l.cells |= static_cast<u128>(1) << (x + side * y);
    }
  return out;
}

}  // namespace

GridSignature grid_signature(const GridBits& grid, int cells) {
  if (cells < 1 || cells > 11) throw InputError("grid signature: cells must be in [1, 11]");
  static const std::array<std::array<Lag, 24>, 12> kLags = [] {
    std::array<std::array<Lag, 24>, 12> t{};
    for (int side = 1; side <= 11; ++side) t[static_cast<std::size_t>(side)] = lags_of(side);
    return t;
  }();
  const u128 g = (static_cast<u128>(grid.words[1]) << 64) | grid.words[0];
  GridSignature out{};
  for (std::size_t lag = 0; lag < 24; ++lag) {
    const Lag& l = kLags[static_cast<std::size_t>(cells)][lag];
    if (l.cells == 0) continue;  // no pair at this lag (and its shift may not be positive)
    const u128 pairs = g & (g >> l.shift) & l.cells;
    const int c = std::popcount(static_cast<std::uint64_t>(pairs)) +
                  std::popcount(static_cast<std::uint64_t>(pairs >> 64));
    const auto value = static_cast<std::uint8_t>(std::min(15, c / 2));
    out[lag / 2] |= static_cast<std::uint8_t>(lag % 2 == 0 ? value : value << 4);
  }
  return out;
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
  blocks_.resize((size_ + 7) / 8);
  records_.resize(blocks_.size() * 8);
  const bool signatures = size_ > keep(0).signature;  // a larger k only keeps more
  for (std::size_t i = 0; i < size_; ++i) {
    blocks_[i / 8].w0[i % 8] = grids[i].words[0];
    blocks_[i / 8].w1[i % 8] = grids[i].words[1];
    if (signatures) records_[i] = grid_signature(grids[i], grid_.cells);
    const double m = mu.empty() ? 0.0 : mu[i];
    const double level = std::round(m * levels_);
    if (!(level >= 0 && level <= levels_) || level / levels_ != m)
      throw InputError("grid cascade: hubness of map " + std::to_string(i) +
                       " is not on the hub_bits lattice");
    records_[i][kSignatureBytes] = static_cast<std::uint8_t>(level);
  }
}

GridCascade::Keep GridCascade::keep(std::size_t k) const {
  Keep out;
  out.coarse = std::max(keep_count(config_.coarse_keep, config_.coarse_min, size_), k);
  out.signature = std::max(keep_count(config_.signature_keep, config_.signature_min, size_), out.coarse);
  return out;
}

std::size_t GridCascade::memory_bytes() const {
  return blocks_.size() * sizeof(Block) + records_.size() * sizeof(GridSignature);
}

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
      out[j + i] = {id, static_cast<double>(both[i]) / either[i] -
                            grid_.hub_weight * (records_[id][kSignatureBytes] / levels_)};
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
                                          GridCascadeStats* stats) const {
  check_query(query);
  const int reach = grid_.max_shift * grid_.substeps, side = 2 * reach + 1;
  GridCascadeStats st;
  const std::size_t n = size_;
  const auto [coarse_n, signature_n] = keep(k);
  auto pose = [&](int turn, int row, int column) {
    return query[static_cast<std::size_t>((turn * side + row) * side + column)];
  };

  // 1. signatures: the maps nearest the query's (turns 0 and 1; 2 and 3 give the same codes), ties by index.
  auto t0 = Clock::now();
  std::vector<std::uint32_t> list;
  if (n > signature_n) {
    const std::array<GridSignature, 2> q{grid_signature(pose(0, reach, reach), grid_.cells),
                                         grid_signature(pose(1, reach, reach), grid_.cells)};
    std::vector<std::uint16_t> distance(records_.size());
    (simd_ ? distances_avx512 : distances_portable)(records_.data(), records_.size(), q, distance.data());
    // Four interleaved histograms: runs of equal distances do not wait on one counter.
    std::array<std::array<std::uint32_t, 512>, 4> part{};
    std::size_t i = 0;
    for (; i + 4 <= n; i += 4)
      for (std::size_t h = 0; h < 4; ++h) ++part[h][distance[i + h]];
    for (; i < n; ++i) ++part[0][distance[i]];
    std::array<std::size_t, 512> histogram{};
    for (std::size_t d = 0; d < histogram.size(); ++d)
      histogram[d] = std::size_t{part[0][d]} + part[1][d] + part[2][d] + part[3][d];
    std::size_t bar = 0, below = 0;
    while (below + histogram[bar] < signature_n) below += histogram[bar++];
    std::size_t at_bar = signature_n - below;
    list.resize(signature_n + 1);  // one spare slot: each map is written, and kept by moving on
    std::size_t kept = 0;
    for (std::size_t j = 0; j < n; ++j) {  // branch-free: most maps are dropped, at random
      const bool tie = distance[j] == bar && at_bar > 0;
      list[kept] = static_cast<std::uint32_t>(j);
      kept += distance[j] < bar || tie;
      at_bar -= tie;
    }
    list.resize(kept);
  } else {
    list.resize(n);
    std::iota(list.begin(), list.end(), std::uint32_t{0});
  }
  st.signature_kept = list.size();
  st.signature_ms = ms_since(t0);

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
