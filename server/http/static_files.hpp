#pragma once
// Serves the browser UI from a folder: content types by extension, index.html for folders, and no
// way out of the folder (no '..' segments, no symlink escaping the root). Every file has an ETag
// (a conditional GET gets 304) and text goes gzipped to clients that accept it; both are kept in a
// bounded cache, checked against the file's time and size. Libraries under node_modules are served
// at versioned paths, /lib/<package>@<version>/<file>, cached by browsers for a year: a new version
// is a new path. Everything else is revalidated on every use (no-cache).
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string_view>

#include "http/router.hpp"

namespace hrisim::http {

/// Content type for a file name's extension; application/octet-stream when unknown.
std::string_view content_type_for(const std::filesystem::path& file);

/// The static files' cache holds at most this many bytes (plain and gzipped); past it, it starts again.
inline constexpr std::size_t kStaticCacheBytes = std::size_t{64} << 20;
/// Text files smaller than this go as they are: gzip's header would eat the gain.
inline constexpr std::size_t kGzipMinBytes = 1024;
/// Cache-Control of the versioned libraries (/lib/<package>@<version>/…).
inline constexpr std::string_view kLibraryCacheControl = "public, max-age=31536000, immutable";

class StaticFiles {
 public:
  explicit StaticFiles(std::filesystem::path root);
  ~StaticFiles();
  /// GET/HEAD of a file under the root; 404 when absent, 400 for '..' segments, 405 for other methods;
  /// 304 when If-None-Match names its ETag; gzipped when Accept-Encoding allows and it pays.
  Response serve(const Request& request) const;

 private:
  struct File;
  /// The file's bytes, ETag and gzip form, from the cache while its time and size are unchanged.
  std::shared_ptr<const File> load(const std::filesystem::path& file) const;

  std::filesystem::path root_;  ///< canonical
  mutable std::mutex mutex_;
  mutable std::map<std::filesystem::path, std::shared_ptr<const File>> cache_;
  mutable std::size_t cached_bytes_ = 0;
};

}  // namespace hrisim::http
