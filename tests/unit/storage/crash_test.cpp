// A writer killed with SIGKILL in the middle of writing episodes leaves every committed episode
// complete and readable, no partial one, and a sound file.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "storage/store.hpp"
#include "support/episodes.hpp"
#include "support/temp_dir.hpp"

namespace hrisim::storage {
namespace {

constexpr int kEpisodes = 100;
constexpr int kMetrics = 10, kEvents = 5, kAgents = 4, kTicks = 250;

/// Child: writes kEpisodes episodes, reporting each commit's index on the pipe. Never returns.
[[noreturn]] void write_episodes(const std::filesystem::path& db, int report_fd) {
  try {
    Store store(db);
    for (int i = 0; i < kEpisodes; ++i) {
      store.write_episode(testing::make_episode("s", i, kMetrics, kEvents, kAgents, kTicks));
      if (write(report_fd, &i, sizeof i) != sizeof i) _exit(3);
    }
  } catch (...) {
    _exit(2);
  }
  _exit(0);
}

class KilledWriter : public ::testing::TestWithParam<int> {};

TEST_P(KilledWriter, CommittedEpisodesSurviveWhole) {
  const int kill_after = GetParam();
  testing::TempDir dir;
  const auto db = dir / "hrisim.db";
  { Store(db).put_scenario(testing::make_scenario("s")); }

  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(fds[0]);
    write_episodes(db, fds[1]);
  }
  close(fds[1]);
  int committed = 0, index = -1;
  while (committed < kill_after && read(fds[0], &index, sizeof index) == sizeof index) ++committed;
  // The child is now inside the next episode's transaction (or just about to enter it).
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_EQ(committed, kill_after) << "the writer stopped early";
  // Commits reported between our last read and the kill are still in the pipe.
  int reported = committed;
  while (read(fds[0], &index, sizeof index) == sizeof index) ++reported;
  close(fds[0]);
  const bool killed = WIFSIGNALED(status);
  ASSERT_TRUE(killed || (WIFEXITED(status) && WEXITSTATUS(status) == 0)) << "the writer failed";

  if (killed) {
    // Recovery really happens: the dead writer left its write-ahead log behind.
    EXPECT_TRUE(std::filesystem::exists(db.string() + "-wal"));
  }
  Store store(db);
  EXPECT_EQ(store.integrity_check(), "ok");
  const StoreCounts counts = store.counts();
  // Every reported commit is there; at most one more (committed, killed before it could report).
  EXPECT_GE(counts.episodes, reported);
  EXPECT_LE(counts.episodes, reported + 1);
  EXPECT_EQ(counts.metric_values, counts.episodes * kMetrics);
  EXPECT_EQ(counts.events, counts.episodes * kEvents);
  EXPECT_EQ(counts.trajectory_samples, counts.episodes * kAgents * kTicks);
  for (int i = 0; i < counts.episodes; ++i) {
    const auto episode = store.episode("episode-" + std::to_string(i));
    ASSERT_TRUE(episode) << "committed episode " << i << " is missing";
    EXPECT_EQ(episode->metrics.size(), static_cast<std::size_t>(kMetrics));
    EXPECT_EQ(episode->trajectory.size(), static_cast<std::size_t>(kAgents * kTicks));
  }
}

INSTANTIATE_TEST_SUITE_P(AtSeveralPoints, KilledWriter, ::testing::Values(1, 17, 60));

}  // namespace
}  // namespace hrisim::storage
