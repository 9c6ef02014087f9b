#include "storage/foreign.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <mutex>
#include <tuple>
#include <vector>

#include "core/error.hpp"
#include "core/files.hpp"
#include "storage/migrations.hpp"
#include "storage/sqlite.hpp"
#include "storage/store.hpp"

namespace hrisim::storage {
namespace {

namespace fs = std::filesystem;

/// The first 16 bytes of every SQLite database file, its NUL included.
constexpr std::string_view kSqliteMagic("SQLite format 3\0", 16);

bool is_sqlite(std::string_view bytes) { return bytes.starts_with(kSqliteMagic); }

/// The private folders' names begin so: remove_abandoned_copies finds those of a killed process.
const std::string kFolderPrefix = "hrisim-foreign-";

using SchemaObject = std::tuple<std::string, std::string, std::string, std::string>;  // type, name, table, sql

/// Every object of a database's schema, by name.
std::vector<SchemaObject> schema_of(Database& db) {
  Statement select = db.prepare("SELECT type, name, tbl_name, coalesce(sql, '') FROM sqlite_schema ORDER BY name");
  std::vector<SchemaObject> objects;
  while (select.step()) objects.emplace_back(select.text(0), select.text(1), select.text(2), select.text(3));
  return objects;
}

/// The schema hrisim's migrations up to `version` make, as SQLite keeps it; made once per version.
const std::vector<SchemaObject>& migrations_schema(int version) {
  static std::mutex mutex;
  static std::map<int, std::vector<SchemaObject>> made;
  std::lock_guard lock(mutex);
  auto found = made.find(version);
  if (found == made.end()) {
    const std::unique_ptr<Database> reference = Database::in_memory();
    migrate(*reference, schema_migrations().first(static_cast<std::size_t>(version)));
    found = made.emplace(version, schema_of(*reference)).first;
  }
  return found->second;
}

[[noreturn]] void refuse(const std::string& name, const std::string& why) {
  throw core::Error(core::ErrorCode::bad_request, name + " " + why);
}

/// Refuses a file whose schema is not exactly the one some version of hrisim made: anything added (a
/// view, a trigger, a virtual table, another index) could run code or cost unbounded work on reading.
void check_schema(Database& db, const std::string& name) {
  const auto version = static_cast<int>(db.scalar_integer("PRAGMA user_version"));
  const int latest = static_cast<int>(schema_migrations().size());
  if (version < 1 || version > latest) {
    refuse(name, "is not a database of this hrisim: its schema version is " + std::to_string(version) + ", not 1 to " + std::to_string(latest));
  }
  std::vector<SchemaObject> found = schema_of(db);
  // SQLite's own statistics table (ANALYZE, PRAGMA optimize) holds numbers, no code.
  std::erase_if(found, [](const SchemaObject& object) { return std::get<1>(object) == "sqlite_stat1"; });
  const std::vector<SchemaObject>& expected = migrations_schema(version);
  if (found == expected) return;
  for (const SchemaObject& object : found) {
    if (std::find(expected.begin(), expected.end(), object) == expected.end()) {
      refuse(name, "has a schema hrisim did not make: its " + std::get<0>(object) + " '" + std::get<1>(object).substr(0, 64) +
                       "' is not in hrisim's schema version " + std::to_string(version));
    }
  }
  refuse(name, "lacks part of hrisim's schema version " + std::to_string(version));
}

}  // namespace

ForeignDatabase::ForeignDatabase(std::string name, fs::path folder)
    : name_(std::move(name)), folder_(std::move(folder)), work_(std::make_unique<WorkBudget>()) {}

ForeignDatabase::ForeignDatabase(ForeignDatabase&& other) noexcept
    : name_(std::move(other.name_)), folder_(std::move(other.folder_)), work_(std::move(other.work_)), store_(std::move(other.store_)) {
  other.folder_.clear();
}

ForeignDatabase::~ForeignDatabase() {
  store_.reset();  // closed before its file goes
  std::error_code ignored;
  if (!folder_.empty()) fs::remove_all(folder_, ignored);
}

Store& ForeignDatabase::store() { return *store_; }

std::uint64_t ForeignDatabase::work_spent() const { return work_->spent; }
std::uint64_t ForeignDatabase::work_budget() const { return work_->steps; }

int ForeignDatabase::remove_abandoned_copies() { return core::remove_folders_of_ended_processes(kFolderPrefix); }

ForeignDatabase ForeignDatabase::from_file(const fs::path& file, std::string name, std::uint64_t max_bytes) {
  std::error_code error;
  const std::uint64_t bytes = fs::file_size(file, error);
  if (error || !fs::is_regular_file(file)) refuse(name, "cannot be read: no such file");
  if (bytes > max_bytes) refuse(name, "is " + std::to_string(bytes) + " bytes, more than the " + std::to_string(max_bytes) + " a database to merge may be");
  ForeignDatabase database(std::move(name), core::make_private_temp_folder(kFolderPrefix));
  database.open(file, bytes);
  return database;
}

ForeignDatabase ForeignDatabase::from_bytes(std::string_view bytes, std::string name) {
  if (!is_sqlite(bytes)) refuse(name, "is not an SQLite database");  // before anything is written
  ForeignDatabase database(std::move(name), core::make_private_temp_folder(kFolderPrefix));
  const fs::path upload = database.folder_ / "upload.db";
  {
    std::ofstream out(upload, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out.flush()) throw core::Error(core::ErrorCode::storage, "the upload could not be written to a temporary file");
  }
  database.open(upload, bytes.size());
  return database;
}

void ForeignDatabase::open(const fs::path& source, std::uint64_t bytes) {
  work_->steps = kForeignWorkBase + kForeignWorkPerByte * bytes;
  char header[kSqliteMagic.size()] = {};
  std::ifstream(source, std::ios::binary).read(header, sizeof header);
  if (!is_sqlite(std::string_view(header, sizeof header))) refuse(name_, "is not an SQLite database");
  const fs::path copy = folder_ / "copy.db";
  try {
    // Read-only, the file is checked where it is and copied (its log included) into the private
    // folder; only the copy is opened for writing, to migrate it.
    {
      const std::unique_ptr<Database> original = Database::open_foreign(source, false, {}, *work_);
      check_schema(*original, name_);
      original->trust_schema();  // the schema is hrisim's own: its CHECKs may run
      const std::string check = original->scalar_text("PRAGMA quick_check");
      if (check != "ok") refuse(name_, "is damaged (SQLite's quick_check: " + check.substr(0, 200) + ")");
      original->prepare("VACUUM INTO ?1").bind(1, copy.string()).run();
    }
    std::unique_ptr<Database> private_copy = Database::open_foreign(copy, true, {}, *work_);
    private_copy->trust_schema();  // made by VACUUM INTO from the schema checked above
    store_ = std::make_unique<Store>(std::move(private_copy), schema_migrations());
  } catch (const core::Error& e) {
    if (e.code() == core::ErrorCode::bad_request) throw;
    refuse(name_, std::string("cannot be read: ") + e.what());
  }
}

}  // namespace hrisim::storage
