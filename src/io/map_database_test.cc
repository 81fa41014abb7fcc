#include "io/map_database.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>

#include "core/error.h"
#include "core/parts/descriptor_layout.h"
#include "io/blob_codec.h"
#include "io/sqlite.h"

namespace partslam::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;
using Mode = MapDatabase::Mode;

// Hand-made submaps with awkward values: timestamps that need float64, points off the float32 grid.
Submaps make_submaps(int count, int points_each, unsigned seed) {
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

Points2 rounded_to_float(const Points2& points) {
  Points2 out;
  for (const Vec2& p : points) out.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  return out;
}

// Turns a current file into what an older partslam wrote: version 3 kept no laser origins, version 2 no counts
// (tables and triggers of schema version 3) either, version 1 no codecs either.
void make_older(const fs::path& path, int version) {
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
std::string kept_counts(const MapDatabase& db) {
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

std::string real_counts(const fs::path& path) {
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

TEST_F(MapDatabaseTest, SubmapsRoundTripExactlyUpToFloat32Points) {
  const fs::path path = dir_ / "maps.db";
  const Submaps submaps = make_submaps(5, 300, 1);
  DatasetSpec spec{"fr079-corrected", "/data/fr079.log", DatasetKind::kSubmaps, {}};
  spec.config.window_length = 3.0;
  spec.config.resolution = 0.05;
  spec.config.min_points = 7;
  spec.config.align = false;
  spec.config.max_range = 12.5;
  spec.scan_matched = true;
  spec.front_end.matcher.linear_window = 0.45;
  spec.front_end.matcher.angular_window = 0.05;
  std::int64_t dataset_id = 0;
  {
    MapDatabase db = MapDatabase::open(path, Mode::kCreate);
    dataset_id = db.store_dataset(spec, submaps);
  }
  const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
  const Submaps loaded = db.load_submaps(dataset_id);
  ASSERT_EQ(loaded.size(), submaps.size());
  const std::vector<std::int64_t> ids = db.map_ids(dataset_id);
  for (std::size_t i = 0; i < submaps.size(); ++i) {
    const Submap& a = submaps[i];
    const Submap& b = loaded[i];
    EXPECT_EQ(b.id, ids[i]);
    EXPECT_EQ(b.anchor_scan, a.anchor_scan);
    EXPECT_EQ(b.anchor_timestamp, a.anchor_timestamp);
    EXPECT_EQ(b.travel, a.travel);
    EXPECT_EQ(b.alignment_angle, a.alignment_angle);
    EXPECT_EQ(b.T_world_map.x, a.T_world_map.x);
    EXPECT_EQ(b.T_world_map.y, a.T_world_map.y);
    EXPECT_EQ(b.T_world_map.theta, a.T_world_map.theta);
    EXPECT_EQ(b.scan_timestamps, a.scan_timestamps);
    EXPECT_EQ(b.points, rounded_to_float(a.points));
    EXPECT_EQ(b.origins, rounded_to_float(a.origins));
    for (std::size_t j = 0; j < a.points.size(); ++j) {
      ASSERT_LT((b.points[j] - a.points[j]).cwiseAbs().maxCoeff(), 6.4 * std::ldexp(1.0, -24));
    }
  }
  const Submap one = db.load_submap(ids[3]);
  EXPECT_EQ(one.points, loaded[3].points);
  EXPECT_EQ(db.locate(ids[3]).index, 3);
  EXPECT_EQ(db.locate(ids[3]).dataset_name, "fr079-corrected");

  const DatasetInfo info = db.dataset(dataset_id);
  EXPECT_EQ(info.spec.name, spec.name);
  EXPECT_EQ(info.spec.source, spec.source);
  EXPECT_EQ(info.spec.kind, DatasetKind::kSubmaps);
  EXPECT_EQ(info.spec.config.window_length, 3.0);
  EXPECT_EQ(info.spec.config.resolution, 0.05);
  EXPECT_EQ(info.spec.config.min_points, 7);
  EXPECT_FALSE(info.spec.config.align);
  EXPECT_EQ(info.spec.config.max_range, 12.5);
  EXPECT_TRUE(info.spec.scan_matched);
  EXPECT_EQ(info.spec.front_end.matcher.linear_window, 0.45);
  EXPECT_EQ(info.spec.front_end.matcher.angular_window, 0.05);
  EXPECT_EQ(info.submap_count, 5);
  EXPECT_DOUBLE_EQ(info.mean_points, 300.0);
  EXPECT_EQ(info.first_map_id, ids.front());
  EXPECT_EQ(info.last_map_id, ids.back());
  EXPECT_EQ(info.created.size(), 20u);  // 2024-01-02T03:04:05Z
  EXPECT_THAT(open_error(path), ::testing::IsEmpty());
}

TEST_F(MapDatabaseTest, MapIdsAreGlobalAndNeverReused) {
  MapDatabase db = MapDatabase::open(dir_ / "maps.db", Mode::kCreate);
  const std::int64_t a = db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(3, 10, 1));
  const std::int64_t b =
      db.store_dataset({"b", "b.log", DatasetKind::kDictionary, {}}, make_submaps(2, 10, 2));
  EXPECT_EQ(db.map_ids(a), (std::vector<std::int64_t>{1, 2, 3}));
  EXPECT_EQ(db.map_ids(b), (std::vector<std::int64_t>{4, 5}));
  db.remove_dataset(b);  // held the largest ids
  EXPECT_THROW(db.load_submap(5), InputError);
  const std::int64_t c = db.store_dataset({"c", "c.log", DatasetKind::kSubmaps, {}}, make_submaps(1, 10, 4));
  EXPECT_EQ(db.map_ids(c), (std::vector<std::int64_t>{6}));
  EXPECT_EQ(db.add_submaps(a, make_submaps(1, 10, 3)), (std::vector<std::int64_t>{7}));
  EXPECT_EQ(db.locate(7).index, 3);
  EXPECT_EQ(db.locate(7).dataset_id, a);
  EXPECT_EQ(db.dataset(c).spec.name, "c");
  EXPECT_EQ(db.summary().submap_count, 5);
  EXPECT_EQ(db.summary().point_count, 50);
  EXPECT_THAT(db.datasets(), ::testing::SizeIs(2));
}

TEST_F(MapDatabaseTest, RefusesDuplicateNamesBadConfigAndUnknownIds) {
  MapDatabase db = MapDatabase::open(dir_ / "maps.db", Mode::kCreate);
  db.add_dataset({"a", "a.log", DatasetKind::kSubmaps, {}});
  try {
    db.add_dataset({"a", "other.log", DatasetKind::kSubmaps, {}});
    FAIL() << "duplicate accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("'a' already exists"));
  }
  SubmapConfig bad;
  bad.resolution = -1;
  EXPECT_THROW(db.add_dataset({"b", "b.log", DatasetKind::kSubmaps, bad}), InputError);
  EXPECT_THROW(db.add_dataset({"", "b.log", DatasetKind::kSubmaps, {}}), InputError);
  EXPECT_THROW(db.add_submaps(42, make_submaps(1, 5, 1)), InputError);
  try {
    db.load_submap(99);
    FAIL() << "unknown map id accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no map with id 99"));
    EXPECT_THAT(e.what(), HasSubstr("maps.db"));
  }
  EXPECT_THROW(parse_dataset_kind("maps"), InputError);
}

// A codec of 42 bits per part (the paper's layout, no rotation bits).
CodecConfig codec42() {
  CodecConfig c;
  c.dictionary_extent = {-20.0, 30.0, -5.0, 45.0};
  c.rotation_bits = 0;
  return c;
}

TEST_F(MapDatabaseTest, DescriptorsPutGetReplaceAndCascade) {
  MapDatabase db = MapDatabase::open(dir_ / "maps.db", Mode::kCreate);
  const std::int64_t ds = db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(3, 10, 1));
  const std::vector<std::int64_t> ids = db.map_ids(ds);
  const CodecConfig c = codec42();
  const PackedDescriptor d126{Bytes{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 0x3f}, 126};
  db.put_descriptor(ids[1], "fr079", 3, c, d126);
  const auto got = db.get_descriptor(ids[1], "fr079", 3);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->bytes, d126.bytes);
  EXPECT_EQ(got->bits, 126);
  EXPECT_FALSE(db.get_descriptor(ids[1], "fr079", 2).has_value());
  EXPECT_FALSE(db.get_descriptor(ids[1], "albert", 3).has_value());
  EXPECT_FALSE(db.get_descriptor(ids[0], "fr079", 3).has_value());

  const PackedDescriptor d42{Bytes{0xab, 1, 2, 3, 4, 0x3}, 42};
  db.put_descriptor(ids[1], "fr079", 3, c, d42);  // replaces
  EXPECT_EQ(db.get_descriptor(ids[1], "fr079", 3)->bytes, d42.bytes);
  db.put_descriptors("fr079", 3, c, {{ids[2], d126}, {ids[0], {Bytes{}, 0}}});
  const std::vector<DescriptorRecord> all = db.load_descriptors("fr079", 3);
  ASSERT_EQ(all.size(), 3u);
  EXPECT_EQ(all[0].map_id, ids[0]);
  EXPECT_EQ(all[0].descriptor.bits, 0);
  EXPECT_EQ(all[2].descriptor.bytes, d126.bytes);
  ASSERT_EQ(db.descriptor_sets().size(), 1u);
  EXPECT_EQ(db.descriptor_sets()[0].count, 3);
  EXPECT_DOUBLE_EQ(db.descriptor_sets()[0].mean_bits, 56.0);

  EXPECT_THROW(db.put_descriptor(ids[0], "fr079", 3, c, {Bytes{1, 2}, 126}), InputError);  // length
  EXPECT_THROW(db.put_descriptor(ids[0], "fr079", 3, c, {Bytes{1}, 8}), InputError);       // not whole parts
  EXPECT_THROW(db.put_descriptor(ids[0], "fr079", 2, c, d126), InputError);                // 3 parts under K=2
  EXPECT_THROW(db.put_descriptor(ids[0], "fr079", 0, c, d42), InputError);                 // K
  EXPECT_THROW(db.put_descriptor(ids[0], "", 3, c, d42), InputError);                      // name
  EXPECT_THROW(db.put_descriptor(1234, "fr079", 3, c, d42), InputError);                   // map id
  EXPECT_THROW(db.put_descriptor(ids[0], "fr079", 3, CodecConfig{}, d42), InputError);     // no extent
  // A failing record leaves the batch unwritten, codec included.
  EXPECT_THROW(db.put_descriptors("fr079", 4, c, {{ids[0], d42}, {999, d42}}), InputError);
  EXPECT_TRUE(db.load_descriptors("fr079", 4).empty());
  EXPECT_FALSE(db.descriptor_codec("fr079", 4).has_value());

  db.remove_dataset(ds);
  EXPECT_TRUE(db.load_descriptors("fr079", 3).empty());
}

