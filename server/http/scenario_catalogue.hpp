#pragma once
// The scenarios the server knows: the bundled files (id = file stem), compiled once at start, and
// uploaded ones (id = "u" and 128 random bits in hex), stored with their source and summary and
// compiled when used, kept in a cache of bounded size (least recently used first out). An upload may
// bring files along (its ROS map and image, an IMHuS world): they are stored with it and, while the
// server runs, written to a private folder of this process that the upload's references are looked up
// in before the bundled scenarios' folder. Thread-safe.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
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
/// Bytes of compiled uploads kept in memory at most (estimated from their grids and what their sources
/// expand to: the values of their native documents);
/// `--scenario-cache-mb`.
inline constexpr std::size_t kDefaultScenarioCacheBytes = 256u << 20;

/// The private folder the uploads' files are written to is named so (core::make_private_temp_folder).
inline constexpr const char* kFilesFolderPrefix = "hrisim-files-";

/// Most files one upload may bring along.
inline constexpr std::size_t kMaxUploadFiles = 64;

/// A scenario as a client hands it in: its text in its format, and the files it names, by their path
/// relative to it (checked: see storage::scenario_file_path_problem).
struct Upload {
  std::string text;
  scenario::SourceFormat format = scenario::SourceFormat::json;
  std::map<std::string, std::string> files;
};

/// A path of an upload's files that lies inside another of its paths, which would be both a file and
/// a folder: {`d`, `d/f`}; none when no path does.
struct NestedFile {
  std::string file, inside;
};
std::optional<NestedFile> nested_upload_file(const std::map<std::string, std::string>& files);

class ScenarioCatalogue {
 public:
  ScenarioCatalogue(storage::Store* store, std::filesystem::path scenarios_dir, scenario::ScenarioLimits limits = {},
                    std::size_t cache_bytes = kDefaultScenarioCacheBytes);
  /// Removes the folder the uploads' files were written to.
  ~ScenarioCatalogue();
  ScenarioCatalogue(const ScenarioCatalogue&) = delete;
  ScenarioCatalogue& operator=(const ScenarioCatalogue&) = delete;

  struct Entry {
    std::string origin;  ///< "bundled" or "uploaded"
    scenario::CompiledSource source;
    std::string sha256;  ///< of an uploaded source and its files
    std::string owner;   ///< who uploaded it; empty for bundled ones and without owners
    std::filesystem::path files;  ///< where the files uploaded with it are; empty without any

    /// What the scenario is made of: an upload's sha256, a bundled one's of its document.
    std::string content_sha256() const;
  };

  /// How the scenario of `entry` is compiled here (again, e.g. with another controller): its files
  /// first, then the bundled scenarios' folder, within the limits.
  scenario::SourceOptions options(const Entry& entry) const;
  /// Compiles an upload without keeping it (validation). `also`, when given, is called with what was
  /// compiled and the options it was compiled with while the upload's files are still there (a run's
  /// config compiled against it).
  using AlsoCheck = std::function<void(const scenario::CompiledSource&, const scenario::SourceOptions&)>;
  scenario::CompiledSource check(const Upload& upload, const AlsoCheck& also = {});
  /// What add() did: the scenario's id (empty when it is not valid) and whether `owner` had uploaded
  /// the same content in the same format before (then that one's id, listed again).
  struct Added {
    std::string id;
    bool existed = false;
  };
  /// Compiles an upload and, when it is valid, stores it for `owner`: its new id, or the id of the same
  /// content uploaded before, or empty (nothing stored) with the errors in `compiled`.
  Added add(const Upload& upload, const std::string& owner, scenario::CompiledSource& compiled);
  /// Takes an upload out of the catalogue: deleted when no run ran it, else unlisted (found by id by
  /// what ran it): true when deleted. 404 for an unknown one or another owner's; 409 for a bundled scenario.
  bool remove(const std::string& id, const Caller& caller);
  /// The scenario with this id, or null; an upload not in the cache is compiled first.
  std::shared_ptr<const Entry> find(const std::string& id);
  /// The same as `caller` may see it: null also for another owner's upload.
  std::shared_ptr<const Entry> find(const std::string& id, const Caller& caller);
  /// What a list shows of a scenario: an upload's stored summary (compiled once for uploads stored
  /// before summaries were), with id, origin, format and sha256.
  nlohmann::json summary(const std::string& id);
  /// Up to `limit` ids after `cursor`, bundled and uploaded (those `caller` may see) merged in id order.
  std::vector<std::string> page(const std::string& cursor, int limit, const Caller& caller);
  /// Estimated bytes of the compiled uploads held now.
  std::size_t cached_bytes() const;

 private:
  nlohmann::json summary_of(const std::string& id, const Entry& entry) const;
  /// Options with `files` (empty: none) looked up before the bundled scenarios.
  scenario::SourceOptions options_with(const std::filesystem::path& files) const;
  /// Writes an upload's files to the folder `name` of this process's files folder (once: a folder
  /// already there is kept, as uploads never change); empty without files.
  std::filesystem::path write_files(const std::string& name, const std::map<std::string, std::string>& files);
  /// Compiles `upload` with its files written to folder `name`.
  scenario::CompiledSource compile(const Upload& upload, const std::filesystem::path& files);
  /// Keeps an upload in the cache as the most recently used, dropping the least recently used ones
  /// beyond the cache's size (the mutex held).
  void remember(const std::string& id, std::shared_ptr<const Entry> entry);
  /// Drops a compiled upload from the cache, if it is there (the mutex held).
  void forget(const std::string& id);

  storage::Store* store_;
  std::filesystem::path dir_;
  std::filesystem::path files_root_;  ///< this process's folder of uploaded files, made when first needed
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
