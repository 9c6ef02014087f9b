#pragma once
// The scenarios the server knows: the bundled files (id = file stem), compiled once at start, and
// uploaded ones (id = "u" and 128 random bits in hex), stored with their source and compiled on first
// use. Thread-safe.
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenario/source.hpp"

namespace hrisim::storage {
class Store;
}

namespace hrisim::http {

/// First letter of an uploaded scenario's id.
inline constexpr char kUploadedPrefix = 'u';

class ScenarioCatalogue {
 public:
  ScenarioCatalogue(storage::Store* store, std::filesystem::path scenarios_dir);

  struct Entry {
    std::string origin;  ///< "bundled" or "uploaded"
    scenario::CompiledSource source;
    std::string sha256;  ///< of an uploaded source
  };

  /// How sources are compiled here (maps looked up among the bundled scenarios).
  scenario::SourceOptions options() const;
  /// The scenario with this id, or null. Entries live as long as the catalogue.
  const Entry* find(const std::string& id);
  /// What a list shows of it.
  nlohmann::json summary(const std::string& id, const Entry& entry) const;
  /// Up to `limit` ids after `cursor`, bundled and uploaded merged in id order.
  std::vector<std::string> page(const std::string& cursor, int limit);
  /// Stores a compiled, valid source; returns its new id.
  std::string store(const std::string& text, scenario::CompiledSource compiled);

 private:
  storage::Store* store_;
  std::filesystem::path dir_;
  std::map<std::string, Entry> bundled_;
  std::mutex mutex_;
  std::map<std::string, Entry> uploaded_;
};

}  // namespace hrisim::http
