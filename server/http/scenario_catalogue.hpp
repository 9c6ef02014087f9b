#pragma once
// The scenarios the server knows: the bundled files (id = file stem), compiled once at start, and
// uploaded ones (id = "u" and 128 random bits in hex), stored with their source and summary and
// compiled when used, kept in a cache of bounded size (least recently used first out). Thread-safe.
#include <cstddef>
#include <filesystem>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "http/router.hpp"
#include "scenario/source.hpp"

namespace hrisim::storage {
class Store;
}

namespace hrisim::http {

/// First letter of an uploaded scenario's id.
inline constexpr char kUploadedPrefix = 'u';
/// Bytes of compiled uploads kept in memory at most (estimated from their grids and sources);
/// `--scenario-cache-mb`.
inline constexpr std::size_t kDefaultScenarioCacheBytes = 256u << 20;

class ScenarioCatalogue {
 public:
  ScenarioCatalogue(storage::Store* store, std::filesystem::path scenarios_dir, scenario::ScenarioLimits limits = {},
                    std::size_t cache_bytes = kDefaultScenarioCacheBytes);

  struct Entry {
    std::string origin;  ///< "bundled" or "uploaded"
    scenario::CompiledSource source;
    std::string sha256;  ///< of an uploaded source
    std::string owner;   ///< who uploaded it; empty for bundled ones and without owners
  };

  /// How sources are compiled here (maps looked up among the bundled scenarios, within the limits).
  scenario::SourceOptions options() const;
  /// The scenario with this id, or null; an upload not in the cache is compiled first.
  std::shared_ptr<const Entry> find(const std::string& id);
  /// The same as `caller` may see it: null also for another owner's upload.
  std::shared_ptr<const Entry> find(const std::string& id, const Caller& caller);
  /// What a list shows of a scenario: an upload's stored summary (compiled once for uploads stored
  /// before summaries were), with id, origin, format and sha256.
  nlohmann::json summary(const std::string& id);
  /// Up to `limit` ids after `cursor`, bundled and uploaded (those `caller` may see) merged in id order.
  std::vector<std::string> page(const std::string& cursor, int limit, const Caller& caller);
  /// Stores a compiled, valid source; returns its new id.
  std::string store(const std::string& text, scenario::CompiledSource compiled, const std::string& owner = "");
  /// Estimated bytes of the compiled uploads held now.
  std::size_t cached_bytes() const;

 private:
  nlohmann::json summary_of(const std::string& id, const Entry& entry) const;
  /// Keeps an upload in the cache as the most recently used, dropping the least recently used ones
  /// beyond the cache's size (the mutex held).
  void remember(const std::string& id, std::shared_ptr<const Entry> entry, std::size_t source_bytes);

  storage::Store* store_;
  std::filesystem::path dir_;
  scenario::ScenarioLimits limits_;
  std::size_t cache_bytes_;
  std::map<std::string, std::shared_ptr<const Entry>> bundled_;
  mutable std::mutex mutex_;
  struct Cached {
    std::shared_ptr<const Entry> entry;
    std::size_t bytes = 0;
    std::list<std::string>::iterator use;  ///< its place in uses_
  };
  std::map<std::string, Cached> uploaded_;
  std::list<std::string> uses_;  ///< cached upload ids, most recently used first
  std::size_t held_bytes_ = 0;
};

}  // namespace hrisim::http
