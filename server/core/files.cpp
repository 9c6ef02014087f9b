#include "core/files.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/random.hpp"

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

std::filesystem::path make_private_temp_folder(const std::string& prefix) {
  namespace fs = std::filesystem;
  const fs::path folder = fs::temp_directory_path() / (prefix + std::to_string(::getpid()) + "-" + unguessable_id('t'));
  fs::create_directory(folder);
  fs::permissions(folder, fs::perms::owner_all, fs::perm_options::replace);
  return folder;
}

int remove_folders_of_ended_processes(const std::string& prefix) {
  namespace fs = std::filesystem;
  std::error_code error;
  int removed = 0;
  for (const auto& entry : fs::directory_iterator(fs::temp_directory_path(), error)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with(prefix) || !entry.is_directory(error)) continue;
    const std::size_t dash = name.find('-', prefix.size());
    long pid = 0;
    const auto [end, parsed] = std::from_chars(name.data() + prefix.size(), name.data() + std::min(dash, name.size()), pid);
    if (parsed != std::errc() || end != name.data() + std::min(dash, name.size()) || pid <= 0) continue;
    // A process that is gone (or was never this user's to signal) left the folder behind.
    if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
    fs::remove_all(entry.path(), error);
    if (!error) ++removed;
  }
  return removed;
}

}  // namespace hrisim::core
