#include <gtest/gtest.h>

#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

template <class Kind>
const Event* first_event(const Session& session, const std::string& subject) {
  for (const Event& event : session.state().events) {
    if (event.is<Kind>() && event.subject == subject) return &event;
  }
  return nullptr;
}

// Pedsim's sources and sinks, in the native format: a human who enters later, and one who leaves.
TEST(EnteringAndLeaving, AHumanEntersAtTheirTimeAndLeavesWhereTheyStand) {
  const auto model = testing::load_valid(testing::room_scenario(json::parse(R"({
    "humans": [{"id": "ana", "start": {"x": 1, "y": 2}}, {"id": "ben", "start": {"x": 1, "y": 8}, "enters_at": 3}],
    "groups": {"pair": {"members": ["ana", "ben"]}},
    "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 8, "y": 2}}}, {"agent": "ana", "leave": {}},
                                            {"agent": "ben", "goto": {"pose": {"x": 8, "y": 8}}}]}]})")));
  ASSERT_TRUE(model);
  Session session(model, 1);
  const int ben = session.index_of(session.agent_id("ben"));
  const int ana = session.index_of(session.agent_id("ana"));
  while (session.time() < 2.9) session.tick();
  EXPECT_FALSE(session.state().agents[ben].active) << "not in the scene before 3 s";
  EXPECT_EQ(session.state().agents[ben].position, Vec2(1, 8)) << "and not walking";
  while (session.time() < 3.2) session.tick();
  const Event* entered = first_event<events::Entered>(session, "ben");
  ASSERT_TRUE(entered);
  EXPECT_NEAR(entered->time, 3.0, 1e-9);
  EXPECT_TRUE(session.state().agents[ben].active);
  while (!session.state().finished) session.tick();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_LT((session.state().agents[ben].position - Vec2(8, 8)).norm(), 0.25) << "ben walked once in";
  const Event* left = first_event<events::Left>(session, "ana");
  ASSERT_TRUE(left);
  EXPECT_FALSE(session.state().agents[ana].active);
  EXPECT_LT((session.state().agents[ana].position - Vec2(8, 2)).norm(), 0.25) << "she left where she arrived";
  EXPECT_EQ(session.state().groups[0], std::vector<int>{ben}) << "and her group";
}

TEST(EnteringAndLeaving, OnlyHumansLeaveAndEntryTimesAreChecked) {
  json robot_leaves = testing::room_scenario(json::parse(R"({
    "robots": [{"id": "bot", "start": {"x": 1, "y": 2}}],
    "steps": [{"name": "go", "actions": [{"agent": "bot", "leave": {}}]}]})"));
  const scenario::LoadResult refused = scenario::load_scenario(robot_leaves, {});
  ASSERT_FALSE(refused.errors.empty());
  EXPECT_EQ(refused.errors[0].pointer, "/steps/0/actions/0/agent");
  json negative = testing::room_scenario(json::parse(R"({
    "humans": [{"id": "ana", "start": {"x": 1, "y": 2}, "enters_at": -1}], "steps": []})"));
  const scenario::LoadResult schema = scenario::load_scenario(negative, {});
  ASSERT_FALSE(schema.errors.empty());
  EXPECT_EQ(schema.errors[0].pointer, "/humans/0/enters_at");
}

}  // namespace
}  // namespace hrisim::sim
