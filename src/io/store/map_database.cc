#include "io/store/map_database.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <fstream>
#include <random>
#include <system_error>
#include <utility>
#include <vector>

#include "core/error.h"
#include "io/files/atomic_file.h"
#include "io/store/map_database_internal.h"

namespace partslam::io {
namespace {

namespace fs = std::filesystem;
using sqlite::Connection;
using sqlite::Statement;

constexpr const char* kSchema = R"sql(
CREATE TABLE datasets (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  name TEXT NOT NULL UNIQUE,
  source TEXT NOT NULL,
  kind TEXT NOT NULL,
  config TEXT NOT NULL,
  created TEXT NOT NULL
) STRICT;
CREATE TABLE submaps (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  dataset_id INTEGER NOT NULL REFERENCES datasets(id) ON DELETE CASCADE,
  idx INTEGER NOT NULL,
  anchor_scan INTEGER NOT NULL,
  anchor_timestamp REAL NOT NULL,
  travel REAL NOT NULL,
  alignment_angle REAL NOT NULL,
  world_x REAL NOT NULL,
  world_y REAL NOT NULL,
  world_theta REAL NOT NULL,
  point_count INTEGER NOT NULL,
  points BLOB NOT NULL,
  scan_timestamps BLOB NOT NULL,
  origins BLOB NOT NULL DEFAULT x'',
  UNIQUE (dataset_id, idx)
) STRICT;
CREATE TABLE dictionaries (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  name TEXT NOT NULL UNIQUE,
  source TEXT NOT NULL,
  resolution REAL NOT NULL,
  alignment_angle REAL NOT NULL,
  world_x REAL NOT NULL,
  world_y REAL NOT NULL,
  world_theta REAL NOT NULL,
  point_count INTEGER NOT NULL,
  points BLOB NOT NULL,
  metadata TEXT NOT NULL,
  created TEXT NOT NULL
) STRICT;
CREATE TABLE descriptors (
  dictionary TEXT NOT NULL,
  k INTEGER NOT NULL,
  map_id INTEGER NOT NULL REFERENCES submaps(id) ON DELETE CASCADE,
  bits INTEGER NOT NULL,
  data BLOB NOT NULL,
  PRIMARY KEY (dictionary, k, map_id)
) STRICT, WITHOUT ROWID;
CREATE INDEX descriptors_by_map ON descriptors(map_id);
)sql";

// The tables of each schema version: version 2 added descriptor_codecs, version 3 the counts.
struct SchemaTable {
  const char* name;
  int since;
};
constexpr std::array<SchemaTable, 7> kTables = {{{"datasets", 1},
                                                 {"submaps", 1},
                                                 {"dictionaries", 1},
                                                 {"descriptors", 1},
                                                 {"descriptor_codecs", 2},
                                                 {"dataset_counts", 3},
                                                 {"descriptor_counts", 3}}};

std::uint32_t big_endian(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

bool has_journal(const fs::path& path) {
  std::error_code ec;
  for (const char* suffix : {"-journal", "-wal"}) {
    if (fs::file_size(path.string() + suffix, ec) > 0 && !ec) return true;
  }
  return false;
}

// Checks the 100-byte SQLite header before SQLite sees the file, for clear messages about files that are
// not databases or were cut short (SQLite itself would only say "file is not a database" or "malformed").
void check_header(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": cannot open for reading");
  std::array<unsigned char, 100> header{};
  in.read(reinterpret_cast<char*>(header.data()), header.size());
  const auto got = static_cast<std::size_t>(in.gcount());
  const std::string prefix = path.string() + ": ";
  if (got == 0) throw InputError(prefix + "empty file, not a PartSLAM map database");
  static constexpr char kMagic[] = "SQLite format 3";  // with its terminating NUL: 16 bytes
  if (got < sizeof(kMagic) || !std::equal(kMagic, kMagic + sizeof(kMagic), header.begin())) {
    throw InputError(prefix + "not an SQLite database (no SQLite header), so not a PartSLAM map database");
  }
  if (got < header.size()) {
    throw InputError(prefix + "truncated SQLite database (" + std::to_string(got) +
                     " bytes, shorter than its header)");
  }
  std::uint32_t page_size = (std::uint32_t{header[16]} << 8) | header[17];
  if (page_size == 1) page_size = 65536;
  if (page_size < 512 || (page_size & (page_size - 1)) != 0) {
    throw InputError(prefix + "corrupt SQLite header (page size " + std::to_string(page_size) + ")");
  }
  // The header's page count is valid when the change counter (offset 24) matches offset 92. A journal
  // beside the file means an interrupted write that SQLite will roll back, so the count may not hold yet.
  const std::uint32_t page_count = big_endian(&header[28]);
  const bool count_valid = page_count > 0 && big_endian(&header[24]) == big_endian(&header[92]);
  if (count_valid && !has_journal(path)) {
    const std::uintmax_t expected = std::uintmax_t{page_count} * page_size;
    std::error_code ec;
    const std::uintmax_t actual = fs::file_size(path, ec);
    if (!ec && actual < expected) {
      throw InputError(prefix + "truncated database: the file has " + std::to_string(actual) +
                       " bytes but its header declares " + std::to_string(page_count) + " pages of " +
                       std::to_string(page_size) + " bytes (" + std::to_string(expected) + " bytes)");
    }
  }
}

void require_table(const Connection& db, const char* table) {
  Statement find(db, "SELECT 1 FROM sqlite_schema WHERE type = 'table' AND name = ?1");
  if (!find.bind_text(1, table).step()) {
    throw InputError(db.path().string() + ": damaged PartSLAM map database: table '" + table + "' is missing");
  }
}

// Checks the application id and the tables of the file's schema version; returns that version.
int check_schema(const Connection& db) {
  const std::string prefix = db.path().string() + ": ";
  const auto application_id = static_cast<std::uint32_t>(db.query_int("PRAGMA application_id"));
  const std::int64_t version = db.query_int("PRAGMA user_version");
  if (application_id != static_cast<std::uint32_t>(kMapDatabaseApplicationId)) {
    char hex[16];
    std::snprintf(hex, sizeof(hex), "0x%08X", application_id);
    throw InputError(prefix + "an SQLite database of another application, not a PartSLAM map database " +
                     "(application_id " + hex + ", expected 0x50534C4D)");
  }
  if (version > kMapDatabaseSchemaVersion) {
    throw InputError(prefix + "schema version " + std::to_string(version) +
                     " is newer than this partslam supports (" + std::to_string(kMapDatabaseSchemaVersion) +
                     "); use a newer partslam");
  }
  if (version < 1) throw InputError(prefix + "unsupported schema version " + std::to_string(version));
  for (const SchemaTable& table : kTables) {
    if (version >= table.since) require_table(db, table.name);
  }
  return static_cast<int>(version);
}

// A database being created is built at ".<name>.new-<random>" beside its path, which its creator holds an exclusive
// flock() on until the file is linked into place; the kernel drops the lock when the creator dies, so a temporary
// whose lock can be taken was abandoned (a creator killed mid-way) and can go, with its journal.
std::string creating_prefix(const fs::path& path) { return "." + path.filename().string() + ".new-"; }

fs::path folder_of(const fs::path& path) { return path.parent_path().empty() ? fs::path(".") : path.parent_path(); }

// An open file descriptor, closed on destruction.
struct FileDescriptor {
  int fd = -1;
  FileDescriptor() = default;
  explicit FileDescriptor(int f) : fd(f) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// Removes the abandoned temporaries (and their journals) of databases created at path; best effort, silent.
void remove_abandoned_temporaries(const fs::path& path) {
  const std::string prefix = creating_prefix(path);
  std::error_code ec;
  std::vector<fs::path> found;
  for (auto it = fs::directory_iterator(folder_of(path), ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!name.starts_with(prefix)) continue;
    if (!name.ends_with("-journal")) {
      found.push_back(it->path());
    } else if (const std::string main = it->path().string(); !fs::exists(main.substr(0, main.size() - 8), ec)) {
      fs::remove(it->path(), ec);  // a journal whose temporary is gone
    }
  }
  for (const fs::path& tmp : found) {
    const FileDescriptor file(::open(tmp.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW));
    if (file.fd < 0 || ::flock(file.fd, LOCK_EX | LOCK_NB) != 0) continue;  // gone, or still being built
    fs::remove(tmp.string() + "-journal", ec);
    fs::remove(tmp, ec);
  }
}

// Creates and locks a new empty temporary for a database at path; returns its name.
fs::path create_locked_temporary(const fs::path& path, FileDescriptor& lock) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::random_device rd;
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string suffix;
    for (int i = 0; i < 12; ++i) suffix.push_back(kDigits[rd() % 16]);
    const fs::path tmp = folder_of(path) / (creating_prefix(path) + suffix);
    const int fd = ::open(tmp.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
      if (errno == EEXIST) continue;
      throw InputError(path.string() + ": cannot create database: " + std::generic_category().message(errno));
    }
    FileDescriptor file(fd);
    if (::flock(fd, LOCK_EX) != 0) {
      throw InputError(path.string() + ": cannot create database: cannot lock " + tmp.string() + ": " +
                       std::generic_category().message(errno));
    }
    // Another process cleaning up may have taken it for abandoned between open() and flock(): start again.
    struct stat opened {}, named {};
    if (::fstat(fd, &opened) != 0 || ::stat(tmp.c_str(), &named) != 0 || opened.st_ino != named.st_ino ||
        opened.st_dev != named.st_dev)
      continue;
    std::swap(lock.fd, file.fd);
    return tmp;
  }
  throw InputError(path.string() + ": cannot create database: no free temporary name beside it");
}

