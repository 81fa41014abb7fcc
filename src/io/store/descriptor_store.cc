#include "io/store/descriptor_store.h"

#include <algorithm>
#include <set>

#include "core/error.h"
#include "core/timing.h"
#include "core/parts/descriptor_layout.h"
#include "io/store/map_database_internal.h"

namespace partslam::io {

Dictionary resolve_dictionary(const MapDatabase& db, const std::string& name) {
  if (!name.empty()) return db.load_dictionary(name);
  const std::vector<DictionaryInfo> all = db.dictionaries();
  if (all.empty()) {
    throw InputError(db.path().string() + ": no dictionary stored (MapDatabase::add_dictionary stores one)");
  }
  if (all.size() > 1) {
    std::string names;
    for (const DictionaryInfo& d : all) names += (names.empty() ? "" : ", ") + d.name;
    throw InputError(db.path().string() + ": several dictionaries (" + names + "): name the one to use");
  }
  return db.load_dictionary(all.front().name);
}

std::string describe_hint(const std::string& dictionary, int k) {
  return "describe the maps against dictionary '" + dictionary + "' with " +
         (k > kMaxUnscoredParts ? "P = " : "K = ") + std::to_string(k) + " first";
}

namespace {

MapDescriptor decode_record(const MapDatabase& db, const std::string& dictionary, int k, std::int64_t map_id,
                            const PackedDescriptor& packed, const CodecConfig& codec) {
  try {
    return decode_stored(packed, k, codec);
  } catch (const InputError& e) {
    throw InputError(internal::descriptor_context(db.path().string(), map_id, dictionary, k) + ": " + e.what());
  }
}

}  // namespace

std::map<std::int64_t, MapDescriptor> load_descriptor_set(const MapDatabase& db, const std::string& dictionary,
                                                          int k) {
  std::map<std::int64_t, MapDescriptor> out;
  const std::optional<CodecConfig> codec = db.descriptor_codec(dictionary, k);
  if (!codec) return out;
  for (const DescriptorRecord& r : db.load_descriptors(dictionary, k))
    out.emplace(r.map_id, decode_record(db, dictionary, k, r.map_id, r.descriptor, *codec));
  return out;
}

LoadedDescriptors load_descriptor_database(const MapDatabase& db, const std::string& dictionary, int k,
                                           const DescriptorDatabaseConfig& config) {
  if (config.parts_per_map < k) {
    throw InputError("load_descriptor_database: parts_per_map " + std::to_string(config.parts_per_map) +
                     " is below K = " + std::to_string(k));
  }
  LoadedDescriptors out{DescriptorDatabase(config), {}};
  const std::optional<CodecConfig> codec = db.descriptor_codec(dictionary, k);
  if (!codec) return out;
  // Rows packed side by side, stride bytes each (a shorter descriptor is padded; bits says how much is used).
  const std::size_t stride = (static_cast<std::size_t>(packed_bits(k, *codec)) + 7) / 8;
  std::vector<std::uint8_t> packed;
  std::vector<std::int32_t> bits;
  db.scan_descriptors(dictionary, k, [&](std::int64_t map_id, const PackedDescriptor& d) {
    if (d.bytes.size() > stride) {  // more parts than K: decode_stored names the problem
      decode_record(db, dictionary, k, map_id, d, *codec);
    }
    out.map_ids.push_back(map_id);
    bits.push_back(d.bits);
    packed.insert(packed.end(), d.bytes.begin(), d.bytes.end());
    packed.resize(out.map_ids.size() * stride, 0);
  });
  PackedDescriptor row;
  out.database = DescriptorDatabase(
      out.map_ids.size(),
      [&](std::size_t i, MapDescriptor& scratch) -> const MapDescriptor& {
        const auto first = packed.begin() + static_cast<std::ptrdiff_t>(i * stride);
        row.bits = bits[i];
        row.bytes.assign(first, first + static_cast<std::ptrdiff_t>((bits[i] + 7) / 8));
        scratch = decode_record(db, dictionary, k, out.map_ids[i], row, *codec);
        return scratch;
      },
      config);
  return out;
}

std::optional<MapDescriptor> load_descriptor(const MapDatabase& db, const std::string& dictionary, int k,
                                             std::int64_t map_id) {
  const std::optional<PackedDescriptor> packed = db.get_descriptor(map_id, dictionary, k);
  if (!packed) return std::nullopt;
  return decode_record(db, dictionary, k, map_id, *packed, *db.descriptor_codec(dictionary, k));
}

int query_list_parts(const MapDatabase& db, const std::string& dictionary, std::int64_t map_id) {
  int best = 0;
  for (const DescriptorSetInfo& s : db.descriptor_sets()) {
    if (s.dictionary == dictionary && s.k > kMaxUnscoredParts && s.k > best &&
        db.get_descriptor(map_id, dictionary, s.k))
      best = s.k;
  }
  return best;
}

std::vector<EncodedSet> encode_descriptor_sets(const Points2& dictionary_points, const std::vector<int>& ks,
                                               std::span<const std::int64_t> ids,
                                               std::span<const std::vector<Part>> parts) {
  if (ids.size() != parts.size())
    throw InputError("encode descriptors: " + std::to_string(ids.size()) + " maps but " +
                     std::to_string(parts.size()) + " part lists");
  std::vector<EncodedSet> sets;
  for (int k : ks) {
    EncodedSet set;
    set.k = k;
    set.codec = descriptor_codec_config(dictionary_points, k);
    double bits = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      try {
        set.records.push_back({ids[i], encode(select_top_parts(parts[i], k), set.codec)});
      } catch (const InputError& e) {
        throw InputError("map " + std::to_string(ids[i]) + ", K=" + std::to_string(k) + ": " + e.what());
      }
      const int b = set.records.back().descriptor.bits;
      set.min_bits = i == 0 ? b : std::min(set.min_bits, b);
      set.max_bits = i == 0 ? b : std::max(set.max_bits, b);
      bits += b;
    }
    set.mean_bits = ids.empty() ? 0.0 : bits / static_cast<double>(ids.size());
    sets.push_back(std::move(set));
  }
  return sets;
}

