// Fuzz target: a results database as `POST /api/v1/runs/import` receives it — checked, copied and
// merged into a server's store (storage::ForeignDatabase, runs::merge_database) — as SQLite's own
// dbsqlfuzz mutates database files. Under libFuzzer a custom mutator also makes structure-aware
// changes: it opens the input as a database and sets one cell of one of hrisim's tables to a value
// chosen to hurt (deep JSON, a path, a huge or negative number, NUL, text of another kind), or adds a
// view, trigger or index, so that the checks behind the schema's are reached, not only SQLite's.
#include <sqlite3.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <string>

#include "core/error.hpp"
#include "runs/merge.hpp"
#include "storage/foreign.hpp"
#include "storage/store.hpp"

namespace {

/// The server's store the inputs are merged into: one for the whole run, in a folder of its own.
hrisim::storage::Store& target() {
  static const std::filesystem::path folder = [] {
    auto made = std::filesystem::temp_directory_path() / ("hrisim-fuzz-import-" + std::to_string(::getpid()));
    std::filesystem::create_directories(made);
    return made;
  }();
  static hrisim::storage::Store store(folder / "target.db");
  return store;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    hrisim::storage::ForeignDatabase source = hrisim::storage::ForeignDatabase::from_bytes(bytes, "the uploaded database");
    hrisim::runs::merge_database(target(), source, "this server's", std::string("fuzz"));
  } catch (const hrisim::core::Error& e) {
    // A refusal names what is wrong; a crash, a hang or another exception is a finding. A store that
    // the import damaged would fail its next write: storage errors are findings too.
    if (e.code() == hrisim::core::ErrorCode::storage || e.code() == hrisim::core::ErrorCode::internal) {
      if (std::string_view(e.what()).find("uploaded database") == std::string_view::npos) throw;
    }
  }
  return 0;
}

#ifdef HRISIM_WITH_LIBFUZZER
extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size);

namespace {

/// Statements that change one part of a results file, each with a `?1` for a hurtful value where it
/// takes one; chosen at random.
constexpr const char* kChanges[] = {
    "UPDATE runs SET config = ?1",
    "UPDATE runs SET config = json_set(config, '$.seeds', json(?1))",
    "UPDATE runs SET config = json_set(config, '$.gates', json_array(?1))",
    "UPDATE runs SET config = json_set(config, '$.controller', json(?1))",
    "UPDATE runs SET id = ?1",
    "UPDATE runs SET name = ?1",
    "UPDATE runs SET tags = ?1",
    "UPDATE runs SET scenario_id = ?1",
    "UPDATE episodes SET seed = ?1",
    "UPDATE episodes SET id = ?1",
    "UPDATE episodes SET run_id = ?1",
    "UPDATE events SET data = ?1",
    "UPDATE metric_values SET value = ?1",
    "UPDATE metric_values SET key = ?1",
    "UPDATE trajectory_samples SET x = ?1",
    "UPDATE metric_series SET name = ?1",
    "UPDATE scenarios SET id = ?1",
    "UPDATE scenarios SET source = ?1",
    "UPDATE scenarios SET owner = ?1",
    "INSERT INTO scenario_files (scenario_id, path, content) SELECT id, ?1, 'x' FROM scenarios",
    "CREATE VIEW v AS SELECT ?1",
    "CREATE TRIGGER t AFTER INSERT ON runs BEGIN SELECT 1; END",
    "CREATE INDEX extra ON runs (name)",
    "DROP TABLE events",
};

std::string hurtful_value(std::mt19937& random) {
  switch (random() % 10) {
    case 0: return std::string(200, '[') + std::string(200, ']');
    case 1: return "../../../tmp/x";
    case 2: return "/etc/passwd";
    case 3: return "-1";
    case 4: return "1e308";
    case 5: return std::string("a\0b", 3);
    case 6: return "[1,1]";
    case 7: return "{\"type\":\"goal\",\"goal\":{\"location\":\"x\"}}";
    case 8: return "r0123456789abcdef0123456789abcdef";
    default: return std::string(random() % 5000, 'x');
  }
}

/// The input as a database changed by one statement of kChanges; false when it is no database.
bool change_as_database(std::uint8_t* data, std::size_t& size, std::size_t max_size, std::mt19937& random) {
  sqlite3* db = nullptr;
  if (sqlite3_open(":memory:", &db) != SQLITE_OK) return false;
  const std::unique_ptr<sqlite3, decltype(&sqlite3_close)> closer(db, sqlite3_close);
  auto* copy = static_cast<unsigned char*>(sqlite3_malloc64(size));
  if (!copy) return false;
  std::memcpy(copy, data, size);
  if (sqlite3_deserialize(db, "main", copy, static_cast<sqlite3_int64>(size), static_cast<sqlite3_int64>(size),
                          SQLITE_DESERIALIZE_FREEONCLOSE | SQLITE_DESERIALIZE_RESIZEABLE) != SQLITE_OK) {
    return false;
  }
  sqlite3_exec(db, "PRAGMA ignore_check_constraints=ON; PRAGMA foreign_keys=OFF;", nullptr, nullptr, nullptr);
  sqlite3_stmt* change = nullptr;
  if (sqlite3_prepare_v2(db, kChanges[random() % std::size(kChanges)], -1, &change, nullptr) != SQLITE_OK) return false;
  const std::string value = hurtful_value(random);
  if (sqlite3_bind_parameter_count(change) > 0) sqlite3_bind_text(change, 1, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT);
  sqlite3_step(change);
  sqlite3_finalize(change);
  sqlite3_int64 length = 0;
  unsigned char* out = sqlite3_serialize(db, "main", &length, 0);
  if (!out) return false;
  const bool fits = static_cast<std::size_t>(length) <= max_size;
  if (fits) {
    std::memcpy(data, out, static_cast<std::size_t>(length));
    size = static_cast<std::size_t>(length);
  }
  sqlite3_free(out);
  return fits;
}

}  // namespace

extern "C" std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size, std::size_t max_size, unsigned int seed) {
  std::mt19937 random(seed);
  if (random() % 2 == 0 && change_as_database(data, size, max_size, random)) return size;
  return LLVMFuzzerMutate(data, size, max_size);
}
#endif
