// Shared by the map database targets and the seed generator: a small database (one dataset of a few submaps, a
// dictionary, descriptor sets of K = 1, 3 and 20), and reading every table of a database the way the commands do.
#pragma once

#include <sqlite3.h>

#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/parts/descriptor_layout.h"
#include "fuzz/fuzz_common.h"
#include "io/store/descriptor_store.h"
#include "io/store/map_database.h"

namespace partslam::fuzz {

/// Writes a small database at path (which must not exist). submap_points / dictionary_points: the points of the
/// maps (synthetic ones when empty). page_size: SQLite page size in bytes (512 keeps the file to a few KB).
/// version1: left at schema version 1 (no descriptor_codecs table, no counts tables), as an older partslam wrote it.
inline void make_small_database(const std::filesystem::path& path, std::vector<Points2> submap_points = {},
                                Points2 dictionary_points = {}, int page_size = 512, bool version1 = false) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-6.0, 6.0);
  if (submap_points.empty()) {
    for (int i = 0; i < 3; ++i) {
      Points2 points;
      for (int j = 0; j < 6; ++j) points.emplace_back(coord(rng), coord(rng));
      submap_points.push_back(points);
    }
  }
  if (dictionary_points.empty()) {
    for (int j = 0; j < 12; ++j) dictionary_points.emplace_back(3 * coord(rng), 3 * coord(rng));
  }
  {
    io::MapDatabase db = io::MapDatabase::open(path, io::MapDatabase::Mode::kCreate);
    Submaps submaps;
    for (std::size_t i = 0; i < submap_points.size(); ++i) {
      Submap m;
      m.id = static_cast<std::int64_t>(i);
      m.anchor_scan = static_cast<std::int64_t>(10 * i);
      m.anchor_timestamp = 1.0e9 + 0.5 * static_cast<double>(i);
      m.travel = 2.0 * static_cast<double>(i);
      m.alignment_angle = 0.25;
      m.T_world_map = Pose2{1.5 * static_cast<double>(i), -2.0, 0.3};
      m.points = submap_points[i];
      m.scan_timestamps = {m.anchor_timestamp, m.anchor_timestamp + 0.1};
      submaps.push_back(std::move(m));
    }
    db.store_dataset({"fuzz", "fuzz.log", io::DatasetKind::kSubmaps, {}}, submaps);
    Dictionary d;
    d.name = "dict";
    d.source = "dict.log";
    d.points = dictionary_points;
    d.metadata = R"({"builder":"fuzz"})";
    db.add_dictionary(d);
    const std::vector<std::int64_t> ids = db.map_ids(db.find_dataset("fuzz")->id);
    for (const int k : {1, 3, 20}) {
      const CodecConfig codec = descriptor_codec_config(dictionary_points, k);
      std::vector<io::DescriptorRecord> records;
      for (std::size_t i = 0; i < ids.size(); ++i) {
        PackedDescriptor p;
        p.bits = bits_per_part(codec) * std::min<int>(k, static_cast<int>(i) + 1);
        p.bytes.assign(static_cast<std::size_t>((p.bits + 7) / 8), 0);
        for (std::size_t b = 0; b + 1 < p.bytes.size(); ++b) p.bytes[b] = static_cast<std::uint8_t>(b % 3);
        records.push_back({ids[i], p});
      }
      db.put_descriptors("dict", k, codec, records);
    }
  }
  // MapDatabase creates its files with SQLite's default page size; VACUUM rewrites the file with the small one.
  sqlite3* raw = nullptr;
  if (sqlite3_open(path.c_str(), &raw) != SQLITE_OK) std::abort();
  // Version 1 had neither the codecs (version 2) nor the counts (version 3): their tables and triggers go.
  const std::string sql = (version1 ? std::string("DROP TRIGGER dataset_counted; DROP TRIGGER submap_added;"
                                                  " DROP TRIGGER submap_removed; DROP TRIGGER submap_changed;"
                                                  " DROP TRIGGER descriptor_added; DROP TRIGGER descriptor_removed;"
                                                  " DROP TRIGGER descriptor_changed; DROP TABLE dataset_counts;"
                                                  " DROP TABLE descriptor_counts; DROP TABLE descriptor_codecs;"
                                                  " PRAGMA user_version = 1; ")
                                    : "") +
                          "PRAGMA page_size = " + std::to_string(page_size) + "; VACUUM;";
  if (sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, nullptr) != SQLITE_OK) std::abort();
  sqlite3_close(raw);
}

