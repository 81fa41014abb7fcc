#include "core/descriptor_database.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
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
constexpr int kMaxSideCells = 255;        // keeps area(Bl ∩ Bg) <= 65025 in 16 bits
constexpr std::uint32_t kNoMap = std::numeric_limits<std::uint32_t>::max();

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

// Query parts in structure-of-arrays form, only those that can score (positive area and weight).
struct QueryBoxes {
  std::vector<std::uint16_t> x0, x1, y0, y1;
  std::vector<float> weight;  // 1 / sqrt(area) [cells^-1], times AS for Sum-Max-Weighted
};

QueryBoxes prepare_query(const MapDescriptor& query, Matcher matcher, double resolution) {
  QueryBoxes q;
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
    q.weight.push_back(static_cast<float>(weight / std::sqrt(static_cast<double>(c.area()))));
  }
  return q;
}

// Scores blocks [begin, end). scores[map] is written for every map of these blocks.
PARTSLAM_MULTIVERSION
void score_blocks(const std::uint16_t* __restrict coords, const float* __restrict inv_sqrt_area,
                  const std::uint16_t* __restrict bounds, const std::uint32_t* __restrict map_index,
                  std::size_t begin, std::size_t end, int num_slots, const QueryBoxes& q, bool use_max,
                  float* __restrict scores) {
  const std::size_t n = q.weight.size();
  std::vector<std::uint32_t> active(n);
  for (std::size_t block = begin; block < end; ++block) {
    const std::uint16_t* b = bounds + 4 * block;
    std::size_t num_active = 0;
    for (std::size_t i = 0; i < n; ++i) {
      active[num_active] = static_cast<std::uint32_t>(i);
      num_active += (q.x0[i] < b[1]) & (b[0] < q.x1[i]) & (q.y0[i] < b[3]) & (b[2] < q.y1[i]);
    }
    alignas(64) float acc[kLanes] = {};
    for (std::size_t a = 0; a < num_active; ++a) {
      const std::size_t i = active[a];
      const std::uint16_t qx0 = q.x0[i], qx1 = q.x1[i], qy0 = q.y0[i], qy1 = q.y1[i];
      alignas(64) float best[kLanes] = {};
      for (int j = 0; j < num_slots; ++j) {
        const std::size_t slot = block * static_cast<std::size_t>(num_slots) + static_cast<std::size_t>(j);
        const std::uint16_t* __restrict x0 = coords + slot * 4 * kLanes;
        const std::uint16_t* __restrict x1 = x0 + kLanes;
        const std::uint16_t* __restrict y0 = x0 + 2 * kLanes;
        const std::uint16_t* __restrict y1 = x0 + 3 * kLanes;
        const float* __restrict g = inv_sqrt_area + slot * kLanes;
#pragma omp simd
        for (int l = 0; l < kLanes; ++l) {
          const std::uint16_t lo_x = std::max(qx0, x0[l]), hi_x = std::min(qx1, x1[l]);
          const std::uint16_t lo_y = std::max(qy0, y0[l]), hi_y = std::min(qy1, y1[l]);
          // max(hi, lo) - lo rather than a conditional: the loop must stay free of control flow to vectorise.
          const std::uint16_t w = static_cast<std::uint16_t>(std::max(hi_x, lo_x) - lo_x);
          const std::uint16_t h = static_cast<std::uint16_t>(std::max(hi_y, lo_y) - lo_y);
          const std::uint16_t overlap = static_cast<std::uint16_t>(w * h);
          best[l] = std::max(best[l], static_cast<float>(overlap) * g[l]);
        }
      }
      const float weight = q.weight[i];
      if (use_max) {
#pragma omp simd
        for (int l = 0; l < kLanes; ++l) acc[l] = std::max(acc[l], weight * best[l]);
      } else {
#pragma omp simd
        for (int l = 0; l < kLanes; ++l) acc[l] += weight * best[l];
      }
    }
    for (int l = 0; l < kLanes; ++l) {
      const std::uint32_t m = map_index[block * kLanes + static_cast<std::size_t>(l)];
      if (m != kNoMap) scores[m] = acc[l];
    }
  }
}

}  // namespace