// Builds an empty database beside path and links it into place without replacing a file that another
// process may have created meanwhile. Killed at any moment, it leaves no file at path or a complete empty
// database, and at most a temporary that the next open of path removes.
void create_empty(const fs::path& path) {
  const fs::path folder = folder_of(path);
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    throw InputError(path.string() + ": cannot create database: folder " + folder.string() +
                     " does not exist");
  }
  FileDescriptor lock;
  const fs::path tmp = create_locked_temporary(path, lock);
  try {
    Connection db = Connection::open(tmp, Connection::Access::kCreate);
    db.exec("BEGIN");
    db.exec("PRAGMA application_id = " + std::to_string(kMapDatabaseApplicationId));
    db.exec("PRAGMA user_version = " + std::to_string(kMapDatabaseSchemaVersion));
    db.exec(kSchema);
    db.exec(internal::kCodecsTable);
    db.exec(internal::kCountsSchema);
    db.exec("COMMIT");
  } catch (const InputError& e) {
    fs::remove(tmp.string() + "-journal", ec);
    fs::remove(tmp, ec);
    throw InputError(path.string() + ": cannot create database (" + e.what() + ")");
  }
  fs::create_hard_link(tmp, path, ec);
  if (!ec || ec == std::errc::file_exists) {
    fs::remove(tmp, ec);
  } else {
    commit_temporary(tmp, path);  // no hard links on this file system
  }
  // The lock is released (closing the descriptor) only now: SQLite's connection is closed, so closing another
  // descriptor of the file cannot drop its POSIX locks.
}

}  // namespace

