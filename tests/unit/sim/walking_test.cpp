#include "sim/walking.hpp"

#include <gtest/gtest.h>

#include "scenario/human_commands.hpp"
#include "sim/session.hpp"
#include "support/events.hpp"
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
  ASSERT_TRUE(ana.navigation.under_way);
  ASSERT_EQ(ana.navigation.path.size(), 1u) << "a straight leg from the start to the goal";
  const Vec2 leg_start = ana.navigation.leg_start;
  ana.position = {2.5, 4.6};  // behind the table (4.4..5.6 x 4.6..5.4) from the goal, the leg's start in sight
  ASSERT_GT((ana.position - leg_start).norm(), kCornerReturnReach);
  state.tick += 60;  // past kReplanInterval since the plan
  WalkingBuffers buffers(*model);
  walk(*model, state, buffers);
  for (const Vec2& waypoint : ana.navigation.path) EXPECT_GT((waypoint - leg_start).norm(), 1.0) << "walks back to where the leg began";
  EXPECT_GT(ana.velocity.x(), 0.0) << "heads on towards the goal";
}

// A person put where their body does not fit (0.1 m from the table, their radius 0.3) plans from the
// nearest free cell, walks there first and on to the goal, and says so once for as long as they stay
// there, however often they plan again. Back in the spot after planning from a free one, they say it again.
TEST(Walking, APersonInAnUnplannableSpotReplansFromTheNearestFreeCellAndSaysSoOncePerStay) {
  const auto model = testing::load_valid(testing::room_scenario(json::parse(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 5}}],
    "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 8, "y": 5}}}]}]})")));
  ASSERT_TRUE(model);
  Session session(model, 1);
  const AgentId ana = session.agent_id("ana");
  const auto recoveries = [&] { return testing::events_of<events::ReplannedFromFreeCell>(session); };
  session.tick();
  ASSERT_TRUE(recoveries().empty()) << "planned from where she stands";
  const Pose2 spot{4.3, 5.0, 0.0};  // the table spans x 4.4 … 5.6
  for (int placed = 0; placed < 3; ++placed) {  // each placing throws her path away: she plans again
    session.place_agent(ana, spot);
    session.tick();
  }
  ASSERT_EQ(recoveries().size(), 1u) << "once for the stay";
  const auto& said = *recoveries()[0]->as<events::ReplannedFromFreeCell>();
  EXPECT_EQ(Vec2(said.x, said.y), spot.position());
  const Vec2 free(said.free_x, said.free_y);
  EXPECT_LT((free - spot.position()).norm(), world::kSnapDistance);
  EXPECT_GE((*nearest_obstacle(*model, session.state(), free, 1.0) - free).norm(), 0.3) << "her body fits there";
  EXPECT_EQ(session.state().agents[0].navigation.path.front(), free) << "she walks there first";
  for (int t = 0; t < 400 && session.state().agents[0].navigation.under_way; ++t) session.tick();
  EXPECT_FALSE(session.state().agents[0].navigation.under_way) << "she recovered and arrived";
  EXPECT_EQ(recoveries().size(), 1u);
  session.command_human(scenario::parse_human_command(*model, 0, "walk 2 5"), "walk 2 5");
  session.tick();
  session.place_agent(ana, spot);
  session.tick();
  EXPECT_EQ(recoveries().size(), 2u) << "a new stay";
}

/// The room split by a wall at x = 5 with a door `door` wide in its middle, and `people` sent from the
/// west half to the east half (three abreast, in rows 0.8 m apart).
json room_with_door(double door, int people) {
  json room = testing::room_scenario(json::parse(R"({"time_limit": 60, "steps": [{"name": "through", "actions": []}]})"));
  room["world"].erase("obstacles");
  room["world"]["walls"].push_back({{"from", {5, 0}}, {"to", {5, 5 - door / 2}}});
  room["world"]["walls"].push_back({{"from", {5, 5 + door / 2}}, {"to", {5, 10}}});
  for (int i = 0; i < people; ++i) {
    const std::string id = "p" + std::to_string(i);
    const double x = 2.0 - 0.8 * (i / 3), y = 4.0 + (i % 3);
    room["humans"].push_back({{"id", id}, {"start", {{"x", x}, {"y", y}}}});
    room["steps"][0]["actions"].push_back({{"agent", id}, {"goto", {{"pose", {{"x", 10.0 - x}, {"y", y}}}}}});
  }
  return room;
}

