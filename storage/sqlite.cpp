#include "storage/sqlite.hpp"

#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include "core/error.hpp"

namespace hrisim::storage {
namespace {

[[noreturn]] void fail(sqlite3* db, int rc, std::string_view what) {
  // Only a foreign database's connection has a work budget (Database::open_foreign) to interrupt it.
  if ((rc & 0xff) == SQLITE_INTERRUPT) {
    throw core::Error(core::ErrorCode::bad_request, std::string(what) + ": the database costs more work to read than its size allows");
  }
  const int extended = db ? sqlite3_extended_errcode(db) : rc;
  const std::string message = std::string(what) + ": " + (db ? sqlite3_errmsg(db) : sqlite3_errstr(rc));
  const auto code = (rc & 0xff) == SQLITE_CONSTRAINT ? core::ErrorCode::conflict : core::ErrorCode::storage;
  throw core::Error(code, message, {{"sqlite_code", extended}});
}

}  // namespace

Statement::Statement(sqlite3* db, std::string_view sql) : db_(db) {
  const int rc = sqlite3_prepare_v2(db_, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
  if (rc != SQLITE_OK) fail(db_, rc, "preparing SQL");
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement& Statement::bind(int index, std::string_view value) {
  const int rc = sqlite3_bind_text(stmt_, index, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) fail(db_, rc, "binding text");
  return *this;
}

Statement& Statement::bind_blob(int index, std::string_view bytes) {
  const int rc = sqlite3_bind_blob(stmt_, index, bytes.data(), static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) fail(db_, rc, "binding a blob");
  return *this;
}

Statement& Statement::bind(int index, std::int64_t value) {
  const int rc = sqlite3_bind_int64(stmt_, index, value);
  if (rc != SQLITE_OK) fail(db_, rc, "binding integer");
  return *this;
}

Statement& Statement::bind(int index, double value) {
  const int rc = sqlite3_bind_double(stmt_, index, value);
  if (rc != SQLITE_OK) fail(db_, rc, "binding real");
  return *this;
}

Statement& Statement::bind_null(int index) {
  const int rc = sqlite3_bind_null(stmt_, index);
  if (rc != SQLITE_OK) fail(db_, rc, "binding null");
  return *this;
}

Statement& Statement::bind(int index, const std::optional<std::string>& value) {
  return value ? bind(index, std::string_view(*value)) : bind_null(index);
}

Statement& Statement::bind(int index, const std::optional<double>& value) {
  return value ? bind(index, *value) : bind_null(index);
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  fail(db_, rc, "executing SQL");
}

void Statement::run() {
  while (step()) {
  }
  reset();
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

bool Statement::is_null(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }

std::string Statement::text(int column) const {
  const auto* chars = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
  return chars ? std::string(chars, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column))) : std::string();
}

std::string Statement::blob(int column) const {
  const auto* bytes = static_cast<const char*>(sqlite3_column_blob(stmt_, column));
  return bytes ? std::string(bytes, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column))) : std::string();
}

std::optional<std::string> Statement::optional_text(int column) const {
  if (is_null(column)) return std::nullopt;
  return text(column);
}

std::int64_t Statement::integer(int column) const { return sqlite3_column_int64(stmt_, column); }

double Statement::real(int column) const { return sqlite3_column_double(stmt_, column); }

std::optional<double> Statement::optional_real(int column) const {
  if (is_null(column)) return std::nullopt;
  return real(column);
}

Database::Database(const std::filesystem::path& path, int flags) {
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = "opening database " + path.string() + ": " + sqlite3_errstr(rc);
    sqlite3_close_v2(db_);
    throw core::Error(core::ErrorCode::storage, message, {{"path", path.string()}});
  }
  sqlite3_extended_result_codes(db_, 1);
}

std::unique_ptr<Database> Database::in_memory() {
  std::unique_ptr<Database> db(new Database(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_MEMORY));
  db->exec("PRAGMA foreign_keys=ON");
  return db;
}

namespace {

/// SQLite's progress handler: every kWorkCheckSteps virtual-machine steps, charged to the budget.
constexpr int kWorkCheckSteps = 1000;

int charge_work(void* budget) {
  auto& work = *static_cast<WorkBudget*>(budget);
  work.spent += kWorkCheckSteps;
  if (work.spent > work.steps) work.exhausted = true;
  return work.exhausted ? 1 : 0;
}

}  // namespace

namespace {

/// The URI of a file that nothing writes while it is open: SQLite then creates nothing beside it (no
/// shared-memory index) and takes no locks.
std::string immutable_uri(const std::filesystem::path& path) {
  std::string uri = "file:";
  for (const char c : std::filesystem::absolute(path).string()) {
    if (c == '%' || c == '?' || c == '#') {
      static constexpr char kHex[] = "0123456789ABCDEF";
      uri += '%';
      uri += kHex[(static_cast<unsigned char>(c) >> 4) & 0xF];
      uri += kHex[static_cast<unsigned char>(c) & 0xF];
    } else {
      uri += c;
    }
  }
  return uri + "?immutable=1";
}

}  // namespace

