#include "core/matching/dmm_bounds.h"

#include <algorithm>

#if defined(__x86_64__) || defined(__SSE2__)
#include <immintrin.h>
#endif

namespace partslam {
namespace {

struct PassInput {
  const std::uint16_t* cells;
  unsigned width;  // columns; the row stride is width + 1
  const int* xs;
  const int* ys;
  std::size_t begin, end;  // points whose row lands on the grid
  int dx, dy;
  int bar;
  std::uint16_t* values;  // may be null
};

constexpr std::size_t kChunk = 65535;  // points per 16-bit count
constexpr std::size_t kCheckEvery = 64;  // points between early-stop tests

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define PARTSLAM_DMM_AVX2 1

__attribute__((target("avx2"))) int max_lane(__m256i v) {
  __m128i m = _mm_max_epu16(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
  m = _mm_max_epu16(m, _mm_shuffle_epi32(m, 0x4e));
  m = _mm_max_epu16(m, _mm_shuffle_epi32(m, 0xb1));
  m = _mm_max_epu16(m, _mm_shufflelo_epi16(m, 0xb1));
  return _mm_extract_epi16(m, 0);
}

// Eight points at a time: their cell indices are computed in one vector, then each cell is broadcast.
template <bool kStore>
__attribute__((target("avx2"))) bool accumulate_avx2(const PassInput& in, std::array<int, 16>& bounds) {
  const __m256i bits = _mm256_setr_epi16(1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096, 8192, 16384,
                                         static_cast<short>(32768));
  const std::uint16_t* cells = in.cells;
  const unsigned width = in.width, stride = in.width + 1;
  const int* xs = in.xs;
  const int* ys = in.ys;
  const int dx = in.dx, dy = in.dy;
  const __m256i vdx = _mm256_set1_epi32(dx), vdy = _mm256_set1_epi32(dy);
  const __m256i vwidth = _mm256_set1_epi32(static_cast<int>(width));
  const __m256i vstride = _mm256_set1_epi32(static_cast<int>(stride));
  alignas(32) std::array<std::uint32_t, 8> index;
  int flushed_max = 0;  // max over children of the counts of finished chunks
  for (std::size_t begin = in.begin; begin < in.end; begin += kChunk) {
    const std::size_t end = std::min(in.end, begin + kChunk);
    __m256i acc0 = _mm256_setzero_si256(), acc1 = _mm256_setzero_si256();
    std::size_t k = begin;
    std::size_t next_check = begin + kCheckEvery;
    for (; k + 8 <= end; k += 8) {
      const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(xs + k));
      const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ys + k));
      _mm256_store_si256(reinterpret_cast<__m256i*>(index.data()),
                         _mm256_add_epi32(_mm256_mullo_epi32(_mm256_add_epi32(y, vdy), vstride),
                                          _mm256_min_epu32(_mm256_add_epi32(x, vdx), vwidth)));
      for (std::size_t p = 0; p < 8; p += 2) {
        const std::uint16_t c0 = cells[index[p]], c1 = cells[index[p + 1]];
        if constexpr (kStore) {
          in.values[k + p] = c0;
          in.values[k + p + 1] = c1;
        }
        const __m256i v0 = _mm256_set1_epi16(static_cast<short>(c0));
        const __m256i v1 = _mm256_set1_epi16(static_cast<short>(c1));
        acc0 = _mm256_sub_epi16(acc0, _mm256_cmpeq_epi16(_mm256_and_si256(v0, bits), bits));
        acc1 = _mm256_sub_epi16(acc1, _mm256_cmpeq_epi16(_mm256_and_si256(v1, bits), bits));
      }
      if (k + 8 >= next_check) {
        next_check += kCheckEvery;
        const int best_possible = flushed_max + max_lane(_mm256_add_epi16(acc0, acc1)) + static_cast<int>(in.end - k - 8);
        if (best_possible <= in.bar) return false;
      }
    }
    for (; k < end; ++k) {
      const unsigned cx = std::min(static_cast<unsigned>(xs[k] + dx), width);
      const std::uint16_t c = cells[static_cast<unsigned>(ys[k] + dy) * stride + cx];
      if constexpr (kStore) in.values[k] = c;
      const __m256i v = _mm256_set1_epi16(static_cast<short>(c));
      acc0 = _mm256_sub_epi16(acc0, _mm256_cmpeq_epi16(_mm256_and_si256(v, bits), bits));
    }
    alignas(32) std::array<std::uint16_t, 16> lanes0, lanes1;
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes0.data()), acc0);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes1.data()), acc1);
    for (std::size_t c = 0; c < 16; ++c) {
      bounds[c] += lanes0[c] + lanes1[c];
      flushed_max = std::max(flushed_max, bounds[c]);
    }
  }
  return true;
}

// Left-packing eight points at a time: a 256-entry table turns the 8-bit keep mask into a permutation.
struct PackTable {
  std::array<std::uint64_t, 256> order{};  // byte p: index of the p-th kept lane
  PackTable() {
    for (unsigned mask = 0; mask < 256; ++mask) {
      unsigned p = 0;
      for (unsigned lane = 0; lane < 8; ++lane) {
        if (mask & (1u << lane)) order[mask] |= static_cast<std::uint64_t>(lane) << (8 * p++);
      }
    }
  }
};

