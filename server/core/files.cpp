#include "core/files.hpp"

#include <algorithm>
#include <fstream>

#include "core/error.hpp"

namespace hrisim::core {

bool inside_folder(const std::filesystem::path& file, const std::filesystem::path& folder) {
  std::error_code ec;
  const auto real_file = std::filesystem::canonical(file, ec);
  if (ec) return false;
  const auto real_folder = std::filesystem::canonical(folder, ec);
  if (ec) return false;
  const auto [folder_end, file_at] = std::mismatch(real_folder.begin(), real_folder.end(), real_file.begin(), real_file.end());
  return folder_end == real_folder.end() && file_at != real_file.end();
}

std::optional<std::filesystem::path> find_file(const std::vector<std::filesystem::path>& folders,
                                               const std::filesystem::path& name, bool confined) {
  std::error_code ec;
  if (name.empty()) return std::nullopt;
  if (name.is_absolute()) {
    if (confined || !std::filesystem::is_regular_file(name, ec)) return std::nullopt;
    return name;
  }
  for (const auto& folder : folders) {
    const auto candidate = folder / name;
    if (!std::filesystem::is_regular_file(candidate, ec)) continue;
    if (confined && !inside_folder(candidate, folder)) continue;
    return candidate;
  }
  return std::nullopt;
}

std::string read_file(const std::filesystem::path& file, std::size_t max_bytes) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw Error(ErrorCode::bad_request, file.string() + " is not a regular file", {{"file", file.string()}});
  }
  const auto size = std::filesystem::file_size(file, ec);
  if (ec || size > max_bytes) {
    throw Error(ErrorCode::bad_request, file.string() + " is larger than " + std::to_string(max_bytes) + " bytes",
                {{"file", file.string()}, {"limit_bytes", max_bytes}});
  }
  std::ifstream in(file, std::ios::binary);
  std::string text(size, '\0');
  if (!in.read(text.data(), static_cast<std::streamsize>(size))) {
    throw Error(ErrorCode::bad_request, "cannot read " + file.string(), {{"file", file.string()}});
  }
  return text;
}

}  // namespace hrisim::core
