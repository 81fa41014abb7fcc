// MapDatabase: dictionary maps and packed part descriptors.
#include <algorithm>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/parts/descriptor_layout.h"
#include "io/store/map_database.h"
#include "io/store/map_database_internal.h"

namespace partslam::io {
namespace {

using internal::descriptor_context;
using internal::require_finite;
using sqlite::Statement;

// bits as stored (64-bit: a database may hold any integer) against the blob's size.
void check_descriptor_size(std::int64_t bits, std::size_t bytes, const std::string& context) {
  if (bits < 0 || bits > std::numeric_limits<int>::max() - 7 || bytes != static_cast<std::size_t>((bits + 7) / 8)) {
    throw InputError(context + ": descriptor of " + std::to_string(bits) + " bits must hold " +
                     (bits < 0 || bits > std::numeric_limits<int>::max() - 7 ? std::string("a whole number of")
                                                                               : std::to_string((bits + 7) / 8)) +
                     " bytes, has " + std::to_string(bytes));
  }
}

void check_descriptor(const PackedDescriptor& d, const std::string& context) {
  check_descriptor_size(d.bits, d.bytes.size(), context);
}

void check_fits_codec(const PackedDescriptor& d, int k, const CodecConfig& codec, const std::string& context) {
  const int per_part = bits_per_part(codec);
  if (d.bits % per_part != 0 || d.bits / per_part > k) {
    throw InputError(context + ": " + std::to_string(d.bits) + " bits are not a whole number of parts (at most K = " +
                     std::to_string(k) + ") of " + std::to_string(per_part) + " bits under the set's codec");
  }
}

// A codec as stored: a JSON object with every field of CodecConfig (numbers round-trip exactly).
std::string codec_json(const CodecConfig& c) {
  const Box2& e = c.dictionary_extent;
  nlohmann::json j = {{"crop_size", c.crop_size},
                      {"keypoint_resolution", c.keypoint_resolution},
                      {"keypoint_bits", c.keypoint_bits},
                      {"dictionary_extent", {e.x_min, e.x_max, e.y_min, e.y_max}},
                      {"origin_bits_x", c.origin_bits_x},
                      {"origin_bits_y", c.origin_bits_y},
                      {"rotation_bits", c.rotation_bits},
                      {"score_bits", c.score_bits},
                      {"score_max", c.score_max}};
  return j.dump();
}

CodecConfig parse_codec_json(const std::string& text, const std::string& context) {
  const auto j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object()) throw InputError(context + ": codec is not a JSON object (corrupt database)");
  auto field = [&](const char* name) -> const nlohmann::json& {
    if (!j.contains(name)) throw InputError(context + ": codec field '" + name + "' is missing (corrupt database)");
    return j.at(name);
  };
  auto number = [&](const char* name) {
    const nlohmann::json& v = field(name);
    if (!v.is_number()) throw InputError(context + ": codec field '" + name + "' is not a number (corrupt database)");
    return v.get<double>();
  };
  auto integer = [&](const char* name) {
    const nlohmann::json& v = field(name);
    if (!v.is_number_integer() || v.get<std::int64_t>() < 0 || v.get<std::int64_t>() > 64)
      throw InputError(context + ": codec field '" + name + "' is not an integer in [0, 64] (corrupt database)");
    return static_cast<int>(v.get<std::int64_t>());
  };
  CodecConfig c;
  c.crop_size = number("crop_size");
  c.keypoint_resolution = number("keypoint_resolution");
  c.keypoint_bits = integer("keypoint_bits");
  const nlohmann::json& e = field("dictionary_extent");
  if (!e.is_array() || e.size() != 4 || !std::all_of(e.begin(), e.end(), [](const auto& v) { return v.is_number(); }))
    throw InputError(context + ": codec field 'dictionary_extent' is not 4 numbers (corrupt database)");
  c.dictionary_extent = {e[0].get<double>(), e[1].get<double>(), e[2].get<double>(), e[3].get<double>()};
  c.origin_bits_x = integer("origin_bits_x");
  c.origin_bits_y = integer("origin_bits_y");
  c.rotation_bits = integer("rotation_bits");
  c.score_bits = integer("score_bits");
  c.score_max = number("score_max");
  try {
    validate(c);
  } catch (const InputError& err) {
    throw InputError(context + ": " + err.what() + " (corrupt database)");
  }
  return c;
}

std::string set_context(const std::string& file, const std::string& dictionary, int k) {
  return file + ": descriptors of dictionary '" + dictionary + "', K=" + std::to_string(k);
}

Points2 stored_dictionary_points(const sqlite::Connection& db, const std::string& dictionary) {
  Statement q(db, "SELECT point_count, points FROM dictionaries WHERE name = ?1");
  if (!q.bind_text(1, dictionary).step()) return {};
  const std::string context = db.path().string() + ": dictionary '" + dictionary + "'";
  if (q.int64(0) < 0) throw InputError(context + ": negative point count (corrupt database)");
  Points2 points = decode_points_f32(q.blob(1), static_cast<std::size_t>(q.int64(0)), context);
  internal::require_plausible(points, context);
  return points;
}

PackedDescriptor read_descriptor(const Statement& q, int bits_column, const std::string& context) {
  const std::int64_t bits = q.int64(bits_column);
  const auto blob = q.blob(bits_column + 1);
  try {  // before narrowing bits to int (fuzz_map_database_values: 2^31 - 1 bits overflowed bits + 7)
    check_descriptor_size(bits, blob.size(), context);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + " (corrupt database)");
  }
  PackedDescriptor d;
  d.bits = static_cast<int>(bits);
  d.bytes.assign(blob.begin(), blob.end());
  return d;
}

}  // namespace

