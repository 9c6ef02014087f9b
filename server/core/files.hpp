#pragma once
// Files a scenario names (a ROS map and its image, an IMHuS world): looked up in trusted folders only,
// read within a size limit, so an uploaded scenario can neither read the server's other files nor make
// it read without end (/dev/zero).
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace hrisim::core {

/// Largest file a scenario may name and have read, bytes (a 4000 × 4000 PGM map is 16 MB).
inline constexpr std::size_t kMaxScenarioFileBytes = 64u << 20;

/// `name` as a regular file in the first of `folders` that has it. With `confined`, only a relative
/// name whose real path (symbolic links followed) lies inside that folder's real path counts, so an
/// absolute path, "../" or a link cannot lead out; the answer for a file outside is the same as for
/// one that does not exist. Without `confined` (a user's own files on the command line) an absolute
/// name is taken as it is.
std::optional<std::filesystem::path> find_file(const std::vector<std::filesystem::path>& folders,
                                               const std::filesystem::path& name, bool confined);

/// True when `file`'s real path lies inside `folder`'s real path.
bool inside_folder(const std::filesystem::path& file, const std::filesystem::path& folder);

/// The whole of a regular file of at most `max_bytes`; throws core::Error(bad_request) naming the
/// file otherwise (a device, a folder, too large, unreadable).
std::string read_file(const std::filesystem::path& file, std::size_t max_bytes = kMaxScenarioFileBytes);

/// A new folder of this process in the system's temporary folder, only its user may enter:
/// `<prefix><pid>-<unguessable id>`, so that remove_folders_of_ended_processes finds it should the
/// process be killed before it removes the folder itself.
std::filesystem::path make_private_temp_folder(const std::string& prefix);

/// Removes the temporary folders named `<prefix><pid>-…` whose process has ended (killed before it
/// removed them); returns how many.
int remove_folders_of_ended_processes(const std::string& prefix);

}  // namespace hrisim::core
