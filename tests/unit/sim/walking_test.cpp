#include "sim/walking.hpp"

#include <gtest/gtest.h>

#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

// The room's table stands between a person pushed behind it and their waypoint, while the leg's start,
// where they set off from 1.5 m away, is in sight. Walking back there is the way round only for a
// corner close by: from farther they plan again.
TEST(Walking, APersonPushedFarOffTheirLegPlansAgainRatherThanWalkBackToItsStart) {
  const auto model = testing::load_valid(testing::room_scenario(json::parse(R"({
    "humans": [{"id": "ana", "start": {"x": 1, "y": 7}, "preferred_speed": 1.2}],
    "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 9, "y": 7}}}]}]})")));
  ASSERT_TRUE(model);
  Session session(model, 1);
  session.tick();
  State state = session.state();
  AgentState& ana = state.agents[0];
  ASSERT_TRUE(ana.navigating);
  ASSERT_EQ(ana.path.size(), 1u) << "a straight leg from the start to the goal";
  const Vec2 leg_start = ana.leg_start;
  ana.position = {2.5, 4.6};  // behind the table (4.4..5.6 x 4.6..5.4) from the goal, the leg's start in sight
  ASSERT_GT((ana.position - leg_start).norm(), kCornerReturnReach);
  state.tick += 60;  // past kReplanInterval since the plan
  WalkingBuffers buffers(*model);
  walk(*model, state, buffers);
  for (const Vec2& waypoint : ana.path) EXPECT_GT((waypoint - leg_start).norm(), 1.0) << "walks back to where the leg began";
  EXPECT_GT(ana.velocity.x(), 0.0) << "heads on towards the goal";
}

}  // namespace
}  // namespace hrisim::sim