TEST_F(MapDatabaseTest, DescriptorSetsKeepTheirCodec) {
  const fs::path path = dir_ / "maps.db";
  MapDatabase db = MapDatabase::open(path, Mode::kCreate);
  const std::vector<std::int64_t> ids =
      db.map_ids(db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(3, 10, 1)));
  CodecConfig c = codec42();
  c.dictionary_extent = {-20.1, 30.0 + 1.0 / 3.0, -5.0, 45.0};  // needs every digit to round-trip
  c.score_bits = 8;
  c.score_max = 0.7;
  const PackedDescriptor d50{Bytes(7, 0), 50};
  db.put_descriptors("fr079", 20, c, {{ids[0], d50}, {ids[1], d50}});
  const std::optional<CodecConfig> back = MapDatabase::open(path, Mode::kReadOnly).descriptor_codec("fr079", 20);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->dictionary_extent.x_min, -20.1);
  EXPECT_EQ(back->dictionary_extent.x_max, 30.0 + 1.0 / 3.0);
  EXPECT_EQ(back->score_bits, 8);
  EXPECT_EQ(back->score_max, 0.7);
  EXPECT_EQ(back->rotation_bits, 0);
  EXPECT_FALSE(db.descriptor_codec("fr079", 3).has_value());

  // Same codec: the set grows. Another codec: the old descriptors, which it cannot decode, go.
  db.put_descriptors("fr079", 20, c, {{ids[2], d50}});
  EXPECT_EQ(db.load_descriptors("fr079", 20).size(), 3u);
  c.score_max = 1.0;
  db.put_descriptors("fr079", 20, c, {{ids[2], d50}});
  EXPECT_EQ(db.load_descriptors("fr079", 20).size(), 1u);
  EXPECT_EQ(db.descriptor_codec("fr079", 20)->score_max, 1.0);

  // A damaged codec is named with its file and set.
  sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite)
      .exec("UPDATE descriptor_codecs SET codec = '{\"crop_size\": 12.8}'");
  try {
    MapDatabase::open(path, Mode::kReadOnly).descriptor_codec("fr079", 20);
    FAIL() << "damaged codec accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
    EXPECT_THAT(e.what(), HasSubstr("K=20"));
    EXPECT_THAT(e.what(), HasSubstr("keypoint_resolution"));
  }
}

