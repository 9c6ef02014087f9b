// Every bundled scenario runs to its end, for several seeds, and the same seed gives the same hash.
#include <gtest/gtest.h>

#include "episode/episode.hpp"
#include "scenario/load.hpp"
#include "sim/session.hpp"

namespace hrisim::sim {
namespace {

class Bundled : public ::testing::TestWithParam<std::string> {};

TEST_P(Bundled, CompletesForEverySeed) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + GetParam() + ".json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  ASSERT_TRUE(loaded.model);
  for (std::uint64_t seed : {0u, 1u, 2u}) {
    episode::Episode run(loaded.model, seed), again(loaded.model, seed);
    run.run();
    again.run();
    EXPECT_EQ(run.session().state().termination, sim::Termination::scenario_end) << GetParam() << " seed " << seed;
    EXPECT_EQ(run.session().state_hash(), again.session().state_hash()) << GetParam() << " seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenarios, Bundled,
                         ::testing::Values("corridor_passing", "perpendicular_crossing", "conversation_group", "queue",
                                           "elevator", "pair_walking", "apartment", "corridor_navigation", "crossing_navigation"));

}  // namespace
}  // namespace hrisim::sim

#include <cstdlib>
#include <optional>

#include "sim/episode_recorder.hpp"

namespace hrisim::sim {
namespace {

TEST(EpisodeRecorder, StopsAtItsBodyLimitAndKeepsTheEventsUpToThere) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/queue.json");
  ASSERT_TRUE(loaded.model);
  Session session(loaded.model, 1);
  const std::size_t bodies = session.model().agents.size();  // every person present, and the robot
  EpisodeRecorder capped(session, {10 * bodies}), full(session);
  for (int i = 0; i < 600; ++i) {
    session.tick();
    capped.record(session);
    full.record(session);
  }
  EXPECT_EQ(capped.recorded_until(), 9) << "ten samples: the start and nine steps";
  EXPECT_EQ(full.recorded_until(), 600);
  const metrics::Recording recording = capped.finish(session);
  ASSERT_EQ(recording.samples.size(), 10u);
  for (const metrics::RecordedEvent& event : recording.events) EXPECT_LE(event.tick, 9) << static_cast<int>(event.kind);
  EXPECT_GT(full.finish(session).events.size(), recording.events.size());
  EXPECT_NE(capped.stopped().find(std::to_string(10 * bodies) + " bodies"), std::string::npos) << capped.stopped();
  EXPECT_EQ(full.stopped(), "");
}

TEST(EpisodeRecorder, RecordingsSharingAMemoryBudgetStopWhenItIsSpentAndGiveItBackWhenTheyEnd) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/queue.json");
  ASSERT_TRUE(loaded.model);
  Session session(loaded.model, 1);
  // Packed, a queue's tick takes tens of bytes: 256 KiB, four blocks, hold less than its 1,706 ticks twice.
  core::MemoryBudget memory(std::size_t{256} << 10);
  std::optional<EpisodeRecorder> first(std::in_place, session, RecorderLimits{std::nullopt, &memory});
  EpisodeRecorder second(session, {std::nullopt, &memory});
  std::int64_t ticks = 0;
  while (first->stopped().empty() && ticks < 100000) {
    session.tick();
    ++ticks;
    first->record(session);
    second.record(session);
  }
  ASSERT_FALSE(first->stopped().empty()) << "256 KiB hold no two recordings of the whole queue";
  EXPECT_EQ(first->stopped(), "the recordings of all sessions and runs hold their maximum of 256 KiB");
  EXPECT_LE(memory.used(), memory.limit());
  EXPECT_GT(memory.used(), memory.limit() - metrics::PackedSamples::kBlockBytes) << "stopped a block short of the ceiling at most";
  EXPECT_LT(first->recorded_until(), session.state().tick);
  // Both recorded alternately: they share the 256 KiB, neither was given all of it.
  EXPECT_LT(std::abs(first->recorded_until() - second.recorded_until()), 2);
  const std::size_t before = memory.used();
  first.reset();
  EXPECT_LT(memory.used(), before / 2 + 4096) << "the ended recording gave its half back";
  session.tick();
  second.record(session);
  EXPECT_LT(second.recorded_until(), session.state().tick) << "a stopped recording stays stopped: a gap would misstate its metrics";
  EpisodeRecorder third(session, {std::nullopt, &memory});
  session.tick();
  third.record(session);
  EXPECT_EQ(third.recorded_until(), session.state().tick) << "a new one records in the room given back";
  EXPECT_EQ(third.stopped(), "");
}

}  // namespace
}  // namespace hrisim::sim
