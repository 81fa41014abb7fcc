// The map database: one SQLite file holding datasets of submaps, dictionary maps and packed part
// descriptors (docs/DESIGN.md, data flow "... ──► packed descriptor ──► map database").
//
// Schema (version 4; PRAGMA application_id = 0x50534C4D "PSLM", PRAGMA user_version = 4; STRICT tables):
//   datasets     (id, name UNIQUE, source, kind 'submaps'|'dictionary', config JSON of SubmapConfig and
//                 scan_matched, created)
//   submaps      (id = global map id, dataset_id, idx within dataset, anchor_scan, anchor_timestamp, travel,
//                 alignment_angle, world_x/world_y/world_theta = T_world_map, point_count, points BLOB,
//                 scan_timestamps BLOB, origins BLOB = Submap::origins, the laser positions (version 4; the
//                 verified dMM casts free space from them))
//   dictionaries (id, name UNIQUE, source, resolution, alignment_angle, world_x/y/theta, point_count,
//                 points BLOB, metadata JSON, created)
//   descriptors  (dictionary, k, map_id, bits, data BLOB), primary key (dictionary, k, map_id)
//   descriptor_codecs (dictionary, k, codec JSON of CodecConfig), primary key (dictionary, k): how the
//                 descriptors of a set are packed, so they decode without the dictionary (version 2)
//   dataset_counts (dataset_id, submaps, points), descriptor_counts (dictionary, k, maps, bits): counts kept by
//                 triggers in the same transaction as every insert, update and delete, cascades included
//                 (version 3), so datasets(), descriptor_sets() and summary() read a few rows at any size
// Blobs are little-endian (io/store/blob_codec.h): points are float32 pairs (< 0.4 um rounding in a submap),
// timestamps float64. Every other number is stored exactly. Map ids are never reused (AUTOINCREMENT).
//
// Crash safety: a new file is built (schema and header) at a temporary sibling (".NAME.new-RANDOM", flock()ed by
// its creator) and linked into place, so the path never holds a half-initialised database; a creator killed
// mid-way leaves only that temporary, which the next open of the path removes (its lock is free). Every write then
// runs in a transaction (rollback journal), so an interrupted run leaves the database as it was before the write;
// store_dataset() writes a dataset and its submaps in one transaction. Callers may group several writes in a
// Transaction. (map_database_test.cc kills writers and creators at many moments and checks all of this.)
//
// Opening checks the file: missing, not SQLite, empty, truncated, foreign (other application_id), or a
// newer schema version all throw InputError naming the file and the problem. An older file opened for writing
// is migrated to the current version in one transaction: from version 1 (no stored codecs) each descriptor set
// gets the codec version 1 implied (descriptor_codec_config_v1 of its dictionary's points); from version 1 or 2
// the counts tables are created and filled by one pass over the rows; from version 1 to 3 the origins column is
// added empty (those maps rank as bare points: no free space to verify against). Opened read-only an older file is left as
// it is: the codec is derived on read, and the counts are computed from every row (slow on a large file;
// keeps_counts() says which). SQLite errors met later
// (e.g. corruption found while reading) are InputError naming the file too.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/maps/dictionary.h"
#include "core/parts/part_codec.h"
#include "core/maps/submap.h"
#include "core/slam/front_end_config.h"

