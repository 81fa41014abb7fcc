#include "io/descriptor_store.h"

#include "core/error.h"
#include "core/parts/descriptor_layout.h"
#include "io/map_database_internal.h"

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

std::string describe_hint(const MapDatabase& db, const std::string& dictionary, int k) {
  return "run 'partslam describe " + db.path().string() + " --dict " + dictionary +
         (k > kMaxUnscoredParts ? " --parts " : " --k ") + std::to_string(k) + "' first";
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

}  // namespace partslam::io