TEST_F(MapDatabaseTest, SchemaVersionOneIsMigratedWhenOpenedForWriting) {
  const fs::path path = dir_ / "maps.db";
  std::vector<std::int64_t> ids;
  Dictionary d;
  d.name = "fr079";
  d.source = "fr079.log";
  d.resolution = 0.1;
  d.points = {{-3.0, 1.0}, {12.0, 7.5}, {4.0, -2.25}};
  const CodecConfig v1 = descriptor_codec_config_v1(d.points, 3);
  {
    MapDatabase db = MapDatabase::open(path, Mode::kCreate);
    ids = db.map_ids(db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(2, 10, 1)));
    db.add_dictionary(d);
    db.put_descriptors("fr079", 3, v1, {{ids[0], {Bytes(6, 0), 44}}});
    db.put_descriptors("gone", 3, v1, {{ids[1], {Bytes(6, 0), 44}}});
  }
  make_older(path, 1);  // no codec table, no counts, user_version 1

  {  // Read-only: left as it is, the codec derived as version 1 did.
    const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
    EXPECT_EQ(db.summary().schema_version, 1);
    EXPECT_EQ(db.descriptor_codec("fr079", 3)->dictionary_extent.x_min, v1.dictionary_extent.x_min);
    EXPECT_THROW(db.descriptor_codec("gone", 3), InputError);  // no dictionary left to derive it from
  }
  {  // Read-write: migrated, the same codec now stored.
    const MapDatabase db = MapDatabase::open(path, Mode::kReadWrite);
    EXPECT_EQ(db.summary().schema_version, kMapDatabaseSchemaVersion);
    EXPECT_EQ(kept_counts(db), real_counts(path));
    const std::optional<CodecConfig> c = db.descriptor_codec("fr079", 3);
    ASSERT_TRUE(c.has_value());
    EXPECT_EQ(c->dictionary_extent.x_min, v1.dictionary_extent.x_min);
    EXPECT_EQ(c->dictionary_extent.y_max, v1.dictionary_extent.y_max);
    EXPECT_EQ(c->rotation_bits, 2);
    EXPECT_THROW(db.descriptor_codec("gone", 3), InputError);
  }
  EXPECT_EQ(MapDatabase::open(path, Mode::kReadOnly).summary().schema_version, kMapDatabaseSchemaVersion);
}

