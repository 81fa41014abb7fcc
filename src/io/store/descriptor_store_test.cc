#include "io/store/descriptor_store.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <random>

#include "core/error.h"
#include "core/parts/descriptor_layout.h"
#include "io/files/sqlite.h"

namespace partslam::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class DescriptorStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = fs::temp_directory_path() / ("partslam_store_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".db");
    fs::remove(path_);
  }
  void TearDown() override {
    fs::remove(path_);
    fs::remove(path_.string() + "-journal");
  }

  // A database of `maps` submaps with K = 3 descriptors of 0..3 random parts (most of them 3) against a
  // 30 m x 20 m dictionary; returns the set's codec.
  CodecConfig fill(int maps) {
    MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kCreate);
    Dictionary d;
    d.name = "dict";
    d.source = "test";
    d.resolution = 0.1;
    d.points = {{0.0, 0.0}, {30.0, 20.0}, {12.0, 7.0}};
    db.add_dictionary(d);
    Submaps submaps(static_cast<std::size_t>(maps));
    for (Submap& m : submaps) m.points = {{0.5, 0.5}};
    const std::vector<std::int64_t> ids =
        db.map_ids(db.store_dataset({"maps", "test", DatasetKind::kSubmaps, {}}, submaps));
    const CodecConfig codec = descriptor_codec_config(d.points, 3);
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> corner(-60, 40), side(3, 24), rotation(0, 3), lattice(0, 60);
    std::discrete_distribution<int> parts({1, 1, 2, 16});
    const Vec2 step = origin_step(codec);
    std::vector<DescriptorRecord> records;
    for (std::int64_t id : ids) {
      MapDescriptor m;
      for (int j = parts(rng); j > 0; --j) {
        const double x0 = 0.1 * corner(rng), y0 = 0.1 * corner(rng);
        const Box2 keypoint{x0, x0 + 0.1 * side(rng), y0, y0 + 0.1 * side(rng)};
        const int r = rotation(rng);
        const Vec2 origin(codec.dictionary_extent.x_min + step.x() * lattice(rng),
                          codec.dictionary_extent.y_min + step.y() * lattice(rng));
        m.parts.push_back({keypoint, place_rotated_box(keypoint, r, origin), 1.0, r});
      }
      records.push_back({id, encode(m, codec)});
    }
    db.put_descriptors("dict", 3, codec, records);
    return codec;
  }

  fs::path path_;
};

TEST_F(DescriptorStoreTest, StreamedMatcherGivesTheScoresOfTheDecodedSet) {
  fill(300);
  const MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kReadOnly);
  const std::map<std::int64_t, MapDescriptor> set = load_descriptor_set(db, "dict", 3);
  ASSERT_EQ(set.size(), 300u);
  std::vector<std::int64_t> ids;
  std::vector<MapDescriptor> maps;
  for (const auto& [id, d] : set) {
    ids.push_back(id);
    maps.push_back(d);
  }
  for (const bool spatial : {true, false}) {
    DescriptorDatabaseConfig config;
    config.spatial_order = spatial;
    const DescriptorDatabase reference(maps, config);
    const LoadedDescriptors loaded = load_descriptor_database(db, "dict", 3, config);
    EXPECT_EQ(loaded.map_ids, ids);
    ASSERT_EQ(loaded.database.size(), reference.size());
    EXPECT_EQ(loaded.database.memory_bytes(), reference.memory_bytes());
    for (std::size_t q : {0u, 17u, 150u, 299u}) {
      for (const Matcher matcher : {Matcher::kMaxMax, Matcher::kSumMax, Matcher::kSumMaxWeighted}) {
        for (const double gate : {0.0, 2.0}) {
          const std::vector<float> want = reference.score_all(maps[q], matcher, {1, gate});
          EXPECT_EQ(loaded.database.score_all(maps[q], matcher, {1, gate}), want);
          std::vector<float> reused(7, 9.0f);  // the overload that reuses a buffer: same scores
          loaded.database.score_all(maps[q], matcher, {1, gate}, reused);
          EXPECT_EQ(reused, want);
          if (!maps[q].parts.empty()) {
            EXPECT_GT(want[q], 0.0f);  // it finds itself
          }
        }
      }
    }
  }
  // No such set: empty. Fewer slots than K: refused.
  EXPECT_TRUE(load_descriptor_database(db, "dict", 2, {}).map_ids.empty());
  DescriptorDatabaseConfig two;
  two.parts_per_map = 2;
  EXPECT_THROW(load_descriptor_database(db, "dict", 3, two), InputError);
}

TEST_F(DescriptorStoreTest, StreamedMatcherNamesTheFileAndMapOfABadRow) {
  fill(20);
  std::int64_t bad = 0;
  {
    const sqlite::Connection raw = sqlite::Connection::open(path_, sqlite::Connection::Access::kReadWrite);
    bad = raw.query_int("SELECT map_id FROM descriptors ORDER BY map_id LIMIT 1 OFFSET 5");
    raw.exec("UPDATE descriptors SET data = x'00' WHERE map_id = " + std::to_string(bad));  // size != bits
  }
  const MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kReadOnly);
  try {
    load_descriptor_database(db, "dict", 3, {});
    FAIL() << "a bad row was loaded";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path_.string()));
    EXPECT_THAT(e.what(), HasSubstr("descriptor of map " + std::to_string(bad)));
  }
  {  // bits and size agree, but the row holds more parts than K = 3
    const sqlite::Connection raw = sqlite::Connection::open(path_, sqlite::Connection::Access::kReadWrite);
    raw.exec("UPDATE descriptors SET bits = 176, data = zeroblob(22) WHERE map_id = " + std::to_string(bad));
  }
  try {
    load_descriptor_database(MapDatabase::open(path_, MapDatabase::Mode::kReadOnly), "dict", 3, {});
    FAIL() << "a row of 4 parts was loaded under K = 3";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("descriptor of map " + std::to_string(bad)));
  }
}

// Without a name, the only dictionary; none or several is an error in the library's words (no CLI flag).
TEST_F(DescriptorStoreTest, ResolvesTheOnlyDictionaryAndNamesWhatIsMissingOrAmbiguous) {
  {
    MapDatabase::open(path_, MapDatabase::Mode::kCreate);
    try {
      resolve_dictionary(MapDatabase::open(path_, MapDatabase::Mode::kReadOnly), "");
      FAIL() << "a dictionary was resolved in an empty database";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()),
                path_.string() + ": no dictionary stored (MapDatabase::add_dictionary stores one)");
    }
  }
  fill(2);
  EXPECT_EQ(resolve_dictionary(MapDatabase::open(path_, MapDatabase::Mode::kReadOnly), "").name, "dict");
  {
    MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kReadWrite);
    Dictionary other;
    other.name = "other";
    other.source = "test";
    other.resolution = 0.1;
    other.points = {{0.0, 0.0}, {1.0, 1.0}};
    db.add_dictionary(other);
  }
  const MapDatabase db = MapDatabase::open(path_, MapDatabase::Mode::kReadOnly);
  EXPECT_EQ(resolve_dictionary(db, "other").name, "other");
  try {
    resolve_dictionary(db, "");
    FAIL() << "one of two dictionaries was resolved without a name";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), path_.string() + ": several dictionaries (dict, other): name the one to use");
  }
}

}  // namespace
}  // namespace partslam::io