std::unique_ptr<Database> Database::open_foreign(const std::filesystem::path& path, bool writable, const ForeignLimits& limits, WorkBudget& work) {
  // A file read with an unfinished write-ahead log beside it is opened as SQLite opens a shared one,
  // so that what its log holds is read too; without one, it is opened immutable.
  std::error_code no_log;
  const bool has_log = std::filesystem::file_size(path.string() + "-wal", no_log) > 0 && !no_log;
  std::unique_ptr<Database> db(writable  ? new Database(path, SQLITE_OPEN_READWRITE)
                               : has_log ? new Database(path, SQLITE_OPEN_READONLY)
                                         : new Database(immutable_uri(path), SQLITE_OPEN_READONLY | SQLITE_OPEN_URI));
  sqlite3* handle = db->db_;
  const auto configure = [&](int option, int value) {
    if (sqlite3_db_config(handle, option, value, nullptr) != SQLITE_OK) fail(handle, SQLITE_ERROR, "configuring a foreign database");
  };
  configure(SQLITE_DBCONFIG_DEFENSIVE, 1);
  configure(SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0);
  configure(SQLITE_DBCONFIG_ENABLE_VIEW, 0);
  configure(SQLITE_DBCONFIG_ENABLE_TRIGGER, 0);
  configure(SQLITE_DBCONFIG_ENABLE_LOAD_EXTENSION, 0);
  // Bounds on what one statement or value of the file may be (sqlite3_limit); hrisim's own statements
  // are far below them.
  sqlite3_limit(handle, SQLITE_LIMIT_LENGTH, limits.value_bytes);
  sqlite3_limit(handle, SQLITE_LIMIT_SQL_LENGTH, 100000);
  sqlite3_limit(handle, SQLITE_LIMIT_COLUMN, 100);
  sqlite3_limit(handle, SQLITE_LIMIT_EXPR_DEPTH, 50);
  sqlite3_limit(handle, SQLITE_LIMIT_COMPOUND_SELECT, 10);
  sqlite3_limit(handle, SQLITE_LIMIT_VDBE_OP, 25000);
  sqlite3_limit(handle, SQLITE_LIMIT_FUNCTION_ARG, 8);
  sqlite3_limit(handle, SQLITE_LIMIT_ATTACHED, 1);  // VACUUM INTO attaches its copy
  sqlite3_limit(handle, SQLITE_LIMIT_LIKE_PATTERN_LENGTH, 50);
  sqlite3_limit(handle, SQLITE_LIMIT_VARIABLE_NUMBER, 32);
  sqlite3_limit(handle, SQLITE_LIMIT_TRIGGER_DEPTH, 1);
  sqlite3_progress_handler(handle, kWorkCheckSteps, charge_work, &work);
  db->exec("PRAGMA cell_size_check=ON; PRAGMA mmap_size=0; PRAGMA foreign_keys=ON;");
  return db;
}

void Database::trust_schema() {
  if (sqlite3_db_config(db_, SQLITE_DBCONFIG_TRUSTED_SCHEMA, 1, nullptr) != SQLITE_OK) fail(db_, SQLITE_ERROR, "configuring a foreign database");
  // A foreign file is only read, and its copy is scratch: nothing to keep through a crash. (Set once
  // the schema is trusted: the pragma reads it.)
  exec("PRAGMA synchronous=OFF");
}

namespace {

/// `path`, its parent folders made.
const std::filesystem::path& with_folders(const std::filesystem::path& path) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  return path;
}

}  // namespace

// A delegating constructor: once the delegate returns, the destructor closes the connection on a throw.
Database::Database(const std::filesystem::path& path) : Database(with_folders(path), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE) {
  sqlite3_busy_timeout(db_, kBusyTimeoutMs);
  if (scalar_text("PRAGMA journal_mode=WAL") != "wal") {
    throw core::Error(core::ErrorCode::storage, "database " + path.string() + " cannot use WAL journaling", {{"path", path.string()}});
  }
  exec("PRAGMA synchronous=NORMAL; PRAGMA foreign_keys=ON;");
}

Database::~Database() { sqlite3_close_v2(db_); }

void Database::exec(std::string_view sql) {
  const std::string statement(sql);
  char* message = nullptr;
  const int rc = sqlite3_exec(db_, statement.c_str(), nullptr, nullptr, &message);
  if (rc != SQLITE_OK) {
    sqlite3_free(message);
    fail(db_, rc, "executing SQL");
  }
}

std::int64_t Database::changes() const { return sqlite3_changes64(db_); }

std::int64_t Database::scalar_integer(std::string_view sql) {
  Statement statement = prepare(sql);
  return statement.step() ? statement.integer(0) : 0;
}

std::string Database::scalar_text(std::string_view sql) {
  Statement statement = prepare(sql);
  return statement.step() ? statement.text(0) : std::string();
}

Transaction::Transaction(Database& db) : db_(db) { db_.exec("BEGIN IMMEDIATE"); }

Transaction::~Transaction() {
  if (!done_) {
    try {
      db_.exec("ROLLBACK");
    } catch (...) {
      // The transaction is already gone (SQLite rolls back by itself on some errors).
    }
  }
}

void Transaction::commit() {
  db_.exec("COMMIT");
  done_ = true;
}

}  // namespace hrisim::storage