TEST_F(MapDatabaseTest, KeptCountsEqualTheRowsAfterInsertsReplacesAndDeletes) {
  const fs::path path = dir_ / "maps.db";
  MapDatabase db = MapDatabase::open(path, Mode::kCreate);
  EXPECT_TRUE(db.keeps_counts());
  EXPECT_EQ(kept_counts(db), real_counts(path));
  const std::int64_t a = db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(5, 10, 1));
  const std::int64_t b = db.add_dataset({"b", "b.log", DatasetKind::kSubmaps, {}});
  db.add_submaps(b, make_submaps(3, 7, 2));
  db.add_submaps(b, make_submaps(2, 0, 3));  // appended, no points
  db.add_dataset({"empty", "e.log", DatasetKind::kDictionary, {}});
  const std::vector<std::int64_t> ids_a = db.map_ids(a), ids_b = db.map_ids(b);
  EXPECT_EQ(kept_counts(db), real_counts(path));
  EXPECT_EQ(db.dataset(b).submap_count, 5);
  EXPECT_EQ(db.dataset(b).first_map_id, ids_b.front());
  EXPECT_EQ(db.dataset(b).last_map_id, ids_b.back());

  const CodecConfig c = codec42();
  const PackedDescriptor d126{Bytes(16, 0x11), 126}, d42{Bytes(6, 0x22), 42};
  std::vector<DescriptorRecord> records;
  for (std::int64_t id : ids_a) records.push_back({id, d126});
  for (std::int64_t id : ids_b) records.push_back({id, d42});
  db.put_descriptors("fr079", 3, c, records);
  db.put_descriptors("fr079", 1, c, {{ids_a[0], d42}, {ids_b[1], d42}});
  db.put_descriptors("albert", 3, c, {{ids_b[2], d126}});
  EXPECT_EQ(kept_counts(db), real_counts(path));
  db.put_descriptors("fr079", 3, c, {{ids_a[1], d42}, {ids_b[0], d126}});  // replaced: bits change
  EXPECT_EQ(kept_counts(db), real_counts(path));
  CodecConfig other = c;
  other.dictionary_extent.x_max += 10.0;
  db.put_descriptors("fr079", 1, other, {{ids_a[3], d42}});  // another codec drops the set's old descriptors
  EXPECT_EQ(kept_counts(db), real_counts(path));
  {  // rolled back: the counts too
    MapDatabase::Transaction t(db);
    db.add_submaps(a, make_submaps(2, 4, 4));
    db.put_descriptors("fr079", 3, c, {{ids_a[2], d42}});
  }
  EXPECT_EQ(kept_counts(db), real_counts(path));
  {  // raw SQL edits (REPLACE deletes, plain updates and deletes) are counted too
    const sqlite::Connection raw = sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite);
    raw.exec("PRAGMA foreign_keys = ON; PRAGMA recursive_triggers = ON;"
             " INSERT OR REPLACE INTO descriptors SELECT dictionary, k, map_id, 42, data FROM descriptors"
             "  WHERE dictionary = 'fr079' AND k = 3 AND map_id = " + std::to_string(ids_a[4]) + ";"
             " UPDATE descriptors SET k = 2 WHERE dictionary = 'albert';"
             " UPDATE submaps SET point_count = 0, points = x'' WHERE id = " + std::to_string(ids_a[0]) + ";"
             " DELETE FROM submaps WHERE id = " + std::to_string(ids_b[3]));
  }
  EXPECT_EQ(kept_counts(db), real_counts(path));

  db.remove_dataset(b);  // cascades to its submaps and their descriptors
  EXPECT_EQ(kept_counts(db), real_counts(path));
  ASSERT_EQ(db.descriptor_sets().size(), 2u);  // albert/2 held only a map of b
  EXPECT_EQ(db.descriptor_sets()[0].dictionary, "fr079");
  db.remove_dataset(a);
  EXPECT_EQ(kept_counts(db), real_counts(path));
  EXPECT_TRUE(db.descriptor_sets().empty());
  EXPECT_EQ(db.summary().submap_count, 0);
}

TEST_F(MapDatabaseTest, SchemaVersionTwoIsSummarisedFromTheRowsReadOnlyAndMigratedForWriting) {
  const fs::path path = dir_ / "maps.db";
  std::string expected;
  {
    MapDatabase db = MapDatabase::open(path, Mode::kCreate);
    const std::int64_t a = db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(4, 10, 1));
    db.store_dataset({"b", "b.log", DatasetKind::kSubmaps, {}}, make_submaps(3, 5, 2));
    std::vector<DescriptorRecord> records;
    for (std::int64_t id : db.map_ids(a)) records.push_back({id, {Bytes(16, 0x11), 126}});
    db.put_descriptors("fr079", 3, codec42(), records);
    expected = kept_counts(db);
  }
  make_older(path, 2);
  {  // Read-only: left at version 2, the counts computed from the rows.
    const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
    EXPECT_FALSE(db.keeps_counts());
    EXPECT_FALSE(db.summary().counts_kept);
    EXPECT_EQ(db.summary().schema_version, 2);
    EXPECT_EQ(kept_counts(db), expected);
  }
  {  // Read-write: migrated, the counts filled and kept from then on.
    MapDatabase db = MapDatabase::open(path, Mode::kReadWrite);
    EXPECT_TRUE(db.keeps_counts());
    EXPECT_EQ(db.summary().schema_version, kMapDatabaseSchemaVersion);
    EXPECT_EQ(kept_counts(db), expected);
    db.remove_dataset(db.find_dataset("a")->id);
    EXPECT_EQ(kept_counts(db), real_counts(path));
  }
}

TEST_F(MapDatabaseTest, SchemaVersionThreeHasNoOriginsReadOnlyAndGetsAnEmptyColumnForWriting) {
  const fs::path path = dir_ / "maps.db";
  const Submaps submaps = make_submaps(3, 20, 4);
  ASSERT_FALSE(submaps[2].origins.empty());
  std::int64_t a = 0;
  {
    MapDatabase db = MapDatabase::open(path, Mode::kCreate);
    a = db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, submaps);
  }
  make_older(path, 3);
  {  // Read-only: left at version 3, its maps read without origins.
    const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
    EXPECT_EQ(db.summary().schema_version, 3);
    const Submaps loaded = db.load_submaps(a);
    ASSERT_EQ(loaded.size(), 3u);
    EXPECT_EQ(loaded[2].points, rounded_to_float(submaps[2].points));
    for (const Submap& m : loaded) EXPECT_TRUE(m.origins.empty());
  }
  {  // Read-write: migrated; the old maps have none, new ones keep theirs.
    MapDatabase db = MapDatabase::open(path, Mode::kReadWrite);
    EXPECT_EQ(db.summary().schema_version, kMapDatabaseSchemaVersion);
    const std::int64_t b = db.store_dataset({"b", "b.log", DatasetKind::kSubmaps, {}}, submaps);
    EXPECT_TRUE(db.load_submaps(a)[2].origins.empty());
    EXPECT_EQ(db.load_submaps(b)[2].origins, rounded_to_float(submaps[2].origins));
  }
  EXPECT_THAT(open_error(path), ::testing::IsEmpty());
}