std::string to_string(DatasetKind kind) { return kind == DatasetKind::kSubmaps ? "submaps" : "dictionary"; }

DatasetKind parse_dataset_kind(const std::string& name) {
  if (name == "submaps") return DatasetKind::kSubmaps;
  if (name == "dictionary") return DatasetKind::kDictionary;
  throw InputError("dataset kind: expected submaps or dictionary, got '" + name + "'");
}

MapDatabase::MapDatabase(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
MapDatabase::MapDatabase(MapDatabase&&) noexcept = default;
MapDatabase& MapDatabase::operator=(MapDatabase&&) noexcept = default;
MapDatabase::~MapDatabase() = default;

namespace {

// A database opened for writing must be writable, file and folder (SQLite writes its journal beside it):
// said at the start, not after a command's work when its first write fails.
void require_writable_file(const Connection& db) {
  const fs::path& path = db.path();
  if (db.read_only())
    throw InputError(path.string() + ": the file is write-protected; this command stores into it");
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (::access(folder.c_str(), W_OK) != 0)
    throw InputError(path.string() + ": the folder " + folder.string() +
                     " is not writable (SQLite writes its journal beside the database)");
}

}  // namespace

MapDatabase MapDatabase::open(const fs::path& path, Mode mode) {
  remove_abandoned_temporaries(path);
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) throw InputError(path.string() + ": " + ec.message());
  if (!fs::exists(status)) {
    if (mode != Mode::kCreate) throw InputError(path.string() + ": no such file");
    create_empty(path);
  } else if (!fs::is_regular_file(status)) {
    throw InputError(path.string() + ": not a regular file");
  }
  check_header(path);
  // Opened read-write even for kReadOnly (SQLite falls back to read-only for a write-protected file), so
  // that a reader can roll back the hot journal of an interrupted write; kReadOnly is enforced above SQLite
  // (require_writable) and by PRAGMA query_only.
  const bool read_only = mode == Mode::kReadOnly;
  auto impl =
      std::make_unique<Impl>(Impl{Connection::open(path, Connection::Access::kReadWrite), read_only, 0, 0});
  impl->schema_version = check_schema(impl->db);
  if (!read_only) require_writable_file(impl->db);
  impl->db.exec("PRAGMA foreign_keys = ON");
  impl->db.exec("PRAGMA recursive_triggers = ON");  // REPLACE deletes keep the counts right (kCountsSchema)
  // Statement journals and savepoint sub-journals (in-transaction rollback only; the crash-safe rollback journal
  // stays a file) in memory: as temporary files their writes took half of the time of writing many maps in one
  // transaction (docs/NOTES.md, "A large database on disk").
  impl->db.exec("PRAGMA temp_store = MEMORY");
  if (impl->schema_version < kMapDatabaseSchemaVersion && !read_only) {
    internal::migrate_to_current(impl->db);
    impl->schema_version = check_schema(impl->db);
  }
  if (read_only) impl->db.exec("PRAGMA query_only = ON");
  return MapDatabase(std::move(impl));
}

