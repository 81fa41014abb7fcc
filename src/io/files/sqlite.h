// A thin RAII layer over the SQLite C API (libsqlite3): a connection and prepared statements whose
// failures become InputError naming the database file and what went wrong. Used by the map database.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

struct sqlite3;
struct sqlite3_stmt;

namespace partslam::io::sqlite {

/// An open database connection (move-only). Extended result codes are on, busy timeout is 10 s.
class Connection {
 public:
  enum class Access { kReadOnly, kReadWrite, kCreate };

  /// Opens path; kCreate also creates a missing file. Throws InputError naming the file on failure.
  static Connection open(const std::filesystem::path& path, Access access);

  Connection(Connection&& other) noexcept;
  Connection& operator=(Connection&& other) noexcept;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  sqlite3* get() const { return db_; }
  const std::filesystem::path& path() const { return path_; }

  /// Runs one or more statements that return no rows.
  void exec(std::string_view sql) const;
  /// Runs a statement returning one integer (e.g. a PRAGMA).
  std::int64_t query_int(std::string_view sql) const;
  /// True while a transaction is open on this connection.
  bool in_transaction() const;
  /// Whether SQLite opened the main database read-only (a write-protected file opened for writing).
  bool read_only() const;

  /// Throws InputError "<file>: <what>: <sqlite message>" for result code rc.
  [[noreturn]] void fail(int rc, std::string_view what) const;

 private:
  Connection(sqlite3* db, std::filesystem::path path) : db_(db), path_(std::move(path)) {}
  sqlite3* db_ = nullptr;
  std::filesystem::path path_;
};

/// A prepared statement. Bind indices and column indices follow SQLite: binds from 1, columns from 0.
/// Bound blobs and strings are copied, so arguments may be temporaries.
class Statement {
 public:
  Statement(const Connection& db, std::string_view sql);
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement();

  Statement& bind_int(int index, std::int64_t value);
  Statement& bind_real(int index, double value);
  Statement& bind_text(int index, std::string_view value);
  Statement& bind_blob(int index, std::span<const std::uint8_t> value);

  /// Advances to the next row; false when the statement is done.
  bool step();
  /// Steps to completion, for statements that return no rows.
  void run();
  /// Makes the statement ready to run again (bindings are kept).
  void reset();

  bool is_null(int column) const;
  std::int64_t int64(int column) const;
  double real(int column) const;
  std::string text(int column) const;
  /// View of a blob column, valid until the next step/reset. Empty for NULL or zero-length blobs.
  std::span<const std::uint8_t> blob(int column) const;

 private:
  const Connection& db_;
  sqlite3_stmt* stmt_ = nullptr;
};

}  // namespace partslam::io::sqlite