TEST_F(MapDatabaseTest, DictionariesRoundTrip) {
  MapDatabase db = MapDatabase::open(dir_ / "maps.db", Mode::kCreate);
  Dictionary d;
  d.name = "fr079";
  d.source = "fr079.log";
  d.resolution = 0.1;
  d.alignment_angle = 0.25;
  d.T_world_dict = Pose2{3.0, -4.0, 0.5};
  d.points = make_submaps(1, 5000, 9)[0].points;
  d.metadata = R"({"scans": 4933})";
  db.add_dictionary(d);
  EXPECT_THROW(db.add_dictionary(d), InputError);
  d.name = "bad";
  d.metadata = "[1, 2]";
  EXPECT_THROW(db.add_dictionary(d), InputError);
  const Dictionary loaded = db.load_dictionary("fr079");
  EXPECT_EQ(loaded.points, rounded_to_float(d.points));
  EXPECT_EQ(loaded.T_world_dict.theta, 0.5);
  EXPECT_EQ(loaded.alignment_angle, 0.25);
  EXPECT_EQ(loaded.metadata, R"({"scans":4933})");
  ASSERT_EQ(db.dictionaries().size(), 1u);
  EXPECT_EQ(db.dictionaries()[0].point_count, 5000);
  EXPECT_THROW(db.load_dictionary("albert"), InputError);
  db.remove_dictionary("fr079");
  EXPECT_TRUE(db.dictionaries().empty());
}

TEST_F(MapDatabaseTest, TransactionRolledBackOnExceptionLeavesNoPartialDataset) {
  const fs::path path = dir_ / "maps.db";
  MapDatabase db = MapDatabase::open(path, Mode::kCreate);
  db.store_dataset({"kept", "k.log", DatasetKind::kSubmaps, {}}, make_submaps(2, 10, 1));
  try {
    MapDatabase::Transaction transaction(db);
    const std::int64_t id = db.add_dataset({"partial", "p.log", DatasetKind::kSubmaps, {}});
    db.add_submaps(id, make_submaps(3, 10, 2));
    throw std::runtime_error("interrupted");
  } catch (const std::runtime_error&) {
  }
  // A bad submap in the middle of a batch: the dataset and the submaps before it are rolled back too.
  Submaps bad = make_submaps(4, 10, 3);
  bad[2].travel = std::nan("");
  try {
    db.store_dataset({"bad", "b.log", DatasetKind::kSubmaps, {}}, bad);
    FAIL() << "NaN travel accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("submap 2: travel must be finite"));
  }
  bad[2].travel = 1.0;
  bad[3].points[5].x() = INFINITY;
  EXPECT_THROW(db.store_dataset({"bad", "b.log", DatasetKind::kSubmaps, {}}, bad), InputError);

  const MapDatabase reopened = MapDatabase::open(path, Mode::kReadOnly);
  ASSERT_EQ(reopened.datasets().size(), 1u);
  EXPECT_EQ(reopened.datasets()[0].spec.name, "kept");
  EXPECT_EQ(reopened.summary().submap_count, 2);
  EXPECT_FALSE(reopened.find_dataset("partial").has_value());
  // The connection is usable after the rollbacks.
  db.store_dataset({"bad", "b.log", DatasetKind::kSubmaps, {}}, make_submaps(1, 10, 4));
  EXPECT_EQ(db.summary().submap_count, 3);
}

TEST_F(MapDatabaseTest, ProcessKilledMidTransactionLeavesNoPartialDataset) {
  const fs::path path = dir_ / "maps.db";
  MapDatabase::open(path, Mode::kCreate)
      .store_dataset({"kept", "k.log", DatasetKind::kSubmaps, {}}, make_submaps(2, 10, 1));
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // ~10 MB in one transaction: more than SQLite's page cache, so pages spill into the file mid-way.
    MapDatabase db = MapDatabase::open(path, Mode::kReadWrite);
    MapDatabase::Transaction transaction(db);
    db.store_dataset({"partial", "p.log", DatasetKind::kSubmaps, {}}, make_submaps(2500, 500, 2));
    ::_exit(0);  // dies without commit or any destructor, like a killed process
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  ASSERT_TRUE(fs::exists(path.string() + "-journal"));  // a hot journal is left behind
  // Any reader with write access rolls the journal back, as SQLite does.
  const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
  EXPECT_FALSE(fs::exists(path.string() + "-journal"));
  db.check_integrity();
  ASSERT_EQ(db.datasets().size(), 1u);
  EXPECT_EQ(db.datasets()[0].spec.name, "kept");
  EXPECT_EQ(db.summary().submap_count, 2);
}

// Runs child_work in a child process and SIGKILLs it after delay_us microseconds (it may have finished by then).
void kill_child_after(const std::function<void()>& child_work, long delay_us) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    try {
      child_work();
    } catch (...) {
      ::_exit(2);
    }
    ::_exit(0);
  }
  ::usleep(static_cast<useconds_t>(delay_us));
  ::kill(child, SIGKILL);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << "the child failed before it was killed";
}

// The files of a folder other than the database itself (temporaries, journals).
std::vector<std::string> others_beside(const fs::path& path) {
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(path.parent_path())) {
    if (entry.path() != path) out.push_back(entry.path().filename().string());
  }
  return out;
}

