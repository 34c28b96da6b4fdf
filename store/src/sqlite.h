#pragma once
// A thin RAII layer over the SQLite C API: a connection and prepared statements with bound
// parameters (values are always bound, never spliced into SQL text).
#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace podium::store {

class Statement {
 public:
  Statement(sqlite3* db, const char* sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  Statement& bind(int index, std::int64_t value);
  Statement& bind(int index, double value);
  Statement& bind(int index, const std::string& value);
  Statement& bind_null(int index);
  Statement& bind(int index, const std::optional<std::string>& value) { return value ? bind(index, *value) : bind_null(index); }
  /// Advances; true while a row is available.
  bool step();
  /// Runs a statement that returns no rows, then resets it for reuse.
  void run();
  void reset();

  std::int64_t int64(int column) const;
  double real(int column) const;
  std::string text(int column) const;
  bool is_null(int column) const;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

/// Throws base::RuntimeError with SQLite's message for a failed call.
void check_sqlite(sqlite3* db, int rc, const char* what);

/// Opens an existing database for reading. A WAL database's readers need its -shm file, which
/// SQLite cannot create on a read-only filesystem (a results archive, a read-only NFS export):
/// then, if no -wal file exists (every transaction is in the database file itself), it is opened
/// with SQLite's `immutable=1` URI parameter (no -shm, no locks; sqlite.org/uri.html). Throws
/// base::RuntimeError naming the file.
sqlite3* open_for_reading(const std::filesystem::path& path);

}  // namespace podium::store
