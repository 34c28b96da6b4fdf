#include "sqlite.h"

#include <cctype>
#include <cstdio>

#include "podium/base/error.h"

namespace podium::store {

void check_sqlite(sqlite3* db, int rc, const char* what) {
  if (rc == SQLITE_OK || rc == SQLITE_ROW || rc == SQLITE_DONE) return;
  throw base::RuntimeError(std::string("database: ") + what + ": " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc)));
}

Statement::Statement(sqlite3* db, const char* sql) : db_(db) {
  check_sqlite(db, sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr), sql);
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement& Statement::bind(int index, std::int64_t value) {
  check_sqlite(db_, sqlite3_bind_int64(stmt_, index, value), "bind");
  return *this;
}
Statement& Statement::bind(int index, double value) {
  check_sqlite(db_, sqlite3_bind_double(stmt_, index, value), "bind");
  return *this;
}
Statement& Statement::bind(int index, const std::string& value) {
  check_sqlite(db_, sqlite3_bind_text(stmt_, index, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT), "bind");
  return *this;
}
Statement& Statement::bind_null(int index) {
  check_sqlite(db_, sqlite3_bind_null(stmt_, index), "bind");
  return *this;
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  const std::string message = sqlite3_errmsg(db_);
  sqlite3_reset(stmt_);
  throw base::RuntimeError("database: " + message);
}

void Statement::run() {
  step();
  reset();
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

std::int64_t Statement::int64(int column) const { return sqlite3_column_int64(stmt_, column); }
double Statement::real(int column) const { return sqlite3_column_double(stmt_, column); }
std::string Statement::text(int column) const {
  const auto* p = sqlite3_column_text(stmt_, column);
  return p ? std::string(reinterpret_cast<const char*>(p), sqlite3_column_bytes(stmt_, column)) : std::string();
}
bool Statement::is_null(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }

namespace {

// A file: URI for `path` (RFC 3986 unreserved bytes and '/' kept, the rest percent-encoded).
std::string file_uri(const std::filesystem::path& path) {
  std::string out = "file:";
  for (const char ch : std::filesystem::absolute(path).string()) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || ch == '/' || ch == '-' || ch == '.' || ch == '_' || ch == '~') {
      out += ch;
    } else {
      char escaped[4];
      std::snprintf(escaped, sizeof escaped, "%%%02X", c);
      out += escaped;
    }
  }
  return out;
}

// Opens and reads the schema once (the first read is where a missing -shm shows); the SQLite
// result code, with the connection closed on failure. The busy timeout is set before that read:
// after a writer was killed, the first connection to open the file recovers its WAL under an
// exclusive lock, and a reader arriving meanwhile (a scheduler restarting beside `podium status`)
// would otherwise fail at once with "database is locked".
int try_open(const std::string& name, int flags, sqlite3** db) {
  int rc = sqlite3_open_v2(name.c_str(), db, flags | SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc == SQLITE_OK) rc = sqlite3_busy_timeout(*db, 10000);
  if (rc == SQLITE_OK) rc = sqlite3_exec(*db, "SELECT count(*) FROM sqlite_master", nullptr, nullptr, nullptr);
  if (rc != SQLITE_OK) {
    sqlite3_close_v2(*db);
    *db = nullptr;
  }
  return rc;
}

}  // namespace

sqlite3* open_for_reading(const std::filesystem::path& path) {
  sqlite3* db = nullptr;
  int rc = try_open(path.string(), 0, &db);
  const std::filesystem::path wal = path.string() + "-wal";
  std::error_code ignored;
  if (rc == SQLITE_CANTOPEN && !std::filesystem::exists(wal, ignored))
    rc = try_open(file_uri(path) + "?immutable=1", SQLITE_OPEN_URI, &db);
  if (rc != SQLITE_OK) throw base::RuntimeError(path.string() + ": cannot open database: " + sqlite3_errstr(rc));
  return db;
}

}  // namespace podium::store
