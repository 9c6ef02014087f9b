#pragma once
// Files compiled into the binary by cmake/EmbedFiles.cmake (schemas, robots, motions, the API
// description): looking one up by name, and listing the JSON ones.
#include <algorithm>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hrisim::core {

using EmbeddedFile = std::pair<std::string_view, std::string_view>;  ///< file name, contents

/// The contents of the file named `name`; empty when there is none.
inline std::string_view find_embedded(std::span<const EmbeddedFile> files, std::string_view name) {
  const auto found = std::find_if(files.begin(), files.end(), [&](const EmbeddedFile& file) { return file.first == name; });
  return found == files.end() ? std::string_view() : found->second;
}

/// The names, without ".json", of the JSON files but `except`, sorted.
inline std::vector<std::string> json_file_stems(std::span<const EmbeddedFile> files, std::string_view except = {}) {
  std::vector<std::string> stems;
  for (const auto& [name, contents] : files) {
    if (name != except && name.ends_with(".json")) stems.emplace_back(name.substr(0, name.size() - 5));
  }
  std::sort(stems.begin(), stems.end());
  return stems;
}

}  // namespace hrisim::core
