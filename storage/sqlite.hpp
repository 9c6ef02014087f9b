#pragma once
// Thin RAII layer over the sqlite3 C API, private to the storage module: a connection that turns
// every failure into core::Error, and prepared statements with typed bind/read.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

struct sqlite3;
struct sqlite3_stmt;

namespace hrisim::storage {

class Statement {
 public:
  Statement(sqlite3* db, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  /// Bind parameters by 1-based index.
  Statement& bind(int index, std::string_view value);
  Statement& bind(int index, const std::string& value) { return bind(index, std::string_view(value)); }
  Statement& bind(int index, std::int64_t value);
  Statement& bind(int index, double value);
  Statement& bind_null(int index);
  /// Binds bytes as a BLOB.
  Statement& bind_blob(int index, std::string_view bytes);
  Statement& bind(int index, const std::optional<std::string>& value);
  Statement& bind(int index, const std::optional<double>& value);

  /// Advances; true while a row is available.
  bool step();
  /// Runs to completion, for statements that return no rows; then resets for reuse.
  void run();
  void reset();

  bool is_null(int column) const;
  std::string text(int column) const;
  std::string blob(int column) const;
  std::optional<std::string> optional_text(int column) const;
  std::int64_t integer(int column) const;
  double real(int column) const;
  std::optional<double> optional_real(int column) const;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

/// Work a connection to a foreign database may do, counted in SQLite's virtual-machine steps over every
/// statement it runs; past it, the statement running fails (SQLITE_INTERRUPT) and `exhausted` is set.
struct WorkBudget {
  std::uint64_t steps = 0;
  std::uint64_t spent = 0;
  bool exhausted = false;
};

/// Values and statements a connection to a foreign database accepts (sqlite3_limit), beyond which
/// reading or preparing fails as a corrupt file would.
struct ForeignLimits {
  int value_bytes = 64 << 20;  ///< a string or blob: a scenario's source or file, a series
};

class Database {
 public:
  /// Opens (creating if needed, with parent folders) and configures the connection: WAL journal,
  /// synchronous=NORMAL, busy timeout, foreign keys on.
  explicit Database(const std::filesystem::path& path);
  /// A connection to a database that came from elsewhere, hardened as SQLite's guide to untrusted
  /// databases says: an existing file, read-only unless `writable`; defensive mode, the schema's
  /// functions untrusted, views and triggers disabled, cell sizes checked, no memory map, `limits`,
  /// and every statement's work counted against `work` (which must outlive the connection).
  static std::unique_ptr<Database> open_foreign(const std::filesystem::path& path, bool writable, const ForeignLimits& limits, WorkBudget& work);
  /// Trusts the schema's functions again (SQLITE_DBCONFIG_TRUSTED_SCHEMA): only once a foreign file's
  /// schema was found to be exactly hrisim's own, whose CHECK constraints call json_valid(); and
  /// stops syncing to disk (the file is only read, its copy is scratch).
  void trust_schema();
  /// An empty database in memory, configured as a file's (foreign keys on): a migrations' reference.
  static std::unique_ptr<Database> in_memory();
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  void exec(std::string_view sql);
  Statement prepare(std::string_view sql) { return Statement(db_, sql); }
  std::int64_t scalar_integer(std::string_view sql);
  /// Rows the last INSERT, UPDATE or DELETE changed.
  std::int64_t changes() const;
  std::string scalar_text(std::string_view sql);

 private:
  Database(const std::filesystem::path& path, int flags);
  sqlite3* db_ = nullptr;
};

/// RAII transaction: BEGIN IMMEDIATE on construction, ROLLBACK unless commit() was called.
class Transaction {
 public:
  explicit Transaction(Database& db);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void commit();

 private:
  Database& db_;
  bool done_ = false;
};

/// Busy timeout applied to every connection, in milliseconds: how long a writer waits for another.
inline constexpr int kBusyTimeoutMs = 5000;

}  // namespace hrisim::storage
