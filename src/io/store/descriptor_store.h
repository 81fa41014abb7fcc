// The stored descriptors of one dictionary, decoded with the codec stored with their set (schema version 2);
// what `partslam match` and `render` read.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/parts/descriptor_database.h"
#include "core/parts/part.h"
#include "core/ranking/method_spec.h"
#include "io/store/map_database.h"

namespace partslam::io {

/// The dictionary named, or when name is empty the only dictionary of the database; throws InputError naming
/// what is missing or ambiguous.
Dictionary resolve_dictionary(const MapDatabase& db, const std::string& name);

/// "describe the maps against dictionary 'NAME' with K = k first": how to produce a missing descriptor set.
std::string describe_hint(const std::string& dictionary, int k);

/// Every stored descriptor of (dictionary, K), decoded, by map id.
std::map<std::int64_t, MapDescriptor> load_descriptor_set(const MapDatabase& db,
                                                          const std::string& dictionary, int k);

/// A descriptor set loaded straight into the in-memory matcher: database's map i is the stored map map_ids[i].
struct LoadedDescriptors {
  DescriptorDatabase database;
  std::vector<std::int64_t> map_ids;  ///< increasing
};

/// Every stored descriptor of (dictionary, K) in a DescriptorDatabase, without load_descriptor_set's per-map
/// objects: the rows are kept packed (ceil(K * bits per part / 8) bytes each) and decoded as the matcher is
/// built. Same maps, same scores as DescriptorDatabase(load_descriptor_set(...) in map id order, config).
/// config.parts_per_map must be >= K. Empty when the set has no descriptor; errors name the file and the map.
LoadedDescriptors load_descriptor_database(const MapDatabase& db, const std::string& dictionary, int k,
                                           const DescriptorDatabaseConfig& config);

/// One map's stored descriptor of (dictionary, K), decoded; nullopt when there is none.
std::optional<MapDescriptor> load_descriptor(const MapDatabase& db, const std::string& dictionary, int k,
                                             std::int64_t map_id);

/// K of the longest hMM query list (K > kMaxUnscoredParts, appearance scores stored) kept for the dictionary
/// that holds map_id; 0 when there is none.
int query_list_parts(const MapDatabase& db, const std::string& dictionary, std::int64_t map_id);

/// The descriptors of one K for every described map, packed with the set's codec (what `describe` stores).
struct EncodedSet {
  int k = 0;
  CodecConfig codec;
  std::vector<DescriptorRecord> records;
  int min_bits = 0, max_bits = 0;  ///< over the records
  double mean_bits = 0;
};

/// Each K's descriptor set: for every map (ids[i] with parts[i], best first) its top-K parts, encoded with the
/// codec of (dictionary_points, K). Throws InputError naming the map and K a part cannot be encoded for.
std::vector<EncodedSet> encode_descriptor_sets(const Points2& dictionary_points, const std::vector<int>& ks,
                                               std::span<const std::int64_t> ids,
                                               std::span<const std::vector<Part>> parts);

/// Stores the sets under the dictionary's name in one transaction (all or none).
void store_descriptor_sets(MapDatabase& db, const std::string& dictionary, const std::vector<EncodedSet>& sets);

/// The dictionary whose descriptors to read: the one named (which must have descriptors or be stored), else
/// the only one with descriptors; throws InputError saying what to run or choose.
std::string resolve_descriptor_dictionary(const MapDatabase& db, const std::string& name);

/// What a part method (MethodTraits::needs_parts) reads of a database for one query.
struct RankingParts {
  std::vector<std::vector<Part>> stored;  ///< each candidate's K-part descriptor, in the candidates' order
  std::vector<Part> query;                ///< the query's parts (MethodTraits::query_parts)
  int query_k = 0;                        ///< K of the query's stored descriptor
  double ms = 0;                          ///< reading them [ms]
};

/// Every candidate's K-part descriptor (K = traits.parts) and the query's: its K-part descriptor (iMM) or its
/// stored part list (hMM: K = query_parts when > 0, else the longest list kept). Throws InputError naming what
/// is missing and how to produce it.
RankingParts load_ranking_parts(const MapDatabase& db, const std::string& dictionary, const MethodTraits& traits,
                                std::span<const std::int64_t> candidates, std::int64_t query, int query_parts);

}  // namespace partslam::io
