// The map database's datasets and submaps (io/store/map_database_submaps.cc): exact round trips, global ids, kept
// counts, and values that are refused.
#include "io/store/map_database.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"
#include "core/parts/descriptor_layout.h"
#include "io/files/sqlite.h"
#include "io/testing/map_database_fixture.h"

namespace partslam::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Mode = MapDatabase::Mode;
using testing::codec42;
using testing::kept_counts;
using testing::make_submaps;
using testing::MapDatabaseTest;
using testing::real_counts;
using testing::rounded_to_float;

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