TEST_F(MapDatabaseTest, WriterKilledAtAnyMomentLeavesTheLastCommittedState) {
  const fs::path path = dir_ / "maps.db";
  MapDatabase::open(path, Mode::kCreate);
  const Submaps submaps = make_submaps(200, 200, 5);  // ~320 KB a dataset: each commit takes a while
  const auto time_one = std::chrono::steady_clock::now();
  {
    MapDatabase db = MapDatabase::open(dir_ / "timing.db", Mode::kCreate);
    db.store_dataset({"timing", "t.log", DatasetKind::kSubmaps, {}}, submaps);
  }
  const auto one_us =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - time_one).count();
  fs::remove(dir_ / "timing.db");
  int next = 0;  // datasets are named d0, d1, ... in commit order
  // The child appends datasets one transaction each until it is killed, 0.3 .. 3 commits in; on a busy machine
  // (the suite runs in parallel) more rounds with longer delays, until a commit has survived.
  for (int round = 0; round < 10 || (next == 0 && round < 20); ++round) {
    const long delay = round < 10 ? one_us * (round + 1) * 3 / 10 : one_us * 3 * (1L << std::min(round - 9, 5));
    kill_child_after(
        [&] {
          MapDatabase db = MapDatabase::open(path, Mode::kReadWrite);
          for (int i = next;; ++i) db.store_dataset({"d" + std::to_string(i), "x.log", DatasetKind::kSubmaps, {}}, submaps);
        },
        delay);
    const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);  // rolls back a hot journal
    db.check_integrity();
    const std::vector<DatasetInfo> datasets = db.datasets();
    ASSERT_GE(static_cast<int>(datasets.size()), next) << "a committed dataset was lost";
    for (int i = 0; i < static_cast<int>(datasets.size()); ++i) {
      EXPECT_EQ(datasets[static_cast<std::size_t>(i)].spec.name, "d" + std::to_string(i));
      EXPECT_EQ(datasets[static_cast<std::size_t>(i)].submap_count, 200) << "a dataset was stored in part";
    }
    next = static_cast<int>(datasets.size());
    // Killed before its journal had a header, the writer leaves a journal that is not hot (first byte zero): SQLite
    // ignores it and the next write replaces it. Anything else beside the database would be an orphan.
    for (const std::string& name : others_beside(path)) {
      ASSERT_EQ(name, "maps.db-journal");
      std::ifstream journal(dir_ / name, std::ios::binary);
      const int first = journal.get();  // EOF for an empty journal
      EXPECT_TRUE(first == 0 || first == std::char_traits<char>::eof()) << "a hot journal was left";
    }
  }
  EXPECT_GT(next, 0);
  MapDatabase::open(path, Mode::kReadWrite).store_dataset({"last", "x.log", DatasetKind::kSubmaps, {}}, submaps);
  EXPECT_THAT(others_beside(path), ::testing::IsEmpty());
}

TEST_F(MapDatabaseTest, CreationKilledAtAnyMomentLeavesNoFileOrAValidOneAndNoOrphans) {
  const fs::path path = dir_ / "maps.db";
  const auto start = std::chrono::steady_clock::now();
  MapDatabase::open(dir_ / "timing.db", Mode::kCreate);
  const auto create_us =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - start).count();
  fs::remove(dir_ / "timing.db");
  int none = 0, valid = 0, orphaned = 0, round = 0;
  // 0 .. 3 times the time a creation takes; on a busy machine more rounds with longer delays, until both outcomes
  // were seen.
  for (; round < 24 || ((none == 0 || valid == 0) && round < 40); ++round) {
    const long delay = round < 24       ? create_us * round / 8
                       : round % 2 == 0 ? 0
                                        : create_us * 3 * (1L << std::min((round - 24) / 2, 6));
    kill_child_after([&] { MapDatabase::open(path, Mode::kCreate); }, delay);
    if (!others_beside(path).empty()) ++orphaned;
    if (fs::exists(path)) {
      const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
      db.check_integrity();
      EXPECT_TRUE(db.datasets().empty());
      ++valid;
    } else {
      ++none;
    }
    // Whatever the killed creator left beside the path is gone once the path is opened again.
    MapDatabase::open(path, Mode::kCreate);
    EXPECT_THAT(others_beside(path), ::testing::IsEmpty()) << "round " << round;
    fs::remove(path);
  }
  EXPECT_GT(none, 0);
  EXPECT_GT(valid, 0);
  std::printf("creation killed %d times: %d left no file, %d a valid one, %d temporaries beside it\n", round, none,
              valid, orphaned);
}

TEST_F(MapDatabaseTest, AbandonedTemporariesAreRemovedButNotOnesBeingBuilt) {
  const fs::path path = dir_ / "maps.db";
  // An abandoned creation: its temporary and journal, nobody holding its lock.
  const fs::path abandoned = dir_ / ".maps.db.new-dead";
  std::ofstream(abandoned) << "half a database";
  std::ofstream(abandoned.string() + "-journal") << "its journal";
  // One being built: locked by its creator (here, this process through another open file).
  const fs::path building = dir_ / ".maps.db.new-live";
  std::ofstream(building) << "";
  const int fd = ::open(building.c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX), 0);
  // Another database's temporaries and unrelated files are left alone.
  std::ofstream(dir_ / ".other.db.new-dead") << "";
  std::ofstream(dir_ / "maps.db.new-notes.txt") << "";
  MapDatabase::open(path, Mode::kCreate);
  EXPECT_FALSE(fs::exists(abandoned));
  EXPECT_FALSE(fs::exists(abandoned.string() + "-journal"));
  EXPECT_TRUE(fs::exists(building));
  EXPECT_TRUE(fs::exists(dir_ / ".other.db.new-dead"));
  EXPECT_TRUE(fs::exists(dir_ / "maps.db.new-notes.txt"));
  ::close(fd);
  MapDatabase::open(path, Mode::kReadOnly);  // any open cleans up
  EXPECT_FALSE(fs::exists(building));
}

TEST_F(MapDatabaseTest, ReadOnlyRefusesWritesAndMissingFilesAreNotCreated) {
  const fs::path path = dir_ / "maps.db";
  EXPECT_THAT(open_error(path, Mode::kReadOnly), HasSubstr("no such file"));
  EXPECT_THAT(open_error(path, Mode::kReadWrite), HasSubstr("no such file"));
  EXPECT_FALSE(fs::exists(path));
  EXPECT_THAT(open_error(dir_ / "no-folder" / "maps.db", Mode::kCreate), HasSubstr("does not exist"));
  EXPECT_THAT(open_error(dir_, Mode::kCreate), HasSubstr("not a regular file"));
  EXPECT_THAT(open_error(dir_ / std::string(5000, 'a'), Mode::kCreate), HasSubstr("File name too long"));
  EXPECT_THAT(open_error(dir_ / std::string(5000, 'a') / "maps.db", Mode::kCreate), HasSubstr("File name too long"));
  MapDatabase::open(path, Mode::kCreate);
  MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
  try {
    db.add_dataset({"a", "a.log", DatasetKind::kSubmaps, {}});
    FAIL() << "write to read-only database accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("read-only"));
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);  // no temporaries
}

