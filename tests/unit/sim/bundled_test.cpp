// Every bundled scenario runs to its end, for several seeds, and the same seed gives the same hash.
#include <gtest/gtest.h>

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
    Session session(loaded.model, seed), again(loaded.model, seed);
    session.run();
    again.run();
    EXPECT_EQ(session.state().termination, "scenario_end") << GetParam() << " seed " << seed;
    EXPECT_EQ(session.state_hash(), again.state_hash()) << GetParam() << " seed " << seed;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenarios, Bundled,
                         ::testing::Values("corridor_passing", "perpendicular_crossing", "conversation_group", "queue",
                                           "elevator", "pair_walking", "apartment"));

}  // namespace
}  // namespace hrisim::sim

#include "sim/episode_recorder.hpp"

namespace hrisim::sim {
namespace {

TEST(EpisodeRecorder, StopsAtItsBodyLimitAndKeepsTheEventsUpToThere) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/queue.json");
  ASSERT_TRUE(loaded.model);
  Session session(loaded.model, 1);
  const std::size_t bodies = session.model().agents.size();  // every person present, and the robot
  EpisodeRecorder capped(session, 10 * bodies), full(session);
  for (int i = 0; i < 600; ++i) {
    session.step();
    capped.record(session);
    full.record(session);
  }
  EXPECT_EQ(capped.recorded_until(), 9) << "ten samples: the start and nine steps";
  EXPECT_EQ(full.recorded_until(), 600);
  const metrics::Recording recording = capped.finish(session);
  ASSERT_EQ(recording.samples.size(), 10u);
  for (const metrics::RecordedEvent& event : recording.events) EXPECT_LE(event.tick, 9) << event.kind;
  EXPECT_GT(full.finish(session).events.size(), recording.events.size());
}

}  // namespace
}  // namespace hrisim::sim
