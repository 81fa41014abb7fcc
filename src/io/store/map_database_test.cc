// Opening the map database (io/store/map_database.cc): files of older schema versions migrated, transactions and
// writers killed at any moment leaving the last committed state, and foreign, damaged, edited or unwritable files
// refused with the file named.
#include "io/store/map_database.h"

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
#include "io/files/sqlite.h"
#include "io/testing/map_database_fixture.h"

namespace partslam::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;
using Mode = MapDatabase::Mode;
using testing::codec42;
using testing::kept_counts;
using testing::make_older;
using testing::make_submaps;
using testing::MapDatabaseTest;
using testing::real_counts;
using testing::rounded_to_float;

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

}  // namespace
}  // namespace partslam::io