void validate(const DescriptorDatabaseConfig& c) {
  if (c.parts_per_map < 1 || c.parts_per_map > 64) {
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
    : DescriptorDatabase(config) {
  if (maps.size() >= kNoMap) throw InputError("descriptor database: too many maps");
  std::vector<std::uint32_t> order(maps.size());
  std::iota(order.begin(), order.end(), 0u);
  if (config_.spatial_order) {
    std::vector<std::uint32_t> key(maps.size(), std::numeric_limits<std::uint32_t>::max());
    for (std::size_t i = 0; i < maps.size(); ++i) {
      long long x0 = std::numeric_limits<long long>::max(), x1 = std::numeric_limits<long long>::min();
      long long y0 = x0, y1 = x1;
      for (const Part& p : maps[i].parts) {
        if (!finite(p.descriptor_box)) continue;  // add() reports it
        const CellBox c = to_cells(p.descriptor_box, config_.resolution);
        x0 = std::min(x0, c.x0), x1 = std::max(x1, c.x1), y0 = std::min(y0, c.y0), y1 = std::max(y1, c.y1);
      }
      if (x0 <= x1 && y0 <= y1) key[i] = morton(clamp16((x0 + x1) / 2), clamp16((y0 + y1) / 2));
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  }
  const std::size_t blocks = (maps.size() + kLanes - 1) / kLanes;
  coords_.reserve(blocks * static_cast<std::size_t>(config_.parts_per_map) * 4 * kLanes);
  inv_sqrt_area_.reserve(blocks * static_cast<std::size_t>(config_.parts_per_map) * kLanes);
  for (std::uint32_t i : order) append(maps[i], i);
  num_maps_ = maps.size();
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
  std::vector<CellBox> cells(map.parts.size());
  for (std::size_t j = 0; j < map.parts.size(); ++j) {
    const Box2& box = map.parts[j].descriptor_box;
    const std::string where =
        "descriptor database: map " + std::to_string(index) + " part " + std::to_string(j);
    if (!finite(box)) throw InputError(where + ": descriptor_box is not finite");
    const CellBox c = to_cells(box, config_.resolution);
    if (std::min({c.x0, c.x1, c.y0, c.y1}) < 0 || std::max({c.x0, c.x1, c.y0, c.y1}) > 65535) {
      throw InputError(where + ": descriptor_box lies outside the grid of +-32768 cells of resolution");
    }
    if (c.x1 - c.x0 > kMaxSideCells || c.y1 - c.y0 > kMaxSideCells) {
      throw InputError(where + ": descriptor_box is larger than 255 cells of resolution on a side");
    }
    cells[j] = c;
  }
  const std::size_t lane = num_stored_ % kLanes;
  const std::size_t block = num_stored_ / kLanes;
  if (lane == 0) {  // open a new block: empty slots, empty bounds, padding lanes
    coords_.resize(coords_.size() + k * 4 * kLanes, 0);
    inv_sqrt_area_.resize(inv_sqrt_area_.size() + k * kLanes, 0.0f);
    bounds_.insert(bounds_.end(), {65535, 0, 65535, 0});
    map_index_.resize(map_index_.size() + kLanes, kNoMap);
  }
  std::uint16_t* bound = &bounds_[4 * block];
  for (std::size_t j = 0; j < cells.size(); ++j) {
    const CellBox& c = cells[j];
    if (c.area() == 0) continue;  // an empty slot never overlaps anything
    std::uint16_t* base = &coords_[((block * k + j) * 4) * kLanes + lane];
    base[0] = static_cast<std::uint16_t>(c.x0);
    base[kLanes] = static_cast<std::uint16_t>(c.x1);
    base[2 * kLanes] = static_cast<std::uint16_t>(c.y0);
    base[3 * kLanes] = static_cast<std::uint16_t>(c.y1);
    inv_sqrt_area_[(block * k + j) * kLanes + lane] =
        static_cast<float>(1.0 / std::sqrt(static_cast<double>(c.area())));
    bound[0] = std::min(bound[0], base[0]);
    bound[1] = std::max(bound[1], base[kLanes]);
    bound[2] = std::min(bound[2], base[2 * kLanes]);
    bound[3] = std::max(bound[3], base[3 * kLanes]);
  }
  map_index_[block * kLanes + lane] = static_cast<std::uint32_t>(index);
  ++num_stored_;
}

std::size_t DescriptorDatabase::memory_bytes() const {
  return coords_.size() * sizeof(std::uint16_t) + inv_sqrt_area_.size() * sizeof(float) +
         bounds_.size() * sizeof(std::uint16_t) + map_index_.size() * sizeof(std::uint32_t);
}

std::vector<float> DescriptorDatabase::score_all(const MapDescriptor& query, Matcher matcher,
                                                 const ScoreOptions& options) const {
  if (options.num_threads < 0) throw InputError("score_all: num_threads must be >= 0");
  const QueryBoxes q = prepare_query(query, matcher, config_.resolution);
  std::vector<float> scores(num_maps_, 0.0f);
  const std::size_t blocks = map_index_.size() / kLanes;
  const bool use_max = matcher == Matcher::kMaxMax;
  const int threads = options.num_threads == 0 ? omp_get_max_threads() : options.num_threads;
  auto run = [&](std::size_t begin, std::size_t end) {
    score_blocks(coords_.data(), inv_sqrt_area_.data(), bounds_.data(), map_index_.data(), begin, end,
                 config_.parts_per_map, q, use_max, scores.data());
  };
  if (threads <= 1 || blocks < 2) {
    run(0, blocks);
    return scores;
  }
#pragma omp parallel num_threads(threads)
  {
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t nt = static_cast<std::size_t>(omp_get_num_threads());
    run(blocks * t / nt, blocks * (t + 1) / nt);
  }
  return scores;
}

}  // namespace partslam
