// Helpers shared by the map database's tests (io/store/map_database*_test.cc): hand-made submaps, a database made
// to look as an older partslam wrote it, its kept counts against the rows, and a fixture with a scratch folder.
// Test-only; not part of the library.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>

#include "core/error.h"
#include "core/parts/descriptor_layout.h"
#include "io/files/sqlite.h"
#include "io/store/map_database.h"

namespace partslam::io::testing {

namespace fs = std::filesystem;
using Mode = MapDatabase::Mode;

// Hand-made submaps with awkward values: timestamps that need float64, points off the float32 grid.
inline Submaps make_submaps(int count, int points_each, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(-6.4, 6.4);
  Submaps submaps;
  for (int i = 0; i < count; ++i) {
    Submap m;
    m.id = i;
    m.anchor_scan = 10 * i + 3;
    m.anchor_timestamp = 1.0e9 + 0.123456789 * i;
    m.travel = 0.5 * i + 1e-9;
    m.alignment_angle = 0.1 + 0.01 * i;
    m.T_world_map = Pose2{1.5 * i, -2.25 * i + 1.0 / 3.0, 0.3 - 0.02 * i};
    for (int j = 0; j < points_each; ++j) m.points.emplace_back(coord(rng), coord(rng));
    for (int j = 0; j < 4; ++j) m.scan_timestamps.push_back(m.anchor_timestamp + 0.0251 * j);
    for (int j = 0; j < i % 3; ++j) m.origins.emplace_back(0.25 * j + 1.0 / 3.0, -0.1 * j);  // none for some
    submaps.push_back(std::move(m));
  }
  return submaps;
}

inline Points2 rounded_to_float(const Points2& points) {
  Points2 out;
  for (const Vec2& p : points) out.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  return out;
}

// Turns a current file into what an older partslam wrote: version 3 kept no laser origins, version 2 no counts
// (tables and triggers of schema version 3) either, version 1 no codecs either.
inline void make_older(const fs::path& path, int version) {
  const sqlite::Connection db = sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite);
  db.exec("ALTER TABLE submaps DROP COLUMN origins");
  if (version == 3) {
    db.exec("PRAGMA user_version = 3");
    return;
  }
  db.exec("DROP TRIGGER dataset_counted; DROP TRIGGER submap_added; DROP TRIGGER submap_removed;"
          " DROP TRIGGER submap_changed; DROP TRIGGER descriptor_added; DROP TRIGGER descriptor_removed;"
          " DROP TRIGGER descriptor_changed; DROP TABLE dataset_counts; DROP TABLE descriptor_counts");
  if (version == 1) db.exec("DROP TABLE descriptor_codecs");
  db.exec("PRAGMA user_version = " + std::to_string(version));
}

// What a summary says, as text, and the same figures counted from every row by plain SQL.
inline std::string kept_counts(const MapDatabase& db) {
  const DatabaseSummary s = db.summary();
  std::string out = "total " + std::to_string(s.submap_count) + " " + std::to_string(s.point_count) + ";";
  for (const DatasetInfo& d : s.datasets) {
    out += " dataset " + std::to_string(d.id) + ": " + std::to_string(d.submap_count) + " " +
           std::to_string(d.mean_points) + " " + std::to_string(d.first_map_id) + ".." +
           std::to_string(d.last_map_id) + ";";
  }
  for (const DescriptorSetInfo& d : s.descriptor_sets)
    out += " set " + d.dictionary + "/" + std::to_string(d.k) + ": " + std::to_string(d.count) + " " +
           std::to_string(d.mean_bits) + ";";
  return out;
}

inline std::string real_counts(const fs::path& path) {
  const sqlite::Connection db = sqlite::Connection::open(path, sqlite::Connection::Access::kReadOnly);
  sqlite::Statement totals(db, "SELECT COUNT(*), COALESCE(SUM(point_count), 0) FROM submaps");
  totals.step();
  std::string out = "total " + std::to_string(totals.int64(0)) + " " + std::to_string(totals.int64(1)) + ";";
  sqlite::Statement datasets(db,
                             "SELECT d.id, COUNT(s.id), COALESCE(AVG(s.point_count), 0), COALESCE(MIN(s.id), -1),"
                             " COALESCE(MAX(s.id), -1) FROM datasets d LEFT JOIN submaps s ON s.dataset_id = d.id"
                             " GROUP BY d.id ORDER BY d.id");
  while (datasets.step()) {
    out += " dataset " + std::to_string(datasets.int64(0)) + ": " + std::to_string(datasets.int64(1)) + " " +
           std::to_string(datasets.real(2)) + " " + std::to_string(datasets.int64(3)) + ".." +
           std::to_string(datasets.int64(4)) + ";";
  }
  sqlite::Statement sets(db, "SELECT dictionary, k, COUNT(*), AVG(bits) FROM descriptors GROUP BY dictionary, k"
                             " ORDER BY dictionary, k");
  while (sets.step())
    out += " set " + sets.text(0) + "/" + std::to_string(sets.int64(1)) + ": " + std::to_string(sets.int64(2)) +
           " " + std::to_string(sets.real(3)) + ";";
  return out;
}

class MapDatabaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("partslam_db_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The message of the InputError that opening path throws ("" when it opens).
  static std::string open_error(const fs::path& path, Mode mode = Mode::kReadOnly) {
    try {
      MapDatabase::open(path, mode);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

// A codec of 42 bits per part (the paper's layout, no rotation bits).
inline CodecConfig codec42() {
  CodecConfig c;
  c.dictionary_extent = {-20.0, 30.0, -5.0, 45.0};
  c.rotation_bits = 0;
  return c;
}

}  // namespace partslam::io::testing