// Returns how many points were kept from the first multiple-of-8 prefix (also how many were read: `k` out).
__attribute__((target("avx2,popcnt"))) std::size_t filter_avx2(const CellList& cells, const std::uint16_t* values,
                                                               int bit, int* out_x, int* out_y, std::size_t& k) {
  static const PackTable table;
  const __m256i select = _mm256_set1_epi32(1 << bit);
  std::size_t m = 0;
  for (k = 0; k + 8 <= cells.size; k += 8) {
    const __m256i v = _mm256_cvtepu16_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(values + k)));
    const auto mask = static_cast<unsigned>(
        _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(v, select), select))));
    const __m256i order = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(table.order[mask])));
    const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(cells.x + k));
    const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(cells.y + k));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out_x + m), _mm256_permutevar8x32_epi32(x, order));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out_y + m), _mm256_permutevar8x32_epi32(y, order));
    m += static_cast<std::size_t>(__builtin_popcount(mask));
  }
  return m;
}
#endif

// Portable path: never stops early (the search's result does not depend on it).
void accumulate_portable(const PassInput& in, std::array<int, 16>& bounds) {
  const std::uint16_t* cells = in.cells;
  const unsigned width = in.width, stride = in.width + 1;
  const int* xs = in.xs;
  const int* ys = in.ys;
  const int dx = in.dx, dy = in.dy;
#if defined(__SSE2__)
  const __m128i bits_lo = _mm_setr_epi16(1, 2, 4, 8, 16, 32, 64, 128);
  const __m128i bits_hi = _mm_setr_epi16(256, 512, 1024, 2048, 4096, 8192, 16384, static_cast<short>(32768));
  for (std::size_t begin = in.begin; begin < in.end; begin += kChunk) {
    const std::size_t end = std::min(in.end, begin + kChunk);
    __m128i lo = _mm_setzero_si128(), hi = _mm_setzero_si128();
    for (std::size_t k = begin; k < end; ++k) {
      const unsigned cx = std::min(static_cast<unsigned>(xs[k] + dx), width);
      const std::uint16_t c = cells[static_cast<unsigned>(ys[k] + dy) * stride + cx];
      if (in.values != nullptr) in.values[k] = c;
      const __m128i v = _mm_set1_epi16(static_cast<short>(c));
      lo = _mm_sub_epi16(lo, _mm_cmpeq_epi16(_mm_and_si128(v, bits_lo), bits_lo));  // +1 where set
      hi = _mm_sub_epi16(hi, _mm_cmpeq_epi16(_mm_and_si128(v, bits_hi), bits_hi));
    }
    alignas(16) std::array<std::uint16_t, 16> lanes;
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes.data()), lo);
    _mm_store_si128(reinterpret_cast<__m128i*>(lanes.data() + 8), hi);
    for (std::size_t c = 0; c < 16; ++c) bounds[c] += lanes[c];
  }
#else
  for (std::size_t k = in.begin; k < in.end; ++k) {
    const unsigned cx = std::min(static_cast<unsigned>(xs[k] + dx), width);
    const unsigned v = cells[static_cast<unsigned>(ys[k] + dy) * stride + cx];
    if (in.values != nullptr) in.values[k] = static_cast<std::uint16_t>(v);
    for (unsigned c = 0; c < 16; ++c) bounds[c] += static_cast<int>((v >> c) & 1u);
  }
#endif
}

}  // namespace

bool cpu_has_avx2() {
#if defined(PARTSLAM_DMM_AVX2)
  static const bool has_avx2 = __builtin_cpu_supports("avx2");
  return has_avx2;
#else
  return false;
#endif
}

bool child_bounds(const PackedLevel& packed, const CellList& cells, int i, int j, int bar, std::uint16_t* values,
                  std::array<int, 16>& bounds, bool use_avx2) {
  bounds.fill(0);
  if (packed.cells.empty()) {
    if (values != nullptr) std::fill(values, values + cells.size, std::uint16_t{0});
    return true;
  }
  PassInput in;
  in.cells = packed.cells.data();
  in.width = static_cast<unsigned>(packed.width);
  in.xs = cells.x;
  in.ys = cells.y;
  in.dx = i - packed.x0;
  in.dy = j - packed.y0;
  in.bar = bar;
  in.values = values;
  // Points with 0 <= y + dy < height.
  in.begin = static_cast<std::size_t>(std::lower_bound(cells.y, cells.y + cells.size, -in.dy) - cells.y);
  in.end = static_cast<std::size_t>(std::lower_bound(cells.y, cells.y + cells.size, packed.height - in.dy) - cells.y);
  if (values != nullptr) {
    std::fill(values, values + in.begin, std::uint16_t{0});
    std::fill(values + in.end, values + cells.size, std::uint16_t{0});
  }
#if defined(PARTSLAM_DMM_AVX2)
  if (use_avx2 && cpu_has_avx2()) {
    return values != nullptr ? accumulate_avx2<true>(in, bounds) : accumulate_avx2<false>(in, bounds);
  }
#endif
  accumulate_portable(in, bounds);
  return true;
}

std::size_t filter_cells(const CellList& cells, const std::uint16_t* values, int bit, int* out_x, int* out_y) {
  std::size_t k = 0, m = 0;
#if defined(PARTSLAM_DMM_AVX2)
  if (cpu_has_avx2()) m = filter_avx2(cells, values, bit, out_x, out_y, k);
#endif
  for (; k < cells.size; ++k) {  // branchless compaction
    out_x[m] = cells.x[k];
    out_y[m] = cells.y[k];
    m += (values[k] >> bit) & 1u;
  }
  return m;
}

}  // namespace partslam
