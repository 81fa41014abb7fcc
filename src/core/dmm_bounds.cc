#include "core/dmm_bounds.h"

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
};

constexpr std::size_t kChunk = 65535;  // points per 16-bit count

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define PARTSLAM_DMM_AVX2 1
// Eight points at a time: their cell indices are computed in one vector, then each cell is broadcast.
__attribute__((target("avx2"))) void accumulate_avx2(const PassInput& in, std::array<int, 16>& bounds) {
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
  for (std::size_t begin = in.begin; begin < in.end; begin += kChunk) {
    const std::size_t end = std::min(in.end, begin + kChunk);
    __m256i acc0 = _mm256_setzero_si256(), acc1 = _mm256_setzero_si256();
    std::size_t k = begin;
    for (; k + 8 <= end; k += 8) {
      const __m256i x = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(xs + k));
      const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(ys + k));
      _mm256_store_si256(reinterpret_cast<__m256i*>(index.data()),
                         _mm256_add_epi32(_mm256_mullo_epi32(_mm256_add_epi32(y, vdy), vstride),
                                          _mm256_min_epu32(_mm256_add_epi32(x, vdx), vwidth)));
      for (std::size_t p = 0; p < 8; p += 2) {
        const __m256i v0 = _mm256_set1_epi16(static_cast<short>(cells[index[p]]));
        const __m256i v1 = _mm256_set1_epi16(static_cast<short>(cells[index[p + 1]]));
        acc0 = _mm256_sub_epi16(acc0, _mm256_cmpeq_epi16(_mm256_and_si256(v0, bits), bits));
        acc1 = _mm256_sub_epi16(acc1, _mm256_cmpeq_epi16(_mm256_and_si256(v1, bits), bits));
      }
    }
    for (; k < end; ++k) {
      const unsigned cx = std::min(static_cast<unsigned>(xs[k] + dx), width);
      const __m256i v = _mm256_set1_epi16(static_cast<short>(cells[static_cast<unsigned>(ys[k] + dy) * stride + cx]));
      acc0 = _mm256_sub_epi16(acc0, _mm256_cmpeq_epi16(_mm256_and_si256(v, bits), bits));
    }
    alignas(32) std::array<std::uint16_t, 16> lanes0, lanes1;
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes0.data()), acc0);
    _mm256_store_si256(reinterpret_cast<__m256i*>(lanes1.data()), acc1);
    for (std::size_t c = 0; c < 16; ++c) bounds[c] += lanes0[c] + lanes1[c];
  }
}
#endif

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
      const __m128i v = _mm_set1_epi16(static_cast<short>(cells[static_cast<unsigned>(ys[k] + dy) * stride + cx]));
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

std::array<int, 16> child_bounds(const PackedLevel& packed, const RotatedQuery& r, int i, int j, bool use_avx2) {
  std::array<int, 16> bounds{};
  if (packed.cells.empty()) return bounds;
  PassInput in;
  in.cells = packed.cells.data();
  in.width = static_cast<unsigned>(packed.width);
  in.xs = r.x.data();
  in.ys = r.y.data();
  in.dx = i - packed.x0;
  in.dy = j - packed.y0;
  // Points with 0 <= y + dy < height.
  in.begin = static_cast<std::size_t>(std::lower_bound(r.y.begin(), r.y.end(), -in.dy) - r.y.begin());
  in.end = static_cast<std::size_t>(std::lower_bound(r.y.begin(), r.y.end(), packed.height - in.dy) - r.y.begin());
#if defined(PARTSLAM_DMM_AVX2)
  if (use_avx2 && cpu_has_avx2()) {
    accumulate_avx2(in, bounds);
    return bounds;
  }
#endif
  accumulate_portable(in, bounds);
  return bounds;
}

}  // namespace partslam
