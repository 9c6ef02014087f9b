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
                                           "elevator", "pair_walking"));

}  // namespace
}  // namespace hrisim::sim
