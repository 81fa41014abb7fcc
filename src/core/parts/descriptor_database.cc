#include "core/parts/descriptor_database.h"

#include <omp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "core/error.h"

// The kernel is compiled twice, for AVX2 and for baseline x86-64, and the loader picks one. Both do the same
// float operations in the same order (no FMA contraction under -std=c++20), so results are identical.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_ADDRESS__)
#define PARTSLAM_MULTIVERSION __attribute__((target_clones("avx2", "default")))
#else
#define PARTSLAM_MULTIVERSION
#endif

namespace partslam {
namespace {

constexpr int kLanes = DescriptorDatabase::kLanes;
constexpr long long kGridOffset = 32768;  // cell 0 of the grid sits at -32768 * resolution
constexpr int kMaxSideCells = 255;
constexpr int kMaxPartsPerMap = 64;  // keeps area(Bl ∩ Bg) <= 65025 in 16 bits
constexpr std::uint32_t kNoMap = std::numeric_limits<std::uint32_t>::max();
constexpr std::size_t kBlocksPerSuper = DescriptorDatabase::kBlocksPerSuper;

// A box in grid cells (unclamped).
struct CellBox {
  long long x0, x1, y0, y1;
  long long area() const { return x1 > x0 && y1 > y0 ? (x1 - x0) * (y1 - y0) : 0; }
};

CellBox to_cells(const Box2& b, double resolution) {
  return {std::llround(b.x_min / resolution) + kGridOffset, std::llround(b.x_max / resolution) + kGridOffset,
          std::llround(b.y_min / resolution) + kGridOffset, std::llround(b.y_max / resolution) + kGridOffset};
}

std::uint16_t clamp16(long long v) { return static_cast<std::uint16_t>(std::clamp(v, 0LL, 65535LL)); }

bool finite(const Box2& b) {
  return std::isfinite(b.x_min) && std::isfinite(b.x_max) && std::isfinite(b.y_min) && std::isfinite(b.y_max);
}

// Interleaves the bits of x and y (Morton / Z order).
std::uint32_t morton(std::uint16_t x, std::uint16_t y) {
  auto spread = [](std::uint32_t v) {
    v = (v | (v << 8)) & 0x00FF00FFu;
    v = (v | (v << 4)) & 0x0F0F0F0Fu;
    v = (v | (v << 2)) & 0x33333333u;
    v = (v | (v << 1)) & 0x55555555u;
    return v;
  };
  return spread(x) | (spread(y) << 1);
}

// A part's dictionary_origin in half cells (exact for boxes on the grid), offset into 16 bits.
std::array<std::uint16_t, 2> origin_half_cells(const Part& part, double resolution) {
  const Vec2 o = dictionary_origin(part);
  return {clamp16(std::llround(2 * o.x() / resolution) + kGridOffset),
          clamp16(std::llround(2 * o.y() / resolution) + kGridOffset)};
}

// Query parts in structure-of-arrays form, only those that can score (positive area and weight).
struct QueryBoxes {
  std::vector<std::uint16_t> x0, x1, y0, y1;
  std::vector<std::uint16_t> ox, oy;  // dictionary origin [half cells]
  std::uint16_t gate = 65535;         // origin gate [half cells]; 65535: off
  std::vector<float> weight;  // 1 / sqrt(area) [cells^-1], times AS for Sum-Max-Weighted
};

QueryBoxes prepare_query(const MapDescriptor& query, Matcher matcher, double resolution, double origin_gate) {
  QueryBoxes q;
  if (origin_gate > 0) q.gate = clamp16(static_cast<long long>(std::floor(2 * origin_gate / resolution + 1e-9)));
  for (std::size_t i = 0; i < query.parts.size(); ++i) {
    const Part& p = query.parts[i];
    if (!finite(p.descriptor_box)) {
      throw InputError("score_all: query part " + std::to_string(i) + " has a non-finite descriptor_box");
    }
    double weight = 1.0;
    if (matcher == Matcher::kSumMaxWeighted) {
      weight = p.appearance_score;
      if (!std::isfinite(weight) || weight < 0) {
        throw InputError("score_all: query part " + std::to_string(i) +
                         " has an appearance_score that is negative or not finite");
      }
    }
    const CellBox c = to_cells(p.descriptor_box, resolution);
    // Clamping to the grid does not change the overlap with any stored box, which all lie on the grid; the
    // area comes from the unclamped box.
    if (c.area() == 0 || weight == 0) continue;
    q.x0.push_back(clamp16(c.x0));
    q.x1.push_back(clamp16(c.x1));
    q.y0.push_back(clamp16(c.y0));
    q.y1.push_back(clamp16(c.y1));
    const auto o = origin_half_cells(p, resolution);
    q.ox.push_back(o[0]);
    q.oy.push_back(o[1]);
    q.weight.push_back(static_cast<float>(weight / std::sqrt(static_cast<double>(c.area()))));
  }
  return q;
}

// GCC/Clang vector extensions: element-wise IEEE operations, lowered to AVX2 or SSE2 per clone.
static_assert(std::endian::native == std::endian::little, "the zero-extension below assumes little endian");
using U16x16 = std::uint16_t __attribute__((vector_size(32)));
using F32x8 = float __attribute__((vector_size(32)));
using I32x8 = std::int32_t __attribute__((vector_size(32)));
// Element-wise max / min as macros: helper functions taking 32-byte vectors by value would change the ABI
// of the baseline clone (-Wpsabi).
#define PARTSLAM_VMAX(a, b) ((a) > (b) ? (a) : (b))
#define PARTSLAM_VMIN(a, b) ((a) < (b) ? (a) : (b))

// A block's (and a super block's) bounds: the union of its boxes (x0, x1, y0, y1) and the range of its parts'
// dictionary origins (ox0, ox1, oy0, oy1, half cells), empty slots left out.
constexpr std::size_t kBoundFields = 8;

// Read-only view of the database layout for the kernel.
struct Layout {
  const std::uint16_t* coords;
  const std::uint16_t* origins;  // [block][slot][ox, oy][lane], half cells
  const float* inv_sqrt_area;
  const std::uint16_t* bounds;        // per block
  const std::uint16_t* super_bounds;  // per group of kBlocksPerSuper blocks
  const std::uint32_t* map_index;
  std::size_t num_blocks;
  int num_slots;
};

// Keeps the query parts of `in` whose box overlaps `bound` (x0, x1, y0, y1) with positive area and whose
// dictionary origin lies within the gate of the bound's origins (ox0, ox1, oy0, oy1): a part failing either
// adds exactly 0 to every map under the bound. With the gate off (65535) the origin test always passes.
std::size_t filter_overlapping(const QueryBoxes& q, const std::uint32_t* in, std::size_t n,
                               const std::uint16_t* bound, std::uint32_t* out) {
  std::size_t kept = 0;
  const int gate = q.gate;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = in[k];
    out[kept] = i;
    kept += (q.x0[i] < bound[1]) & (bound[0] < q.x1[i]) & (q.y0[i] < bound[3]) & (bound[2] < q.y1[i]) &
            (q.ox[i] + gate >= bound[4]) & (bound[5] + gate >= q.ox[i]) & (q.oy[i] + gate >= bound[6]) &
            (bound[7] + gate >= q.oy[i]);
  }
  return kept;
}

// Scores the maps of super blocks [begin, end) into scores[map]; maps no query part can reach keep 0.
PARTSLAM_MULTIVERSION
void score_range(const Layout& layout, std::size_t begin, std::size_t end, const QueryBoxes& q, bool use_max,
                 float* __restrict scores) {
  const std::size_t n = q.weight.size();
  std::vector<std::uint32_t> all(n), near_super(n), active(n);
  std::iota(all.begin(), all.end(), 0u);
  for (std::size_t super = begin; super < end; ++super) {
    const std::size_t num_near =
        filter_overlapping(q, all.data(), n, layout.super_bounds + kBoundFields * super, near_super.data());
    if (num_near == 0) continue;
    const std::size_t block_end = std::min(layout.num_blocks, (super + 1) * kBlocksPerSuper);
    for (std::size_t block = super * kBlocksPerSuper; block < block_end; ++block) {
      const std::size_t num_active =
          filter_overlapping(q, near_super.data(), num_near, layout.bounds + kBoundFields * block, active.data());
      if (num_active == 0) continue;
      // Lanes are 16 maps: coordinates in one 16 x u16 vector, scores in two 8 x float halves.
      F32x8 acc_lo = {}, acc_hi = {};
      for (std::size_t a = 0; a < num_active; ++a) {
        const std::size_t i = active[a];
        const U16x16 qx0 = U16x16{} + q.x0[i], qx1 = U16x16{} + q.x1[i];
        const U16x16 qy0 = U16x16{} + q.y0[i], qy1 = U16x16{} + q.y1[i];
        const U16x16 qox = U16x16{} + q.ox[i], qoy = U16x16{} + q.oy[i], gate = U16x16{} + q.gate;
        F32x8 best_lo = {}, best_hi = {};
        for (int j = 0; j < layout.num_slots; ++j) {
          const std::size_t slot =
              block * static_cast<std::size_t>(layout.num_slots) + static_cast<std::size_t>(j);
          const std::uint16_t* c = layout.coords + slot * 4 * kLanes;
          const float* g = layout.inv_sqrt_area + slot * kLanes;
          const std::uint16_t* o = layout.origins + slot * 2 * kLanes;
          U16x16 x0, x1, y0, y1, ox, oy;
          F32x8 g_lo, g_hi;
          std::memcpy(&x0, c, sizeof(x0));
          std::memcpy(&x1, c + kLanes, sizeof(x1));
          std::memcpy(&y0, c + 2 * kLanes, sizeof(y0));
          std::memcpy(&y1, c + 3 * kLanes, sizeof(y1));
          std::memcpy(&ox, o, sizeof(ox));
          std::memcpy(&oy, o + kLanes, sizeof(oy));
          std::memcpy(&g_lo, g, sizeof(g_lo));
          std::memcpy(&g_hi, g + 8, sizeof(g_hi));
          const U16x16 lo_x = PARTSLAM_VMAX(qx0, x0), hi_x = PARTSLAM_VMIN(qx1, x1);
          const U16x16 lo_y = PARTSLAM_VMAX(qy0, y0), hi_y = PARTSLAM_VMIN(qy1, y1);
          // Saturating differences: the overlap's sides, 0 when the boxes miss.
          // Origin gate: |dx|, |dy| <= gate, as a lane mask (all ones / zero).
          const U16x16 dox = PARTSLAM_VMAX(qox, ox) - PARTSLAM_VMIN(qox, ox);
          const U16x16 doy = PARTSLAM_VMAX(qoy, oy) - PARTSLAM_VMIN(qoy, oy);
          const U16x16 pass = reinterpret_cast<U16x16>((dox <= gate) & (doy <= gate));
          const U16x16 overlap =
              ((PARTSLAM_VMAX(hi_x, lo_x) - lo_x) * (PARTSLAM_VMAX(hi_y, lo_y) - lo_y)) & pass;
          // Zero-extend each half to 32 bits (interleave with zeros, reinterpret), then convert to float.
          const U16x16 z = {};
          const I32x8 overlap_lo = reinterpret_cast<I32x8>(
              __builtin_shufflevector(overlap, z, 0, 16, 1, 16, 2, 16, 3, 16, 4, 16, 5, 16, 6, 16, 7, 16));
          const I32x8 overlap_hi = reinterpret_cast<I32x8>(__builtin_shufflevector(
              overlap, z, 8, 16, 9, 16, 10, 16, 11, 16, 12, 16, 13, 16, 14, 16, 15, 16));
          best_lo = PARTSLAM_VMAX(best_lo, __builtin_convertvector(overlap_lo, F32x8) * g_lo);
          best_hi = PARTSLAM_VMAX(best_hi, __builtin_convertvector(overlap_hi, F32x8) * g_hi);
        }
        const F32x8 weight = F32x8{} + q.weight[i];
        if (use_max) {
          acc_lo = PARTSLAM_VMAX(acc_lo, weight * best_lo);
          acc_hi = PARTSLAM_VMAX(acc_hi, weight * best_hi);
        } else {
          acc_lo += weight * best_lo;
          acc_hi += weight * best_hi;
        }
      }
      alignas(32) float acc[kLanes];
      std::memcpy(acc, &acc_lo, sizeof(acc_lo));
      std::memcpy(acc + 8, &acc_hi, sizeof(acc_hi));
      for (int l = 0; l < kLanes; ++l) {
        const std::uint32_t m = layout.map_index[block * kLanes + static_cast<std::size_t>(l)];
        if (m != kNoMap) scores[m] = acc[l];
      }
    }
  }
}

#undef PARTSLAM_VMAX
#undef PARTSLAM_VMIN

}  // namespace

