// A thread team: every index of a loop runs once, in fixed parts, loop after loop; a part's exception
// reaches the caller; one thread runs on the caller.
#include "core/thread_team.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

namespace hrisim::core {
namespace {

TEST(ThreadTeam, EveryIndexRunsOnceInItsFixedPartLoopAfterLoop) {
  ThreadTeam team(3);
  ASSERT_EQ(team.size(), 3u);
  for (const std::size_t count : {0u, 1u, 2u, 7u, 1000u}) {
    for (int loop = 0; loop < 200; ++loop) {
      std::vector<int> runs(count, 0);
      std::vector<unsigned> part_of(count, 99);
      team.run(count, [&](unsigned part, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
          ++runs[i];
          part_of[i] = part;
        }
      });
      for (std::size_t i = 0; i < count; ++i) {
        ASSERT_EQ(runs[i], 1) << "index " << i << " of " << count;
        unsigned expected = 0;
        while (ThreadTeam::bounds(count, 3, expected).second <= i) ++expected;
        ASSERT_EQ(part_of[i], expected) << "index " << i << " of " << count;
      }
    }
  }
}

TEST(ThreadTeam, PartsRunOnDifferentThreadsAndTheCallerTakesTheFirst) {
  ThreadTeam team(2);
  std::thread::id first, second;
  team.run(2, [&](unsigned part, std::size_t, std::size_t) { (part == 0 ? first : second) = std::this_thread::get_id(); });
  EXPECT_EQ(first, std::this_thread::get_id());
  EXPECT_NE(second, std::this_thread::get_id());
}

TEST(ThreadTeam, AHelpersExceptionReachesTheCallerAndTheTeamGoesOn) {
  ThreadTeam team(2);
  EXPECT_THROW(team.run(10, [](unsigned part, std::size_t, std::size_t) {
    if (part == 1) throw std::runtime_error("part 1 failed");
  }), std::runtime_error);
  std::atomic<int> done{0};
  team.run(10, [&](unsigned, std::size_t begin, std::size_t end) { done += static_cast<int>(end - begin); });
  EXPECT_EQ(done, 10);
}

TEST(ThreadTeam, OneThreadRunsTheWholeLoopOnTheCaller) {
  ThreadTeam team(1);
  std::vector<std::pair<std::size_t, std::size_t>> calls;
  team.run(5, [&](unsigned part, std::size_t begin, std::size_t end) {
    EXPECT_EQ(part, 0u);
    calls.emplace_back(begin, end);
  });
  ASSERT_EQ(calls.size(), 1u);
  EXPECT_EQ(calls[0], (std::pair<std::size_t, std::size_t>{0, 5}));
}

}  // namespace
}  // namespace hrisim::core