namespace partslam::io {

inline constexpr std::int32_t kMapDatabaseApplicationId = 0x50534C4D;  // "PSLM"
inline constexpr int kMapDatabaseSchemaVersion = 4;

/// What a dataset's submaps are for: maps to match, or the submaps of a dictionary log.
enum class DatasetKind { kSubmaps, kDictionary };

std::string to_string(DatasetKind kind);
/// Parses "submaps" or "dictionary"; throws InputError otherwise.
DatasetKind parse_dataset_kind(const std::string& name);

/// What the caller gives to create a dataset.
struct DatasetSpec {
  std::string name;    ///< unique within the database, non-empty
  std::string source;  ///< where the submaps came from (log path)
  DatasetKind kind = DatasetKind::kSubmaps;
  SubmapConfig config;  ///< the parameters the submaps were built with
  bool scan_matched = false;  ///< scan poses from the front end (core/slam/front_end.h), not from the log
  FrontEndConfig front_end{};  ///< its settings when scan_matched (the search window is stored)
};

/// A stored dataset with its counts.
struct DatasetInfo {
  std::int64_t id = -1;
  DatasetSpec spec;
  std::string created;  ///< UTC, ISO 8601
  std::int64_t submap_count = 0;
  double mean_points = 0.0;        ///< mean points per submap (0 when empty)
  /// Map ids of the dataset's first and last submap by index (-1 when empty): its smallest and largest map id,
  /// as ids and indices both grow as submaps are appended.
  std::int64_t first_map_id = -1;
  std::int64_t last_map_id = -1;
};

/// Where a map id lives.
struct MapLocation {
  std::int64_t map_id = -1;
  std::int64_t dataset_id = -1;
  std::string dataset_name;
  std::int64_t index = -1;  ///< position within its dataset, from 0
};

/// Dictionaries are partslam::Dictionary (core/maps/dictionary.h).
using partslam::Dictionary;

struct DictionaryInfo {
  std::int64_t id = -1;
  std::string name;
  std::string source;
  double resolution = 0.0;  ///< [m]
  std::int64_t point_count = 0;
  std::string created;  ///< UTC, ISO 8601
};

/// An opaque packed descriptor: `bits` meaningful bits in ceil(bits / 8) bytes.
/// Descriptors are stored as partslam::PackedDescriptor (core/parts/part_codec.h), an opaque blob of `bits` bits.
using partslam::PackedDescriptor;

struct DescriptorRecord {
  std::int64_t map_id = -1;
  PackedDescriptor descriptor;
};

/// Descriptors stored for one (dictionary, K).
struct DescriptorSetInfo {
  std::string dictionary;
  int k = 0;
  std::int64_t count = 0;
  double mean_bits = 0.0;
};

struct DatabaseSummary {
  int schema_version = 0;
  bool counts_kept = true;  ///< false for an older file opened read-only: the counts were computed from every row
  std::vector<DatasetInfo> datasets;
  std::vector<DictionaryInfo> dictionaries;
  std::vector<DescriptorSetInfo> descriptor_sets;
  std::int64_t submap_count = 0;  ///< over all datasets
  std::int64_t point_count = 0;   ///< over all submaps
};

class MapDatabase {
 public:
  enum class Mode {
    kReadOnly,   ///< the file must exist; writes throw (an interrupted write's journal is still rolled back)
    kReadWrite,  ///< the file must exist
    kCreate,     ///< opens the file read-write, creating an empty database first when it is missing
  };

  /// Opens (and checks) a database; see the file comment for what is refused.
  static MapDatabase open(const std::filesystem::path& path, Mode mode);

  MapDatabase(MapDatabase&&) noexcept;
  MapDatabase& operator=(MapDatabase&&) noexcept;
  ~MapDatabase();

  const std::filesystem::path& path() const;

  /// RAII transaction: commit() makes the writes since construction durable; destruction without
  /// commit() (e.g. by an exception) rolls them back. Nests (inner ones are savepoints). Must not outlive
  /// its database; create and destroy in LIFO order.
  class Transaction {
   public:
    explicit Transaction(MapDatabase& db);
    Transaction(const Transaction&) = delete;
    Transaction& operator=(const Transaction&) = delete;
    ~Transaction();
    void commit();

   private:
    MapDatabase& db_;
    bool outermost_ = false;
    bool done_ = false;
  };