std::int64_t MapDatabase::add_dictionary(const Dictionary& d) {
  require_writable();
  internal::require_name(d.name, "dictionary");
  const std::string context = "dictionary '" + d.name + "'";
  if (!(d.resolution > 0.0) || !std::isfinite(d.resolution)) {
    throw InputError(context + ": resolution must be a positive finite number");
  }
  require_finite(d.alignment_angle, context, "alignment_angle");
  require_finite(d.T_world_dict.x, context, "T_world_dict.x");
  require_finite(d.T_world_dict.y, context, "T_world_dict.y");
  require_finite(d.T_world_dict.theta, context, "T_world_dict.theta");
  const auto metadata = nlohmann::json::parse(d.metadata, nullptr, /*allow_exceptions=*/false);
  if (!metadata.is_object())
    throw InputError(context + ": metadata must be a JSON object, got '" + d.metadata + "'");
  Statement exists(impl_->db, "SELECT id FROM dictionaries WHERE name = ?1");
  if (exists.bind_text(1, d.name).step()) {
    throw InputError(path().string() + ": a dictionary named '" + d.name + "' already exists");
  }
  Statement insert(impl_->db,
                   "INSERT INTO dictionaries (name, source, resolution, alignment_angle, world_x, world_y,"
                   " world_theta, point_count, points, metadata, created) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7,"
                   " ?8, ?9, ?10, strftime('%Y-%m-%dT%H:%M:%SZ', 'now')) RETURNING id");
  insert.bind_text(1, d.name)
      .bind_text(2, d.source)
      .bind_real(3, d.resolution)
      .bind_real(4, d.alignment_angle);
  insert.bind_real(5, d.T_world_dict.x).bind_real(6, d.T_world_dict.y).bind_real(7, d.T_world_dict.theta);
  insert.bind_int(8, static_cast<std::int64_t>(d.points.size()));
  insert.bind_blob(9, encode_points_f32(d.points, context)).bind_text(10, metadata.dump());
  insert.step();
  const std::int64_t id = insert.int64(0);
  insert.run();
  return id;
}

Dictionary MapDatabase::load_dictionary(const std::string& name) const {
  Statement q(
      impl_->db,
      "SELECT source, resolution, alignment_angle, world_x, world_y, world_theta, point_count, points,"
      " metadata FROM dictionaries WHERE name = ?1");
  if (!q.bind_text(1, name).step()) {
    throw InputError(path().string() + ": no dictionary named '" + name + "'");
  }
  const std::string context = path().string() + ": dictionary '" + name + "'";
  Dictionary d;
  d.name = name;
  d.source = q.text(0);
  d.resolution = q.real(1);
  d.alignment_angle = q.real(2);
  d.T_world_dict = Pose2{q.real(3), q.real(4), q.real(5)};
  const std::int64_t count = q.int64(6);
  if (count < 0) throw InputError(context + ": negative point count (corrupt database)");
  d.points = decode_points_f32(q.blob(7), static_cast<std::size_t>(count), context);
  internal::require_plausible(d.points, context);
  d.metadata = q.text(8);
  return d;
}

