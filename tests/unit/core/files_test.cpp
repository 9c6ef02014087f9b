// Temporary folders a killed process leaves (issue 40: an import's copy stayed in /tmp).
#include "core/files.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

namespace hrisim::core {
namespace {

TEST(TempFolders, TheFoldersOfAnEndedProcessAreRemovedAndALiveOnesKept) {
  const std::string prefix = "hrisim-files-test-" + std::to_string(::getpid()) + "-";
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::waitpid(child, nullptr, 0);  // ended and reaped: its pid names no process
  const auto temp = std::filesystem::temp_directory_path();
  const std::filesystem::path left = temp / (prefix + std::to_string(child) + "-abc");
  std::filesystem::create_directories(left / "inside");
  const std::filesystem::path mine = make_private_temp_folder(prefix);
  EXPECT_TRUE(mine.filename().string().starts_with(prefix + std::to_string(::getpid()) + "-"));
  EXPECT_EQ(std::filesystem::status(mine).permissions() & std::filesystem::perms::all, std::filesystem::perms::owner_all);

  EXPECT_EQ(remove_folders_of_ended_processes(prefix), 1);
  EXPECT_FALSE(std::filesystem::exists(left));
  EXPECT_TRUE(std::filesystem::exists(mine)) << "this process is alive";
  std::filesystem::remove_all(mine);
}

}  // namespace
}  // namespace hrisim::core
