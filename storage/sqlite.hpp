#pragma once
// Thin RAII layer over the sqlite3 C API, private to the storage module: a connection that turns
// every failure into core::Error, and prepared statements with typed bind/read.
#include <cstdint>
#include <filesystem>
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

class Database {
 public:
  /// Opens (creating if needed, with parent folders) and configures the connection: WAL journal,
  /// synchronous=NORMAL, busy timeout, foreign keys on.
  explicit Database(const std::filesystem::path& path);
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
