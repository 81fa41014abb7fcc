// libFuzzer target: the values stored in a map database (io/store/map_database.h). A small valid database (one
// dataset of three submaps, a dictionary, descriptor sets of K = 1, 3, 20) is built once; each input is decoded into
// edits of it made with SQLite directly — a column of a row set to an integer, real, text, blob or NULL (edge values
// included), a row deleted, the schema version changed — and the edited file is then opened read-only and every table
// read (fuzz_map_database.h, read_everything). Edits SQLite refuses (STRICT column types) are skipped.
#include <fuzzer/FuzzedDataProvider.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>

#include "fuzz/fuzz_map_database.h"

namespace {

struct Column {
  const char* name;
  char type;  // 'i' integer, 'r' real, 't' text, 'b' blob
};

struct Table {
  const char* name;
  const char* key;  // the primary key, to pick the n-th row
  std::vector<Column> columns;
};

const std::vector<Table>& tables() {
  static const std::vector<Table> kTables = {
      {"datasets", "id", {{"id", 'i'}, {"name", 't'}, {"source", 't'}, {"kind", 't'}, {"config", 't'}, {"created", 't'}}},
      {"submaps",
       "id",
       {{"id", 'i'},
        {"dataset_id", 'i'},
        {"idx", 'i'},
        {"anchor_scan", 'i'},
        {"anchor_timestamp", 'r'},
        {"travel", 'r'},
        {"alignment_angle", 'r'},
        {"world_x", 'r'},
        {"world_y", 'r'},
        {"world_theta", 'r'},
        {"point_count", 'i'},
        {"points", 'b'},
        {"scan_timestamps", 'b'},
        {"origins", 'b'}}},
      {"dictionaries",
       "id",
       {{"id", 'i'},
        {"name", 't'},
        {"source", 't'},
        {"resolution", 'r'},
        {"alignment_angle", 'r'},
        {"world_x", 'r'},
        {"world_y", 'r'},
        {"world_theta", 'r'},
        {"point_count", 'i'},
        {"points", 'b'},
        {"metadata", 't'},
        {"created", 't'}}},
      {"descriptors",
       "(dictionary, k, map_id)",
       {{"dictionary", 't'}, {"k", 'i'}, {"map_id", 'i'}, {"bits", 'i'}, {"data", 'b'}}},
      {"descriptor_codecs", "(dictionary, k)", {{"dictionary", 't'}, {"k", 'i'}, {"codec", 't'}}},
      {"dataset_counts", "dataset_id", {{"dataset_id", 'i'}, {"submaps", 'i'}, {"points", 'i'}}},
      {"descriptor_counts",
       "(dictionary, k)",
       {{"dictionary", 't'}, {"k", 'i'}, {"maps", 'i'}, {"bits", 'i'}}},
  };
  return kTables;
}

std::int64_t integer_value(FuzzedDataProvider& in) {
  static constexpr std::int64_t kEdges[] = {0,
                                            1,
                                            -1,
                                            2,
                                            3,
                                            20,
                                            44,
                                            std::numeric_limits<std::int32_t>::max(),
                                            std::numeric_limits<std::int32_t>::min(),
                                            std::int64_t{1} << 31,
                                            std::int64_t{1} << 32,
                                            std::int64_t{1} << 61,
                                            std::int64_t{1} << 62,
                                            std::numeric_limits<std::int64_t>::max(),
                                            std::numeric_limits<std::int64_t>::min()};
  if (in.ConsumeBool()) return kEdges[in.ConsumeIntegralInRange<std::size_t>(0, std::size(kEdges) - 1)];
  return in.ConsumeIntegral<std::int64_t>();
}

double real_value(FuzzedDataProvider& in) {
  static constexpr double kEdges[] = {0.0,
                                      -0.0,
                                      1e-300,
                                      0.05,
                                      1e5,
                                      1e300,
                                      -1e300,
                                      std::numeric_limits<double>::infinity(),
                                      -std::numeric_limits<double>::infinity(),
                                      std::numeric_limits<double>::quiet_NaN(),
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::denorm_min()};
  if (in.ConsumeBool()) return kEdges[in.ConsumeIntegralInRange<std::size_t>(0, std::size(kEdges) - 1)];
  return in.ConsumeFloatingPoint<double>();
}

// One edit of the database.
void edit(sqlite3* db, FuzzedDataProvider& in) {
  const std::uint8_t op = in.ConsumeIntegralInRange<std::uint8_t>(0, 15);
  if (op == 15) {
    const std::string sql = "PRAGMA user_version = " + std::to_string(in.ConsumeIntegralInRange<int>(0, 4));
    sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr);
    return;
  }
  const Table& table = tables()[in.ConsumeIntegralInRange<std::size_t>(0, tables().size() - 1)];
  const int row = in.ConsumeIntegralInRange<int>(0, 3);
  const std::string key = table.key;
  const std::string columns = key.front() == '(' ? key.substr(1, key.size() - 2) : key;
  const std::string which = " WHERE " + key + " IN (SELECT " + columns + " FROM " + table.name + " LIMIT 1 OFFSET " +
                            std::to_string(row) + ")";
  if (op == 14) {
    sqlite3_exec(db, ("DELETE FROM " + std::string(table.name) + which).c_str(), nullptr, nullptr, nullptr);
    return;
  }
  const Column& column = table.columns[in.ConsumeIntegralInRange<std::size_t>(0, table.columns.size() - 1)];
  // Mostly a value of the column's type; otherwise any type (STRICT refuses most, which is checked too).
  char type = column.type;
  if (in.ConsumeIntegralInRange<int>(0, 7) == 0) type = "irtbn"[in.ConsumeIntegralInRange<int>(0, 4)];
  sqlite3_stmt* stmt = nullptr;
  const std::string sql = "UPDATE " + std::string(table.name) + " SET " + column.name + " = ?1" + which;
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK) std::abort();
  switch (type) {
    case 'i':
      sqlite3_bind_int64(stmt, 1, integer_value(in));
      break;
    case 'r':
      sqlite3_bind_double(stmt, 1, real_value(in));
      break;
    case 't': {
      const std::string text = in.ConsumeRandomLengthString(256);
      sqlite3_bind_text64(stmt, 1, text.data(), text.size(), SQLITE_TRANSIENT, SQLITE_UTF8);
      break;
    }
    case 'b': {
      const std::string blob = in.ConsumeRandomLengthString(512);
      sqlite3_bind_blob64(stmt, 1, blob.data(), blob.size(), SQLITE_TRANSIENT);
      break;
    }
    default:
      sqlite3_bind_null(stmt, 1);
  }
  sqlite3_step(stmt);
  sqlite3_finalize(stmt);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace partslam;
  static const std::string base = [] {
    const std::filesystem::path path = fuzz::scratch_dir() / "base.db";
    std::filesystem::remove(path);
    fuzz::make_small_database(path);
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }();
  const auto path = fuzz::write_database(reinterpret_cast<const std::uint8_t*>(base.data()), base.size());
  FuzzedDataProvider in(data, size);
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) std::abort();
  sqlite3_exec(db, "PRAGMA journal_mode = OFF; PRAGMA synchronous = OFF; BEGIN", nullptr, nullptr, nullptr);
  for (int edits = 0; in.remaining_bytes() > 0 && edits < 16; ++edits) edit(db, in);
  if (sqlite3_exec(db, "COMMIT", nullptr, nullptr, nullptr) != SQLITE_OK) std::abort();
  sqlite3_close(db);
  fuzz::read_everything(path);
  return 0;
}