// A database that cannot be written is refused when opened for writing (not after the command's work, at its
// first write), and still opens for reading. Root may write anything, so as root the check runs in a child
// process that has become nobody.
TEST_F(MapDatabaseTest, AnUnwritableFileOrFolderIsRefusedForWritingAndReadsStill) {
  using fs::perms;
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  const fs::path file = locked / "file.db", other = locked / "other.db";
  MapDatabase::open(file, Mode::kCreate).add_dataset({"a", "a.log", DatasetKind::kSubmaps, {}});
  MapDatabase::open(other, Mode::kCreate);
  const perms readable = perms::owner_read | perms::group_read | perms::others_read;
  const perms searchable = perms::owner_exec | perms::group_exec | perms::others_exec;
  fs::permissions(dir_, perms::owner_all | searchable);
  fs::permissions(file, readable);                                                                   // 0444
  fs::permissions(other, readable | perms::owner_write | perms::group_write | perms::others_write);  // 0666
  fs::permissions(locked, readable | searchable);                                                    // 0555
  // 0: as expected; 1: the write-protected file opened for writing; 2: so did the file in the locked
  // folder; 3: reading failed.
  const auto check = [&]() -> int {
    const auto refused = [](const fs::path& path, const std::string& message) {
      try {
        MapDatabase::open(path, Mode::kReadWrite);
        return false;
      } catch (const InputError& e) {
        return std::string(e.what()).find(message) != std::string::npos;
      }
    };
    if (!refused(file, "file.db: the file is write-protected")) return 1;
    if (!refused(other, "other.db: the folder " + locked.string() + " is not writable")) return 2;
    try {
      return MapDatabase::open(file, Mode::kReadOnly).find_dataset("a") ? 0 : 3;
    } catch (const InputError&) {
      return 3;
    }
  };
  int result = -1;
  if (::geteuid() != 0) {
    result = check();
  } else {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) _exit(::setgid(65534) == 0 && ::setuid(65534) == 0 ? check() : 4);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFEXITED(status));
    result = WEXITSTATUS(status);
  }
  fs::permissions(locked, perms::owner_all);
  EXPECT_EQ(result, 0);
}

TEST_F(MapDatabaseTest, RefusesNewerSchemaVersion) {
  const fs::path path = dir_ / "maps.db";
  MapDatabase::open(path, Mode::kCreate);
  sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite).exec("PRAGMA user_version = 5");
  const std::string error = open_error(path, Mode::kReadWrite);
  EXPECT_THAT(error, HasSubstr(path.string()));
  EXPECT_THAT(error, HasSubstr("schema version 5 is newer"));
}

TEST_F(MapDatabaseTest, RefusesForeignSqliteDatabase) {
  const fs::path path = dir_ / "other.sqlite";
  sqlite::Connection::open(path, sqlite::Connection::Access::kCreate)
      .exec("CREATE TABLE t (x); INSERT INTO t VALUES (1)");
  const std::string error = open_error(path, Mode::kCreate);
  EXPECT_THAT(error, HasSubstr(path.string()));
  EXPECT_THAT(error, HasSubstr("not a PartSLAM map database"));
  EXPECT_THAT(error, HasSubstr("application_id 0x00000000"));
}

TEST_F(MapDatabaseTest, RefusesGarbageAndEmptyFiles) {
  const fs::path garbage = dir_ / "garbage.db";
  std::ofstream(garbage) << "x,y\n1.0,2.0\n";
  EXPECT_THAT(open_error(garbage), HasSubstr("not an SQLite database"));
  const fs::path empty = dir_ / "empty.db";
  std::ofstream{empty};
  EXPECT_THAT(open_error(empty, Mode::kCreate), HasSubstr("empty file"));
}

TEST_F(MapDatabaseTest, RefusesTruncatedDatabase) {
  const fs::path path = dir_ / "maps.db";
  MapDatabase::open(path, Mode::kCreate)
      .store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(20, 500, 1));
  const auto size = fs::file_size(path);
  ASSERT_GT(size, 20u * 4000u);
  fs::resize_file(path, size / 2);
  const std::string error = open_error(path);
  EXPECT_THAT(error, HasSubstr(path.string()));
  EXPECT_THAT(error, HasSubstr("truncated database"));
  fs::resize_file(path, 50);
  EXPECT_THAT(open_error(path), HasSubstr("truncated SQLite database"));
}

TEST_F(MapDatabaseTest, CorruptContentGivesInputError) {
  const fs::path path = dir_ / "maps.db";
  {
    MapDatabase db = MapDatabase::open(path, Mode::kCreate);
    db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(3, 50, 1));
    db.check_integrity();
  }
  // A points blob whose length disagrees with its point count.
  sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite)
      .exec("UPDATE submaps SET points = substr(points, 1, 100) WHERE id = 2");
  const MapDatabase db = MapDatabase::open(path, Mode::kReadOnly);
  EXPECT_THAT([&] { db.load_submap(2); },
              ThrowsMessage<InputError>(HasSubstr("map 2: points blob holds 100 bytes, expected 400")));
  EXPECT_THROW(db.load_submaps(1), InputError);
  EXPECT_NO_THROW(db.load_submap(1));
  // An origins blob that is not whole points, and one with a point beyond the coordinate limit.
  {
    sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite)
        .exec("UPDATE submaps SET origins = x'0102030405' WHERE id = 3");
    const MapDatabase edited = MapDatabase::open(path, Mode::kReadOnly);
    EXPECT_THAT([&] { edited.load_submap(3); },
                ThrowsMessage<InputError>(HasSubstr("map 3: origins blob holds 5 bytes")));
    sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite)
        .exec("UPDATE submaps SET origins = x'0000807f00000000' WHERE id = 3");  // +inf, 0
    EXPECT_THROW(MapDatabase::open(path, Mode::kReadOnly).load_submap(3), InputError);
  }

  // Overwritten b-tree pages: SQLite's own errors come back as InputError naming the file.
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(4096);
    const std::string junk(static_cast<std::size_t>(fs::file_size(path)) - 8192, '\xff');
    f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  try {
    const MapDatabase broken = MapDatabase::open(path, Mode::kReadOnly);
    broken.check_integrity();
    broken.load_submaps(1);
    FAIL() << "corrupt pages accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
  }
}