void validate(const PartsConfig& c) {
  if (c.codec) validate(*c.codec);
  if (c.hmm_query_parts < 1) throw InputError("parts config: hmm_query_parts must be >= 1");
  if (!(c.origin_gate >= 0) || !std::isfinite(c.origin_gate))
    throw InputError("parts config: origin_gate must be a finite number >= 0 [m]");
}

void validate(const DescriptorDatabaseConfig& c) {
  if (c.parts_per_map < 1 || c.parts_per_map > kMaxPartsPerMap) {
    throw InputError("descriptor database config: parts_per_map must be in [1, 64], got " +
                     std::to_string(c.parts_per_map));
  }
  if (!(c.resolution > 0) || !std::isfinite(c.resolution)) {
    throw InputError("descriptor database config: resolution must be a positive finite number [m]");
  }
}

DescriptorDatabase::DescriptorDatabase(const DescriptorDatabaseConfig& config) : config_(config) {
  validate(config_);
}

DescriptorDatabase::DescriptorDatabase(const std::vector<MapDescriptor>& maps,
                                       const DescriptorDatabaseConfig& config)
    : DescriptorDatabase(
          maps.size(), [&maps](std::size_t i, MapDescriptor&) -> const MapDescriptor& { return maps[i]; }, config) {}

DescriptorDatabase::DescriptorDatabase(std::size_t num_maps, const MapSource& map_at,
                                       const DescriptorDatabaseConfig& config)
    : DescriptorDatabase(config) {
  if (num_maps >= kNoMap) throw InputError("descriptor database: too many maps");
  std::vector<std::uint32_t> order(num_maps);
  std::iota(order.begin(), order.end(), 0u);
  MapDescriptor scratch;
  if (config_.spatial_order) {
    std::vector<std::uint32_t> key(num_maps, std::numeric_limits<std::uint32_t>::max());
    for (std::size_t i = 0; i < num_maps; ++i) {
      long long x0 = std::numeric_limits<long long>::max(), x1 = std::numeric_limits<long long>::min();
      long long y0 = x0, y1 = x1;
      for (const Part& p : map_at(i, scratch).parts) {
        if (!finite(p.descriptor_box)) continue;  // add() reports it
        const CellBox c = to_cells(p.descriptor_box, config_.resolution);
        x0 = std::min(x0, c.x0), x1 = std::max(x1, c.x1), y0 = std::min(y0, c.y0), y1 = std::max(y1, c.y1);
      }
      if (x0 <= x1 && y0 <= y1) key[i] = morton(clamp16((x0 + x1) / 2), clamp16((y0 + y1) / 2));
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  }
  const std::size_t blocks = (num_maps + kLanes - 1) / kLanes;
  coords_.reserve(blocks * static_cast<std::size_t>(config_.parts_per_map) * 4 * kLanes);
  inv_sqrt_area_.reserve(blocks * static_cast<std::size_t>(config_.parts_per_map) * kLanes);
  for (std::uint32_t i : order) append(map_at(i, scratch), i);
  num_maps_ = num_maps;
}

std::size_t DescriptorDatabase::add(const MapDescriptor& map) {
  if (num_maps_ + 1 >= kNoMap) throw InputError("descriptor database: too many maps");
  append(map, num_maps_);
  return num_maps_++;
}

void DescriptorDatabase::append(const MapDescriptor& map, std::size_t index) {
  const std::size_t k = static_cast<std::size_t>(config_.parts_per_map);
  if (map.parts.size() > k) {
    throw InputError("descriptor database: map " + std::to_string(index) + " has " +
                     std::to_string(map.parts.size()) +
                     " parts, more than parts_per_map = " + std::to_string(k));
  }
  std::array<CellBox, kMaxPartsPerMap> cells;
  for (std::size_t j = 0; j < map.parts.size(); ++j) {
    auto fail = [&](const char* what) {
      throw InputError("descriptor database: map " + std::to_string(index) + " part " + std::to_string(j) +
                       ": descriptor_box " + what);
    };
    const Box2& box = map.parts[j].descriptor_box;
    if (!finite(box)) fail("is not finite");
    const CellBox c = to_cells(box, config_.resolution);
    if (std::min({c.x0, c.x1, c.y0, c.y1}) < 0 || std::max({c.x0, c.x1, c.y0, c.y1}) > 65535) {
      fail("lies outside the grid of +-32768 cells of resolution");
    }
    if (c.x1 - c.x0 > kMaxSideCells || c.y1 - c.y0 > kMaxSideCells) {
      fail("is larger than 255 cells of resolution on a side");
    }
    cells[j] = c;
  }
  const std::size_t lane = num_stored_ % kLanes;
  const std::size_t block = num_stored_ / kLanes;
  if (lane == 0) {  // open a new block: empty slots, empty bounds, padding lanes
    coords_.resize(coords_.size() + k * 4 * kLanes, 0);
    origins_.resize(origins_.size() + k * 2 * kLanes, 0);
    inv_sqrt_area_.resize(inv_sqrt_area_.size() + k * kLanes, 0.0f);
    bounds_.insert(bounds_.end(), {65535, 0, 65535, 0, 65535, 0, 65535, 0});
    if (block % kBlocksPerSuper == 0)
      super_bounds_.insert(super_bounds_.end(), {65535, 0, 65535, 0, 65535, 0, 65535, 0});
    map_index_.resize(map_index_.size() + kLanes, kNoMap);
  }
  std::uint16_t* bound = &bounds_[kBoundFields * block];
  std::uint16_t* super_bound = &super_bounds_[kBoundFields * (block / kBlocksPerSuper)];
  for (std::size_t j = 0; j < map.parts.size(); ++j) {
    const CellBox& c = cells[j];
    if (c.area() == 0) continue;  // an empty slot never overlaps anything
    std::uint16_t* base = &coords_[((block * k + j) * 4) * kLanes + lane];
    base[0] = static_cast<std::uint16_t>(c.x0);
    base[kLanes] = static_cast<std::uint16_t>(c.x1);
    base[2 * kLanes] = static_cast<std::uint16_t>(c.y0);
    base[3 * kLanes] = static_cast<std::uint16_t>(c.y1);
    const auto o = origin_half_cells(map.parts[j], config_.resolution);
    origins_[((block * k + j) * 2) * kLanes + lane] = o[0];
    origins_[((block * k + j) * 2 + 1) * kLanes + lane] = o[1];
    inv_sqrt_area_[(block * k + j) * kLanes + lane] =
        static_cast<float>(1.0 / std::sqrt(static_cast<double>(c.area())));
    const std::uint16_t fields[kBoundFields] = {base[0], base[kLanes], base[2 * kLanes], base[3 * kLanes],
                                                o[0],    o[0],         o[1],             o[1]};
    for (std::size_t f = 0; f < kBoundFields; f += 2) {
      bound[f] = std::min(bound[f], fields[f]);
      bound[f + 1] = std::max(bound[f + 1], fields[f + 1]);
      super_bound[f] = std::min(super_bound[f], bound[f]);
      super_bound[f + 1] = std::max(super_bound[f + 1], bound[f + 1]);
    }
  }
  map_index_[block * kLanes + lane] = static_cast<std::uint32_t>(index);
  ++num_stored_;
}

std::size_t DescriptorDatabase::memory_bytes() const {
  return (coords_.size() + origins_.size()) * sizeof(std::uint16_t) + inv_sqrt_area_.size() * sizeof(float) +
         (bounds_.size() + super_bounds_.size()) * sizeof(std::uint16_t) +
         map_index_.size() * sizeof(std::uint32_t);
}

std::vector<float> DescriptorDatabase::score_all(const MapDescriptor& query, Matcher matcher,
                                                 const ScoreOptions& options) const {
  std::vector<float> scores;
  score_all(query, matcher, options, scores);
  return scores;
}

void DescriptorDatabase::score_all(const MapDescriptor& query, Matcher matcher, const ScoreOptions& options,
                                   std::vector<float>& scores) const {
  if (options.num_threads < 0 || options.num_threads > 1024)
    throw InputError("score_all: num_threads must be in [0, 1024], got " +
                     std::to_string(options.num_threads));
  if (!(options.origin_gate >= 0) || !std::isfinite(options.origin_gate))
    throw InputError("score_all: origin_gate must be >= 0 [m]");
  const QueryBoxes q = prepare_query(query, matcher, config_.resolution, options.origin_gate);
  scores.assign(num_maps_, 0.0f);
  const Layout layout{coords_.data(),       origins_.data(),    inv_sqrt_area_.data(),
                      bounds_.data(),       super_bounds_.data(), map_index_.data(),
                      bounds_.size() / kBoundFields,   config_.parts_per_map};
  const std::size_t supers = super_bounds_.size() / kBoundFields;
  const bool use_max = matcher == Matcher::kMaxMax;
  const int threads = options.num_threads == 0 ? omp_get_max_threads() : options.num_threads;
  if (threads <= 1 || supers < 2) {
    score_range(layout, 0, supers, q, use_max, scores.data());
    return;
  }
#pragma omp parallel num_threads(threads)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t nt = static_cast<std::size_t>(omp_get_num_threads());
    score_range(layout, supers * t / nt, supers * (t + 1) / nt, q, use_max, scores.data());
  }
}

}  // namespace partslam
