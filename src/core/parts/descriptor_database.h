// Whole-database descriptor matching (paper §"Descriptor Matcher" and §"Time Efficiency"; docs/DESIGN.md "DM"):
// one query descriptor against every stored map, with the definitions of descriptor_matcher.h (Eqs. 3-6).
//
// Layout: descriptor boxes are snapped to a grid (0.1 m by default) and stored as unsigned 16-bit cell
// coordinates in blocks of 16 maps; within a block, slot j (the j-th part of each map) keeps x0[16], x1[16],
// y0[16], y1[16], the part's dictionary origin ox[16], oy[16] (half cells, for the origin gate) and the
// precomputed 1/sqrt(area)[16], so one AVX2 register holds one field of 16 maps and
// nothing is allocated per map. Per block, the union of its boxes and the range of its parts' dictionary origins
// are kept: a query part that misses the union, or (origin gate on) whose origin lies farther than the gate from
// the range, adds exactly 0 to every map of the block and is skipped (tested per super block of 16 blocks, then
// per block; maps of a skipped block are never read). Storing maps in Morton order of their descriptor centre
// (the parts of one map overlap, the paper's GC criterion) makes these block boxes tight.
// Per pair of boxes the kernel does min / max / saturating subtraction on 16-bit lanes, one 16-bit product
// (box sides are limited to 255 cells so the area fits), one conversion and one multiply-max in float:
//   max_j f_RS(Bl_i, Bg_j) = (1 / sqrt(area(Bl_i))) * max_j area(Bl_i ∩ Bg_j) / sqrt(area(Bg_j)).
// Results equal match_score() on the snapped boxes up to float rounding (relative ~1e-6). Serial and
// parallel runs, sorted and unsorted layouts, and the AVX2 and baseline builds of the kernel (chosen at load
// time) all give bit-identical results. score_all is const and may be called concurrently.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/parts/descriptor_matcher.h"
#include "core/parts/part_codec.h"

namespace partslam {

struct DescriptorDatabaseConfig {
  int parts_per_map = 3;      ///< K: part slots per stored map; maps with fewer parts leave slots empty
  double resolution = kMapResolution;  ///< grid of the stored box coordinates [m]; boxes span at most 255 cells
  bool spatial_order = true;  ///< bulk construction stores maps in Morton order of their descriptor centre
};

/// Throws InputError naming the offending field when a value is out of range.
void validate(const DescriptorDatabaseConfig& config);

struct ScoreOptions {
  int num_threads = 1;  ///< OpenMP threads; 1 = serial, 0 = OpenMP's default. Results do not depend on it.
  double origin_gate = 0.0;  ///< descriptor_matcher.h's origin gate [m]; 0 = off (the paper). Origins are
                             ///< compared on the half-cell grid.
};

/// How the part methods (iMM, hMM and a rerank over them) read parts when they rank.
struct PartsConfig {
  /// Storage of part descriptors: when set, stored maps' (and iMM queries') top-K parts are encoded and decoded
  /// through it, so ranking sees what a database would hold; unset: the parts given are already the stored ones.
  std::optional<CodecConfig> codec;
  int hmm_query_parts = 100;                ///< parts of an hMM query (its best ones)
  double origin_gate = kDefaultOriginGate;  ///< the descriptor matcher's origin gate [m]; 0 = the paper
};

/// Throws InputError naming the offending field.
void validate(const PartsConfig& config);

class DescriptorDatabase {
 public:
  static constexpr int kLanes = 16;                   ///< maps per block
  static constexpr std::size_t kBlocksPerSuper = 16;  ///< blocks per super block (two-level pruning)

  explicit DescriptorDatabase(const DescriptorDatabaseConfig& config = {});
  /// Bulk construction; map i keeps index i (its position in score_all's result) whatever the storage order.
  DescriptorDatabase(const std::vector<MapDescriptor>& maps, const DescriptorDatabaseConfig& config = {});
  /// The same from a source of maps, for callers that keep them in another form (e.g. packed, as a map database
  /// stores them: io::load_descriptor_database): map_at(i, scratch) returns map i, in scratch or elsewhere, for
  /// 0 <= i < num_maps. It is called twice per map (once for the storage order, once to store it); exceptions
  /// it throws pass through. The result equals the vector constructor's on the same maps.
  using MapSource = std::function<const MapDescriptor&(std::size_t, MapDescriptor&)>;
  DescriptorDatabase(std::size_t num_maps, const MapSource& map_at, const DescriptorDatabaseConfig& config = {});

  /// Appends one map (in storage order, after the bulk-built ones) and returns its index. Throws InputError
  /// for more than parts_per_map parts, a non-finite box, a box outside the grid's +-32768-cell range, or a
  /// box wider or taller than 255 cells. Boxes that snap to zero area are kept as empty slots (score 0).
  std::size_t add(const MapDescriptor& map);

  std::size_t size() const { return num_maps_; }
  const DescriptorDatabaseConfig& config() const { return config_; }
  /// Bytes held by the layout (boxes, inverse roots, block boxes, index map).
  std::size_t memory_bytes() const;

  /// Scores the query against every stored map: result[i] is the score of map i (Eqs. 4-6).
  std::vector<float> score_all(const MapDescriptor& query, Matcher matcher,
                               const ScoreOptions& options = {}) const;
  /// The same into `scores` (resized to size()), reusing its memory: at 10 M maps a new result is 40 MB of fresh
  /// pages for every query, faulted in one by one by the scattered writes (docs/NOTES.md, "A large database on
  /// disk").
  void score_all(const MapDescriptor& query, Matcher matcher, const ScoreOptions& options,
                 std::vector<float>& scores) const;

 private:
  void append(const MapDescriptor& map, std::size_t index);

  DescriptorDatabaseConfig config_;
  std::size_t num_maps_ = 0;
  std::size_t num_stored_ = 0;               // lanes filled, including maps in storage order
  std::vector<std::uint16_t> coords_;        // [block][slot][x0, x1, y0, y1][lane]
  std::vector<std::uint16_t> origins_;       // [block][slot][ox, oy][lane]: dictionary origin [half cells]
  std::vector<float> inv_sqrt_area_;         // [block][slot][lane]; 0 for an empty slot
  std::vector<std::uint16_t> bounds_;        // [block][x0, x1, y0, y1, ox0, ox1, oy0, oy1]: union of the
                                             // block's boxes, range of its parts' dictionary origins
  std::vector<std::uint16_t> super_bounds_;  // [super block][the same fields]: over its blocks
  std::vector<std::uint32_t> map_index_;     // [block * kLanes + lane] -> map index; UINT32_MAX for padding
};

}  // namespace partslam
