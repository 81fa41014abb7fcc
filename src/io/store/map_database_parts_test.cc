// The map database's dictionaries and descriptor sets (io/store/map_database_parts.cc): put, get, replace,
// cascade, and each set keeping its codec.
#include "io/store/map_database.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>

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
using testing::make_submaps;
using testing::MapDatabaseTest;
using testing::rounded_to_float;

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

}  // namespace
}  // namespace partslam::io