void store_descriptor_sets(MapDatabase& db, const std::string& dictionary, const std::vector<EncodedSet>& sets) {
  MapDatabase::Transaction transaction(db);
  for (const EncodedSet& set : sets) db.put_descriptors(dictionary, set.k, set.codec, set.records);
  transaction.commit();
}

std::string resolve_descriptor_dictionary(const MapDatabase& db, const std::string& name) {
  std::set<std::string> names;
  for (const DescriptorSetInfo& s : db.descriptor_sets()) names.insert(s.dictionary);
  if (!name.empty()) {
    if (!names.count(name)) db.load_dictionary(name);  // throws "no dictionary named ..." when it is unknown
    return name;
  }
  if (names.empty()) {
    throw InputError(db.path().string() + ": no descriptors stored: describe the maps against a dictionary first");
  }
  if (names.size() > 1) throw InputError(db.path().string() + ": descriptors of several dictionaries: choose one");
  return *names.begin();
}

RankingParts load_ranking_parts(const MapDatabase& db, const std::string& dictionary, const MethodTraits& traits,
                                std::span<const std::int64_t> candidates, std::int64_t query, int query_parts) {
  const int k = traits.parts;
  const auto t0 = Clock::now();
  std::map<std::int64_t, MapDescriptor> stored = load_descriptor_set(db, dictionary, k);
  RankingParts out;
  std::size_t missing = 0;
  for (std::int64_t id : candidates) {
    auto it = stored.find(id);
    if (it == stored.end()) {
      ++missing;
    } else {
      out.stored.push_back(std::move(it->second.parts));
    }
  }
  if (missing > 0) {
    throw InputError(std::to_string(missing) + " of " + std::to_string(candidates.size()) + " maps have no K=" +
                     std::to_string(k) + " descriptor for dictionary '" + dictionary +
                     "': " + describe_hint(dictionary, k));
  }
  out.query_k = traits.query_parts == QueryParts::kDescriptor ? k
                : query_parts > 0                              ? query_parts
                                                               : query_list_parts(db, dictionary, query);
  if (out.query_k == 0) {
    throw InputError("map " + std::to_string(query) + " has no hMM query list (a descriptor of more than " +
                     std::to_string(kMaxUnscoredParts) + " parts) for dictionary '" + dictionary +
                     "': describe the maps against it first (the P-part list is stored as K = P when P > " +
                     std::to_string(kMaxUnscoredParts) + "), or name a stored list (query_parts)");
  }
  std::optional<MapDescriptor> descriptor = load_descriptor(db, dictionary, out.query_k, query);
  if (!descriptor) {
    throw InputError("the query map " + std::to_string(query) + " has no K=" + std::to_string(out.query_k) +
                     " descriptor for dictionary '" + dictionary + "': " + describe_hint(dictionary, out.query_k));
  }
  out.query = std::move(descriptor->parts);
  out.ms = ms_since(t0);
  return out;
}

}  // namespace partslam::io
