// Private to io (the map database's .cc files and io/descriptor_store): the state behind MapDatabase, shared
// checks and message wording.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/error.h"
#include "core/maps/scan.h"
#include "io/store/blob_codec.h"
#include "io/store/map_database.h"
#include "io/files/sqlite.h"

namespace partslam::io {

struct MapDatabase::Impl {
  sqlite::Connection db;
  bool read_only = false;
  int depth = 0;  ///< open Transactions
  int schema_version = 0;
};

namespace internal {

/// The table schema version 2 added.
inline constexpr const char* kCodecsTable =
    "CREATE TABLE descriptor_codecs (dictionary TEXT NOT NULL, k INTEGER NOT NULL, codec TEXT NOT NULL,"
    " PRIMARY KEY (dictionary, k)) STRICT, WITHOUT ROWID";

/// What schema version 3 added: counts per dataset and per descriptor set, kept by triggers in the transaction of
/// every insert, update and delete (cascades included), so that summaries read a few rows, not every one.
/// first/last map ids are not kept: they are read through the (dataset_id, idx) index.
/// REPLACE deletes fire the delete triggers only with PRAGMA recursive_triggers = ON (set by MapDatabase::open).
inline constexpr const char* kCountsSchema = R"sql(
CREATE TABLE dataset_counts (
  dataset_id INTEGER PRIMARY KEY REFERENCES datasets(id) ON DELETE CASCADE,
  submaps INTEGER NOT NULL,
  points INTEGER NOT NULL
) STRICT;
CREATE TABLE descriptor_counts (
  dictionary TEXT NOT NULL,
  k INTEGER NOT NULL,
  maps INTEGER NOT NULL,
  bits INTEGER NOT NULL,
  PRIMARY KEY (dictionary, k)
) STRICT, WITHOUT ROWID;
CREATE TRIGGER dataset_counted AFTER INSERT ON datasets BEGIN
  INSERT INTO dataset_counts (dataset_id, submaps, points) VALUES (new.id, 0, 0);
END;
CREATE TRIGGER submap_added AFTER INSERT ON submaps BEGIN
  UPDATE dataset_counts SET submaps = submaps + 1, points = points + new.point_count
   WHERE dataset_id = new.dataset_id;
END;
CREATE TRIGGER submap_removed AFTER DELETE ON submaps BEGIN
  UPDATE dataset_counts SET submaps = submaps - 1, points = points - old.point_count
   WHERE dataset_id = old.dataset_id;
END;
CREATE TRIGGER submap_changed AFTER UPDATE OF dataset_id, point_count ON submaps BEGIN
  UPDATE dataset_counts SET submaps = submaps - 1, points = points - old.point_count
   WHERE dataset_id = old.dataset_id;
  UPDATE dataset_counts SET submaps = submaps + 1, points = points + new.point_count
   WHERE dataset_id = new.dataset_id;
END;
CREATE TRIGGER descriptor_added AFTER INSERT ON descriptors BEGIN
  INSERT INTO descriptor_counts (dictionary, k, maps, bits) VALUES (new.dictionary, new.k, 1, new.bits)
    ON CONFLICT (dictionary, k) DO UPDATE SET maps = maps + 1, bits = bits + excluded.bits;
END;
CREATE TRIGGER descriptor_removed AFTER DELETE ON descriptors BEGIN
  UPDATE descriptor_counts SET maps = maps - 1, bits = bits - old.bits
   WHERE dictionary = old.dictionary AND k = old.k;
  DELETE FROM descriptor_counts WHERE dictionary = old.dictionary AND k = old.k AND maps <= 0;
END;
CREATE TRIGGER descriptor_changed AFTER UPDATE OF dictionary, k, bits ON descriptors BEGIN
  UPDATE descriptor_counts SET maps = maps - 1, bits = bits - old.bits
   WHERE dictionary = old.dictionary AND k = old.k;
  DELETE FROM descriptor_counts WHERE dictionary = old.dictionary AND k = old.k AND maps <= 0;
  INSERT INTO descriptor_counts (dictionary, k, maps, bits) VALUES (new.dictionary, new.k, 1, new.bits)
    ON CONFLICT (dictionary, k) DO UPDATE SET maps = maps + 1, bits = bits + excluded.bits;
END;
)sql";

/// Fills the tables of kCountsSchema from the rows (migration from version 2).
inline constexpr const char* kFillCounts = R"sql(
INSERT INTO dataset_counts (dataset_id, submaps, points)
  SELECT d.id, COUNT(s.id), COALESCE(SUM(s.point_count), 0) FROM datasets d LEFT JOIN submaps s
   ON s.dataset_id = d.id GROUP BY d.id;
INSERT INTO descriptor_counts (dictionary, k, maps, bits)
  SELECT dictionary, k, COUNT(*), SUM(bits) FROM descriptors GROUP BY dictionary, k;
)sql";

/// Migrates a version 1 or 2 file to the current schema in one transaction (see map_database.h).
void migrate_to_current(sqlite::Connection& db);

/// Throws InputError "<context>: <field> must be finite" (SQLite would store NaN as NULL).
inline void require_finite(double value, const std::string& context, const char* field) {
  if (!std::isfinite(value)) {
    throw InputError(context + ": " + field + " must be finite, got " + std::to_string(value));
  }
}

/// Throws InputError "<context>: point i (x, y) lies beyond +-kMaxCoordinate (corrupt database)": stored points are
/// written from logs whose coordinates are bounded, so larger ones were edited in (and would overflow cell
/// indices downstream).
inline void require_plausible(const Points2& points, const std::string& context) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!(std::abs(points[i].x()) <= kMaxCoordinate && std::abs(points[i].y()) <= kMaxCoordinate)) {
      throw InputError(context + ": point " + std::to_string(i) + " (" + std::to_string(points[i].x()) + ", " +
                       std::to_string(points[i].y()) + ") lies beyond +-" +
                       std::to_string(static_cast<long>(kMaxCoordinate)) + " m (corrupt database)");
    }
  }
}

/// True when `text` is valid UTF-8 (nlohmann's strict decoder: no overlong forms, no surrogates) without control
/// characters.
inline bool is_clean_utf8(const std::string& text) {
  if (std::any_of(text.begin(), text.end(), [](char c) { return (c >= 0 && c < 0x20) || c == 0x7F; })) return false;
  try {
    (void)nlohmann::json(text).dump();  // throws type_error 316 on invalid UTF-8
  } catch (const nlohmann::json::type_error&) {
    return false;
  }
  return true;
}

/// "<file>: descriptor of map <id> (dictionary '<name>', K=<k>)": how errors name one stored descriptor.
inline std::string descriptor_context(const std::string& file, std::int64_t map_id, const std::string& dictionary,
                                      int k) {
  return file + ": descriptor of map " + std::to_string(map_id) + " (dictionary '" + dictionary +
         "', K=" + std::to_string(k) + ")";
}

/// Names are non-empty UTF-8 text without control characters (they go to JSON and terminals).
inline void require_name(const std::string& name, const std::string& what) {
  if (name.empty()) throw InputError(what + " name must not be empty");
  if (!is_clean_utf8(name))
    throw InputError(what + " name must be UTF-8 text without control characters (it has other bytes)");
}

}  // namespace internal
}  // namespace partslam::io