// Values edited into a database with SQLite directly, as fuzz_map_database_values makes them: each read that meets
// one throws InputError (and runs without undefined behaviour under the sanitizers).
TEST_F(MapDatabaseTest, EditedValuesAreRefusedNotMisread) {
  const fs::path path = dir_ / "maps.db";
  {
    MapDatabase db = MapDatabase::open(path, Mode::kCreate);
    const std::int64_t ds = db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(3, 10, 1));
    db.put_descriptor(db.map_ids(ds)[0], "fr079", 3, codec42(), {Bytes{0xab, 1, 2, 3, 4, 0x3}, 42});
  }
  const auto edited = [&](const std::string& sql) {
    fs::copy_file(path, dir_ / "edited.db", fs::copy_options::overwrite_existing);
    sqlite::Connection::open(dir_ / "edited.db", sqlite::Connection::Access::kReadWrite).exec(sql);
    return MapDatabase::open(dir_ / "edited.db", Mode::kReadOnly);
  };
  // Descriptor bit counts beyond int (2^31 - 1 overflowed bits + 7) or negative.
  for (const char* bits : {"2147483647", "2147483641", "4294967338", "-1", "-9223372036854775808"}) {
    const MapDatabase db = edited(std::string("UPDATE descriptors SET bits = ") + bits);
    try {
      db.load_descriptors("fr079", 3);
      FAIL() << bits << " bits accepted";
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr("bits must hold")) << bits;
      EXPECT_THAT(e.what(), HasSubstr("(corrupt database)")) << bits;
    }
  }
}

TEST(BlobCodec, LittleEndianAndLengthChecked) {
  const Bytes bytes = encode_points_f32({{1.0, -2.0}}, "test");
  EXPECT_EQ(bytes, (Bytes{0x00, 0x00, 0x80, 0x3f, 0x00, 0x00, 0x00, 0xc0}));
  EXPECT_EQ(encode_f64({1.0}), (Bytes{0, 0, 0, 0, 0, 0, 0xf0, 0x3f}));
  EXPECT_EQ(decode_points_f32(bytes, 1, "test"), (Points2{{1.0, -2.0}}));
  EXPECT_THROW(decode_points_f32(bytes, 2, "test"), InputError);
  EXPECT_THROW(decode_f64(std::span(bytes).first(7), "test"), InputError);
  EXPECT_THROW(encode_points_f32({{1e39, 0.0}}, "test"), InputError);
  EXPECT_THROW(decode_points_f32(Bytes{0, 0, 0xc0, 0x7f, 0, 0, 0, 0}, 1, "test"), InputError);  // NaN
}

TEST_F(MapDatabaseTest, EditedPosesAndPointsAreRefusedOnRead) {
  const fs::path path = dir_ / "maps.db";
  std::int64_t id = 0;
  {
    MapDatabase db = MapDatabase::open(path, Mode::kCreate);
    id = db.map_ids(db.store_dataset({"a", "a.log", DatasetKind::kSubmaps, {}}, make_submaps(2, 10, 1)))[1];
  }
  {  // a point edited to FLT_MAX (little-endian float32 0x7f7fffff at the first x)
    auto c = sqlite::Connection::open(path, sqlite::Connection::Access::kReadWrite);
    c.exec("UPDATE submaps SET points = CAST(X'ffff7f7f' || substr(points, 5) AS BLOB) WHERE id = " + std::to_string(id - 1));
    c.exec("UPDATE submaps SET world_x = 9e999 WHERE id = " + std::to_string(id));
  }
  try {
    MapDatabase::open(path, Mode::kReadOnly).load_submap(id - 1);
    FAIL() << "a FLT_MAX point was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("point 0"));
    EXPECT_THAT(e.what(), HasSubstr("corrupt database"));
  }
  try {
    MapDatabase::open(path, Mode::kReadOnly).load_submap(id);
    FAIL() << "an infinite pose was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("map " + std::to_string(id)));
    EXPECT_THAT(e.what(), HasSubstr("T_world_map.x"));
    EXPECT_THAT(e.what(), HasSubstr("corrupt database"));
  }
}

TEST_F(MapDatabaseTest, NamesMustBeCleanUtf8) {
  MapDatabase db = MapDatabase::open(dir_ / "maps.db", Mode::kCreate);
  EXPECT_NO_THROW(db.add_dataset({"Gebäude 079 – Flur", "a.log", DatasetKind::kSubmaps, {}}));
  for (const std::string& bad : {std::string("bad\xffname"), std::string("a\tb"), std::string("\xc0\xaf"),
                                std::string("\xed\xa0\x80"), std::string("cut\xe2\x82")}) {
    EXPECT_THROW(db.add_dataset({bad, "a.log", DatasetKind::kSubmaps, {}}), InputError) << bad;
  }
  Dictionary d;
  d.name = "x\x01";
  d.resolution = 0.1;
  d.points = {{0, 0}};
  EXPECT_THROW(db.add_dictionary(d), InputError);
}

}  // namespace
}  // namespace partslam::io
