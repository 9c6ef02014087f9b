#include "storage/migrations.hpp"

#include <charconv>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "storage/sqlite.hpp"

namespace hrisim::storage {
namespace embedded {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace embedded

namespace {

std::vector<Migration> load_embedded() {
  std::vector<Migration> migrations;
  for (int i = 0; i < embedded::kEmbeddedCount; ++i) {
    const auto& [name, sql] = embedded::kEmbedded[i];
    int version = 0;
    std::from_chars(name.data(), name.data() + name.size(), version);
    if (version != static_cast<int>(migrations.size()) + 1) {
      throw core::Error(core::ErrorCode::internal,
                        "migration " + std::string(name) + " is out of sequence: expected number " +
                            std::to_string(migrations.size() + 1));
    }
    migrations.push_back({version, name, sql});
  }
  return migrations;
}

}  // namespace

std::span<const Migration> schema_migrations() {
  static const std::vector<Migration> migrations = load_embedded();
  return migrations;
}

void migrate(Database& db, std::span<const Migration> migrations) {
  const int latest = migrations.empty() ? 0 : migrations.back().version;
  const auto current = static_cast<int>(db.scalar_integer("PRAGMA user_version"));
  if (current > latest) {
    throw core::Error(core::ErrorCode::storage,
                      "database schema version " + std::to_string(current) +
                          " is newer than this hrisim understands (" + std::to_string(latest) +
                          "); use a newer hrisim",
                      {{"schema_version", current}, {"supported_version", latest}});
  }
  if (current == latest) return;
  // Foreign keys are off while tables are rebuilt (SQLite's documented procedure for schema changes
  // ALTER TABLE cannot make); each migration is checked for dangling references before it commits.
  db.exec("PRAGMA foreign_keys=OFF");
  struct ForeignKeysBackOn {
    Database& db;
    ~ForeignKeysBackOn() {
      try {
        db.exec("PRAGMA foreign_keys=ON");
      } catch (const core::Error&) {
        // A connection that cannot set a pragma fails at its next statement, with its own message.
      }
    }
  } back_on{db};
  for (const Migration& migration : migrations) {
    if (migration.version <= current) continue;
    Transaction transaction(db);
    // Another process opening the same new file may have applied it while this one waited for the lock.
    if (db.scalar_integer("PRAGMA user_version") >= migration.version) continue;
    try {
      db.exec(migration.sql);
    } catch (const core::Error& e) {
      throw core::Error(core::ErrorCode::storage,
                        "migration " + std::string(migration.name) + " failed: " + e.what(),
                        {{"migration", migration.name}});
    }
    if (db.scalar_integer("SELECT count(*) FROM pragma_foreign_key_check") != 0) {
      throw core::Error(core::ErrorCode::storage, "migration " + std::string(migration.name) + " leaves rows with dangling references",
                        {{"migration", migration.name}});
    }
    db.exec("PRAGMA user_version = " + std::to_string(migration.version));
    transaction.commit();
  }
}

}  // namespace hrisim::storage