std::vector<DictionaryInfo> MapDatabase::dictionaries() const {
  Statement q(impl_->db,
              "SELECT id, name, source, resolution, point_count, created FROM dictionaries ORDER BY id");
  std::vector<DictionaryInfo> out;
  while (q.step()) out.push_back({q.int64(0), q.text(1), q.text(2), q.real(3), q.int64(4), q.text(5)});
  return out;
}

void MapDatabase::remove_dictionary(const std::string& name) {
  require_writable();
  Statement remove(impl_->db, "DELETE FROM dictionaries WHERE name = ?1 RETURNING id");
  if (!remove.bind_text(1, name).step()) {
    throw InputError(path().string() + ": no dictionary named '" + name + "'");
  }
  remove.run();
}

void MapDatabase::put_descriptor(std::int64_t map_id, const std::string& dictionary, int k,
                                 const CodecConfig& codec, const PackedDescriptor& d) {
  put_descriptors(dictionary, k, codec, {{map_id, d}});
}

void MapDatabase::put_descriptors(const std::string& dictionary, int k, const CodecConfig& codec,
                                  const std::vector<DescriptorRecord>& records) {
  internal::require_name(dictionary, "descriptor dictionary");
  if (k < 1) throw InputError("descriptor K must be >= 1, got " + std::to_string(k));
  const std::string set = set_context(path().string(), dictionary, k);
  try {
    validate(codec);
  } catch (const InputError& e) {
    throw InputError(set + ": " + e.what());
  }
  Transaction transaction(*this);
  const std::string stored_codec = codec_json(codec);
  Statement old_codec(impl_->db, "SELECT codec FROM descriptor_codecs WHERE dictionary = ?1 AND k = ?2");
  if (old_codec.bind_text(1, dictionary).bind_int(2, k).step() && old_codec.text(0) != stored_codec) {
    Statement drop(impl_->db, "DELETE FROM descriptors WHERE dictionary = ?1 AND k = ?2");
    drop.bind_text(1, dictionary).bind_int(2, k).run();
  }
  Statement put_codec(impl_->db,
                      "INSERT OR REPLACE INTO descriptor_codecs (dictionary, k, codec) VALUES (?1, ?2, ?3)");
  put_codec.bind_text(1, dictionary).bind_int(2, k).bind_text(3, stored_codec).run();
  Statement exists(impl_->db, "SELECT 1 FROM submaps WHERE id = ?1");
  // An upsert, not INSERT OR REPLACE: the replaced row is updated, so the count triggers see a change of bits.
  Statement insert(impl_->db,
                   "INSERT INTO descriptors (dictionary, k, map_id, bits, data) VALUES (?1, ?2, ?3, ?4, ?5)"
                   " ON CONFLICT (dictionary, k, map_id) DO UPDATE SET bits = excluded.bits, data = excluded.data");
  for (const DescriptorRecord& r : records) {
    const std::string context = descriptor_context(path().string(), r.map_id, dictionary, k);
    check_descriptor(r.descriptor, context);
    check_fits_codec(r.descriptor, k, codec, context);
    exists.reset();
    if (!exists.bind_int(1, r.map_id).step()) throw InputError(context + ": no map with this id");
    insert.reset();
    insert.bind_text(1, dictionary).bind_int(2, k).bind_int(3, r.map_id).bind_int(4, r.descriptor.bits);
    insert.bind_blob(5, r.descriptor.bytes).run();
  }
  transaction.commit();
}

std::optional<PackedDescriptor> MapDatabase::get_descriptor(std::int64_t map_id,
                                                            const std::string& dictionary, int k) const {
  Statement q(impl_->db,
              "SELECT bits, data FROM descriptors WHERE dictionary = ?1 AND k = ?2 AND map_id = ?3");
  if (!q.bind_text(1, dictionary).bind_int(2, k).bind_int(3, map_id).step()) return std::nullopt;
  return read_descriptor(q, 0, descriptor_context(path().string(), map_id, dictionary, k));
}