  // ---- datasets and submaps ----
  /// Creates an empty dataset; throws InputError when the name is taken or the config is invalid.
  std::int64_t add_dataset(const DatasetSpec& spec);
  /// Appends submaps to a dataset (indices continue after the last stored one); returns their map ids.
  std::vector<std::int64_t> add_submaps(std::int64_t dataset_id, const Submaps& submaps);
  /// add_dataset + add_submaps in one transaction; returns the dataset id.
  std::int64_t store_dataset(const DatasetSpec& spec, const Submaps& submaps);
  /// Removes a dataset with its submaps and their descriptors.
  void remove_dataset(std::int64_t dataset_id);

  std::vector<DatasetInfo> datasets() const;
  /// Throws InputError when there is no such dataset.
  DatasetInfo dataset(std::int64_t dataset_id) const;
  std::optional<DatasetInfo> find_dataset(const std::string& name) const;
  /// Map ids of a dataset, in index order.
  std::vector<std::int64_t> map_ids(std::int64_t dataset_id) const;
  /// The submaps of a dataset in index order; Submap::id is the global map id.
  Submaps load_submaps(std::int64_t dataset_id) const;
  /// One submap by global map id; throws InputError naming the id when it does not exist.
  Submap load_submap(std::int64_t map_id) const;
  MapLocation locate(std::int64_t map_id) const;

  // ---- dictionaries ----
  /// Stores a dictionary map; throws InputError when the name is taken.
  std::int64_t add_dictionary(const Dictionary& dictionary);
  /// Throws InputError naming the dictionary when it does not exist.
  Dictionary load_dictionary(const std::string& name) const;
  std::vector<DictionaryInfo> dictionaries() const;
  void remove_dictionary(const std::string& name);

  // ---- descriptors, keyed by (map id, dictionary name, K); one codec per (dictionary, K) ----
  /// Inserts or replaces one descriptor packed under `codec`. Throws InputError for an unknown map id,
  /// k < 1, an empty dictionary name, an invalid codec, bytes.size() != ceil(bits / 8), or a bit count that
  /// is not a whole number of parts (at most K) under the codec.
  void put_descriptor(std::int64_t map_id, const std::string& dictionary, int k, const CodecConfig& codec,
                      const PackedDescriptor& d);
  /// Inserts or replaces many descriptors of one (dictionary, K) in one transaction. A set holds one codec:
  /// writing under a codec other than the stored one first removes the set's old descriptors, which that
  /// codec cannot decode.
  void put_descriptors(const std::string& dictionary, int k, const CodecConfig& codec,
                       const std::vector<DescriptorRecord>& records);
  /// The codec of the set (dictionary, K); nullopt when no descriptor of the set is stored. Throws InputError
  /// naming the file and set for a stored codec that does not parse or validate.
  std::optional<CodecConfig> descriptor_codec(const std::string& dictionary, int k) const;
  std::optional<PackedDescriptor> get_descriptor(std::int64_t map_id, const std::string& dictionary,
                                                 int k) const;
  /// All descriptors of one (dictionary, K), by increasing map id.
  std::vector<DescriptorRecord> load_descriptors(const std::string& dictionary, int k) const;
  /// The same, one row at a time, without holding them all: visit(map_id, descriptor) by increasing map id (the
  /// descriptor is reused between calls). Size checks and errors as load_descriptors.
  void scan_descriptors(const std::string& dictionary, int k,
                        const std::function<void(std::int64_t, const PackedDescriptor&)>& visit) const;
  std::vector<DescriptorSetInfo> descriptor_sets() const;

  /// True when the file keeps its counts (schema version >= 3); false for an older file opened read-only, whose
  /// datasets(), descriptor_sets() and summary() read every row.
  bool keeps_counts() const;
  /// Datasets, dictionaries, descriptor sets and totals; a few rows at any size when keeps_counts().
  DatabaseSummary summary() const;
  /// Runs SQLite's quick_check over the whole file; throws InputError describing the first problem.
  void check_integrity() const;

 private:
  struct Impl;
  explicit MapDatabase(std::unique_ptr<Impl> impl);
  void require_writable() const;
  std::unique_ptr<Impl> impl_;
};

}  // namespace partslam::io