// A door 0.55 m wide, as in users' pedsim_ros and HuNavSim maps: narrower than a person's disc (2 × 0.3
// m), wider than their body (2 × kBodyHalfWidth). Six people plan through it and walk through one by
// one, never onto the wall nor nearer to it than their body's clearance. A door narrower than the body
// stays closed to them.
TEST(Walking, PeoplePlanThroughADoorNarrowerThanTheirDiscButWiderThanTheirBody) {
  const auto model = testing::load_valid(room_with_door(0.55, 6));
  ASSERT_TRUE(model);
  ASSERT_FALSE(model->planner.plan({2, 5}, {8, 5}, 0.3)) << "the door is narrower than the disc";
  Session session(model, 1);
  double nearest_wall = 1.0;
  for (int t = 0; t < 60 * 60 && session.state().termination == Termination::none; ++t) {
    session.tick();
    for (const AgentState& person : session.state().agents) {
      ASSERT_FALSE(model->grid.blocked(person.position)) << "on the wall at tick " << session.state().tick;
      nearest_wall = std::min(nearest_wall, (*nearest_obstacle(*model, session.state(), person.position, 1.0) - person.position).norm());
    }
  }
  EXPECT_TRUE(testing::events_of<events::GoalUnreachable>(session).empty());
  EXPECT_EQ(session.state().termination, Termination::scenario_end) << "everyone got through";
  EXPECT_GE(nearest_wall, body_clearance(model->grid) - 1e-9) << "the walls keep them off by their body's clearance";
  EXPECT_LT(nearest_wall, 0.3) << "through a door their disc does not fit";

  const auto narrower = testing::load_valid(room_with_door(0.45, 1));
  ASSERT_TRUE(narrower);
  Session blocked(narrower, 1);
  blocked.tick();
  EXPECT_EQ(testing::events_of<events::GoalUnreachable>(blocked).size(), 1u) << "a door narrower than the body";
}

// Two groups of 60 cross the room through each other, half with the social force and half with ORCA:
// the crowd's velocities on one, two or three threads give the same trajectory bit for bit.
TEST(Walking, ACrowdOnSeveralThreadsWalksBitForBitAsOnOne) {
  json scenario = testing::room_scenario(json::parse(R"({"time_limit": 30, "steps": [{"name": "cross", "actions": []}]})"));
  scenario["world"].erase("obstacles");
  for (int i = 0; i < 120; ++i) {
    const double x = i < 60 ? 1.0 + (i % 6) * 0.5 : 9.0 - (i % 6) * 0.5, y = 1.0 + (i % 60 / 6) * 0.85;
    const std::string id = "p" + std::to_string(i);
    scenario["humans"].push_back({{"id", id}, {"start", {{"x", x}, {"y", y}}}, {"avoidance", i % 2 ? "orca" : "social_force"}});
    scenario["steps"][0]["actions"].push_back({{"agent", id}, {"goto", {{"pose", {{"x", 10.0 - x}, {"y", y}}}}}});
  }
  const auto model = testing::load_valid(scenario);
  ASSERT_TRUE(model);
  std::vector<std::uint64_t> hashes;
  for (const unsigned threads : {1u, 2u, 3u}) {
    Session session(model, 7);
    session.set_crowd_threads(threads);
    for (int t = 0; t < 240; ++t) session.tick();
    hashes.push_back(session.state_hash());
  }
  EXPECT_EQ(hashes[1], hashes[0]) << "two threads";
  EXPECT_EQ(hashes[2], hashes[0]) << "three threads";
}

}  // namespace
}  // namespace hrisim::sim