const fs::path& MapDatabase::path() const { return impl_->db.path(); }

void MapDatabase::require_writable() const {
  if (impl_->read_only) throw InputError(path().string() + ": opened read-only, cannot write");
}

MapDatabase::Transaction::Transaction(MapDatabase& db) : db_(db) {
  db.require_writable();
  outermost_ = db.impl_->depth == 0;
  db.impl_->db.exec(outermost_ ? "BEGIN IMMEDIATE" : "SAVEPOINT partslam_nested");
  ++db.impl_->depth;
}

void MapDatabase::Transaction::commit() {
  if (done_) throw std::logic_error("MapDatabase::Transaction committed twice");
  db_.impl_->db.exec(outermost_ ? "COMMIT" : "RELEASE partslam_nested");
  done_ = true;
  --db_.impl_->depth;
}

MapDatabase::Transaction::~Transaction() {
  if (done_) return;
  --db_.impl_->depth;
  try {
    if (outermost_) {
      if (db_.impl_->db.in_transaction()) db_.impl_->db.exec("ROLLBACK");
    } else {
      db_.impl_->db.exec("ROLLBACK TO partslam_nested; RELEASE partslam_nested");
    }
  } catch (const InputError&) {
    // SQLite may already have rolled back (e.g. after a full disk); nothing else to undo.
  }
}

std::vector<DescriptorSetInfo> MapDatabase::descriptor_sets() const {
  const bool counted = impl_->schema_version >= 3;  // else (read-only older file): every row is read
  Statement query(impl_->db,
                  counted ? "SELECT dictionary, k, maps, CAST(bits AS REAL) / maps FROM descriptor_counts"
                            " WHERE maps > 0 ORDER BY dictionary, k"
                          : "SELECT dictionary, k, COUNT(*), AVG(bits) FROM descriptors GROUP BY dictionary, k "
                            "ORDER BY dictionary, k");
  std::vector<DescriptorSetInfo> sets;
  while (query.step()) {
    sets.push_back({query.text(0), static_cast<int>(query.int64(1)), query.int64(2), query.real(3)});
  }
  return sets;
}

bool MapDatabase::keeps_counts() const { return impl_->schema_version >= 3; }

DatabaseSummary MapDatabase::summary() const {
  DatabaseSummary s;
  s.schema_version = static_cast<int>(impl_->db.query_int("PRAGMA user_version"));
  s.counts_kept = keeps_counts();
  s.datasets = datasets();
  s.dictionaries = dictionaries();
  s.descriptor_sets = descriptor_sets();
  Statement totals(impl_->db, s.counts_kept
                                  ? "SELECT COALESCE(SUM(submaps), 0), COALESCE(SUM(points), 0) FROM dataset_counts"
                                  : "SELECT COUNT(*), COALESCE(SUM(point_count), 0) FROM submaps");
  totals.step();
  s.submap_count = totals.int64(0);
  s.point_count = totals.int64(1);
  return s;
}

void MapDatabase::check_integrity() const {
  Statement check(impl_->db, "PRAGMA quick_check");
  if (check.step() && check.text(0) != "ok") {
    throw InputError(path().string() + ": integrity check failed: " + check.text(0));
  }
}

}  // namespace partslam::io
