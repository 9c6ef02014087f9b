#pragma once
// A results database that came from elsewhere — an import's upload, a shard's file to merge, a file
// given to `serve --import` — opened the one way such a file is: checked, copied and read within
// bounds, never written. SQLite's guide "Defense Against The Dark Arts" is the checklist.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace hrisim::storage {

class Store;
struct WorkBudget;

/// Largest foreign database file read by default (`hrisim merge`, `serve --import`); a server's
/// import is bounded by its request body limit before it gets here.
inline constexpr std::uint64_t kDefaultMaxForeignBytes = std::uint64_t{4} << 30;
/// SQLite virtual-machine steps a foreign database may cost per byte of its file, over every statement
/// that checks, copies and reads it; plus kForeignWorkBase for what any file costs. Checking, copying
/// and reading the whole of a results file of hrisim's costs 0.05 a byte (two merged shards, 104 KiB:
/// ForeignDatabase.AResultsFileCostsAFractionOfItsBudget prints it), so the budget is 200 times that.
/// A statement past it fails.
inline constexpr std::uint64_t kForeignWorkPerByte = 10;
inline constexpr std::uint64_t kForeignWorkBase = 50'000'000;

class ForeignDatabase {
 public:
  /// The database in `file`, which is only read (its write-ahead log included); `name` says it in
  /// messages. Throws core::Error(bad_request), with nothing written beside `file`, when the file is
  /// larger than `max_bytes`, is not an SQLite database, fails SQLite's quick_check, has a schema that
  /// is not exactly one of hrisim's migrations (a view, a trigger, a virtual table or any other object
  /// added), or costs more work than its size allows.
  static ForeignDatabase from_file(const std::filesystem::path& file, std::string name, std::uint64_t max_bytes = kDefaultMaxForeignBytes);
  /// The same for a database's bytes (an upload).
  static ForeignDatabase from_bytes(std::string_view bytes, std::string name);

  ForeignDatabase(ForeignDatabase&&) noexcept;
  ForeignDatabase& operator=(ForeignDatabase&&) = delete;
  /// Removes the private copy.
  ~ForeignDatabase();

  /// The private copy, migrated to this hrisim's schema; its reads stay within the work budget (then
  /// they throw core::Error(bad_request)).
  Store& store();
  /// Removes the private copies of processes that were killed before they removed them; how many.
  static int remove_abandoned_copies();
  const std::string& name() const { return name_; }
  /// SQLite virtual-machine steps spent on the file so far, and all it may spend.
  std::uint64_t work_spent() const;
  std::uint64_t work_budget() const;

 private:
  ForeignDatabase(std::string name, std::filesystem::path folder);
  std::string name_;
  std::filesystem::path folder_;  ///< private to this process: the copy and anything SQLite makes beside it
  std::unique_ptr<WorkBudget> work_;
  std::unique_ptr<Store> store_;
  void open(const std::filesystem::path& source, std::uint64_t bytes);
};

}  // namespace hrisim::storage
