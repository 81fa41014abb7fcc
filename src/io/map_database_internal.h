// Private to the map database's .cc files: the state behind MapDatabase and shared checks.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "core/maps/scan.h"
#include "io/map_database.h"
#include "io/sqlite.h"

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

/// Migrates a version 1 file to the current schema in one transaction (see map_database.h).
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

/// True when `text` is valid UTF-8 (no overlong forms, no surrogates) without control characters.
inline bool is_clean_utf8(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    if (n == 0 || i + n > text.size() || (n == 1 && (c < 0x20 || c == 0x7F))) return false;
    std::uint32_t cp = n == 1 ? c : c & (0x7F >> n);
    for (std::size_t k = 1; k < n; ++k) {
      const auto d = static_cast<unsigned char>(text[i + k]);
      if ((d >> 6) != 0x2) return false;
      cp = (cp << 6) | (d & 0x3F);
    }
    const std::uint32_t min[] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < min[n] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += n;
  }
  return true;
}

/// Names are non-empty UTF-8 text without control characters (they go to JSON and terminals).
inline void require_name(const std::string& name, const std::string& what) {
  if (name.empty()) throw InputError(what + " name must not be empty");
  if (!is_clean_utf8(name))
    throw InputError(what + " name must be UTF-8 text without control characters (it has other bytes)");
}

}  // namespace internal
}  // namespace partslam::io