std::optional<CodecConfig> MapDatabase::descriptor_codec(const std::string& dictionary, int k) const {
  Statement any(impl_->db, "SELECT 1 FROM descriptors WHERE dictionary = ?1 AND k = ?2 LIMIT 1");
  if (!any.bind_text(1, dictionary).bind_int(2, k).step()) return std::nullopt;
  const std::string context = set_context(path().string(), dictionary, k);
  if (impl_->schema_version < 2) {  // read-only version 1 file: the codec version 1 implied
    const Points2 points = stored_dictionary_points(impl_->db, dictionary);
    if (points.empty()) {
      throw InputError(context + ": stored by schema version 1 without their codec, and the dictionary's points "
                       "that implied it are gone");
    }
    return descriptor_codec_config_v1(points, k);
  }
  Statement q(impl_->db, "SELECT codec FROM descriptor_codecs WHERE dictionary = ?1 AND k = ?2");
  if (!q.bind_text(1, dictionary).bind_int(2, k).step())
    throw InputError(context + ": no codec stored for them (corrupt database)");
  return parse_codec_json(q.text(0), context);
}

std::vector<DescriptorRecord> MapDatabase::load_descriptors(const std::string& dictionary, int k) const {
  std::vector<DescriptorRecord> out;
  scan_descriptors(dictionary, k, [&out](std::int64_t map_id, const PackedDescriptor& d) { out.push_back({map_id, d}); });
  return out;
}

void MapDatabase::scan_descriptors(const std::string& dictionary, int k,
                                   const std::function<void(std::int64_t, const PackedDescriptor&)>& visit) const {
  Statement q(impl_->db,
              "SELECT map_id, bits, data FROM descriptors WHERE dictionary = ?1 AND k = ?2 ORDER BY map_id");
  q.bind_text(1, dictionary).bind_int(2, k);
  PackedDescriptor d;
  while (q.step()) {
    const std::int64_t map_id = q.int64(0);
    const std::int64_t bits = q.int64(1);
    const auto blob = q.blob(2);
    if (bits < 0 || bits > std::numeric_limits<int>::max() - 7 || blob.size() != static_cast<std::size_t>((bits + 7) / 8))
      d = read_descriptor(q, 1, descriptor_context(path().string(), map_id, dictionary, k));  // throws, naming it
    d.bits = static_cast<int>(bits);
    d.bytes.assign(blob.begin(), blob.end());
    visit(map_id, d);
  }
}

namespace internal {

void migrate_to_current(sqlite::Connection& db) {
  db.exec("BEGIN IMMEDIATE");
  std::int64_t version = 0;
  try {
    version = db.query_int("PRAGMA user_version");  // another process may have migrated it meanwhile
    if (version == 1) {
      db.exec(kCodecsTable);
      Statement sets(db, "SELECT DISTINCT dictionary, k FROM descriptors ORDER BY dictionary, k");
      Statement insert(db, "INSERT INTO descriptor_codecs (dictionary, k, codec) VALUES (?1, ?2, ?3)");
      while (sets.step()) {
        const std::string dictionary = sets.text(0);
        const int k = static_cast<int>(sets.int64(1));
        const Points2 points = stored_dictionary_points(db, dictionary);
        if (points.empty() || k < 1) continue;  // undecodable under version 1 already; left without a codec
        insert.reset();
        insert.bind_text(1, dictionary).bind_int(2, k).bind_text(3, codec_json(descriptor_codec_config_v1(points, k)));
        insert.run();
      }
    }
    if (version == 1 || version == 2) {  // version 3: counts kept by triggers, filled once here
      db.exec(kCountsSchema);
      db.exec(kFillCounts);
    }
    if (version >= 1 && version <= 3) {  // version 4: the laser origins, none for the maps already stored
      db.exec("ALTER TABLE submaps ADD COLUMN origins BLOB NOT NULL DEFAULT x''");
      db.exec("PRAGMA user_version = " + std::to_string(kMapDatabaseSchemaVersion));
    }
    db.exec("COMMIT");
  } catch (const InputError& e) {
    if (db.in_transaction()) db.exec("ROLLBACK");
    throw InputError(db.path().string() + ": cannot migrate the database from schema version " +
                     std::to_string(version) + ": " + e.what());
  }
}

}  // namespace internal

}  // namespace partslam::io
