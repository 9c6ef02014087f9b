#pragma once
// Serves the browser UI from a folder: content types by extension, index.html for folders, and no
// way out of the folder (no '..' segments, no symlink escaping the root).
#include <filesystem>
#include <string_view>

#include "http/router.hpp"

namespace hrisim::http {

/// Content type for a file name's extension; application/octet-stream when unknown.
std::string_view content_type_for(const std::filesystem::path& file);

class StaticFiles {
 public:
  explicit StaticFiles(std::filesystem::path root);
  /// GET/HEAD of a file under the root; 404 when absent, 400 for '..' segments, 405 for other methods.
  Response serve(const Request& request) const;

 private:
  std::filesystem::path root_;  ///< canonical
};

}  // namespace hrisim::http