/// Writes a database file for a run, removing what an earlier run may have left beside it (journal, WAL).
inline std::filesystem::path write_database(const std::uint8_t* data, std::size_t size) {
  std::error_code ec;
  for (const char* suffix : {"-journal", "-wal", "-shm"})
    std::filesystem::remove(scratch_dir() / (std::string("maps.db") + suffix), ec);
  return write_file("maps.db", data, size);
}

inline void check_submap(const Submap& m) {
  check(finite(m.T_world_map) && std::isfinite(m.travel) && std::isfinite(m.anchor_timestamp), "submap numbers");
  for (const Vec2& p : m.points) {
    check(finite(p) && std::abs(p.x()) <= kMaxCoordinate && std::abs(p.y()) <= kMaxCoordinate, "submap point");
  }
}

/// Opens path read-only and reads every table through the library (datasets, submaps, dictionaries, descriptor
/// sets with their codecs, decoded), each step on its own so that one refused row does not hide the others.
inline void read_everything(const std::filesystem::path& path) {
  std::optional<io::MapDatabase> opened;
  if (!expect_input_error([&] { opened.emplace(io::MapDatabase::open(path, io::MapDatabase::Mode::kReadOnly)); }))
    return;
  const io::MapDatabase& db = *opened;
  expect_input_error([&] { db.summary(); });
  std::vector<io::DatasetInfo> datasets;
  expect_input_error([&] { datasets = db.datasets(); });
  for (const io::DatasetInfo& d : datasets) {
    expect_input_error([&] { db.find_dataset(d.spec.name); });
    expect_input_error([&] {
      for (const Submap& m : db.load_submaps(d.id)) check_submap(m);
    });
    std::vector<std::int64_t> ids;
    expect_input_error([&] { ids = db.map_ids(d.id); });
    for (std::size_t i = 0; i < ids.size() && i < 2; ++i) {
      expect_input_error([&] { db.locate(ids[i]); });
      expect_input_error([&] { check_submap(db.load_submap(ids[i])); });
    }
  }
  std::vector<io::DictionaryInfo> dictionaries;
  expect_input_error([&] { dictionaries = db.dictionaries(); });
  for (const io::DictionaryInfo& info : dictionaries) {
    expect_input_error([&] {
      const Dictionary d = db.load_dictionary(info.name);
      for (const Vec2& p : d.points) check(finite(p), "dictionary point");
    });
  }
  expect_input_error([&] { io::resolve_dictionary(db, ""); });
  std::vector<io::DescriptorSetInfo> sets;
  expect_input_error([&] { sets = db.descriptor_sets(); });
  for (const io::DescriptorSetInfo& s : sets) {
    expect_input_error([&] { db.descriptor_codec(s.dictionary, s.k); });
    std::vector<io::DescriptorRecord> records;
    expect_input_error([&] { records = db.load_descriptors(s.dictionary, s.k); });
    expect_input_error([&] { io::load_descriptor_set(db, s.dictionary, s.k); });
    if (!records.empty()) {  // one record by itself (the whole set was read above)
      expect_input_error([&] { io::load_descriptor(db, s.dictionary, s.k, records.back().map_id); });
      expect_input_error([&] { io::query_list_parts(db, s.dictionary, records.back().map_id); });
    }
  }
  expect_input_error([&] { db.check_integrity(); });
}

}  // namespace partslam::fuzz
