#pragma once
// Numbered schema migrations, applied in order at open; PRAGMA user_version records the last one.
#include <span>
#include <string_view>
#include <vector>

namespace hrisim::storage {

class Database;

struct Migration {
  int version;             ///< 1, 2, ... from the file name's number (0001_initial.sql → 1)
  std::string_view name;   ///< file name, for messages
  std::string_view sql;    ///< statements to run
};

/// The migrations shipped with this binary (storage/migrations/*.sql), in version order.
std::span<const Migration> schema_migrations();

/// Brings db up to the last of `migrations`, each migration in its own transaction together with its
/// user_version bump. A database newer than the last known migration is refused, not touched.
void migrate(Database& db, std::span<const Migration> migrations);

}  // namespace hrisim::storage
