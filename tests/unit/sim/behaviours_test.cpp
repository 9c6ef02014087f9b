// HuNavSim's behaviours, each by its signature: the surprised one stops and looks at the robot, the
// scared one keeps away from it, the curious one comes up to it and follows, the threatening one
// stands in its way, the impassive one passes it as closely as an obstacle, the regular one keeps
// its personal space and does not react.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/session.hpp"
#include "support/commands.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// The room with a disc robot `r` at `robot` and a person `p` at `person` with `behaviour`; `steps`
/// is the choreography.
json scene(const json& behaviour, const json& person, const json& robot, const json& steps) {
  json document = testing::room_scenario({{"time_limit", 60}});
  document["humans"] = json::array({{{"id", "p"}, {"start", person}, {"behaviour", behaviour}, {"preferred_speed", 1.2}}});
  document["robots"] = json::array({{{"id", "r"}, {"start", robot}}});
  document["steps"] = steps;
  return document;
}

struct Watch {
  Session session;
  int p, r;
  explicit Watch(const json& document) : session(testing::load_valid(document), 1) {
    p = session.index_of(session.agent_id("p"));
    r = session.index_of(session.agent_id("r"));
  }
  const AgentState& person() const { return session.state().agents[p]; }
  const AgentState& robot() const { return session.state().agents[r]; }
  double distance() const { return (person().position - robot().position).norm(); }
  void run_until(double time) {
    while (session.time() < time - 1e-9 && !session.state().finished) session.tick();
  }
  /// When the first reaction started, or -1.
  double reaction_started() const {
    for (const Event& event : session.state().events) {
      if (event.is<sim::events::ReactionStarted>()) return event.time;
    }
    return -1.0;
  }
};

const json kWalkWest = json::parse(R"([{"name": "go", "actions": [{"agent": "p", "goto": {"pose": {"x": 1, "y": 3}}}]}])");
const json kRobotDrivesEast = json::parse(R"([{"name": "go", "actions": [{"agent": "p", "wait": {"duration": 50}},
                                                                         {"agent": "r", "goto": {"pose": {"x": 9, "y": 2}}}]}])");

TEST(Behaviours, TheSurprisedOneStopsAndLooksAtTheRobot) {
  Watch watch(scene("surprised", {{"x", 9}, {"y", 3}, {"theta", 3.14159}}, {{"x", 2}, {"y", 2}, {"theta", 0}}, kWalkWest));
  watch.run_until(8.0);
  const double started = watch.reaction_started();
  ASSERT_GT(started, 0.0);
  const Vec2 stopped_at = watch.person().position;
  EXPECT_NEAR(watch.distance(), 4.0, 0.6) << "it reacts at its detection distance, 4 m";
  watch.run_until(started + 10.0);
  EXPECT_LT((watch.person().position - stopped_at).norm(), 0.15) << "it stands";
  EXPECT_NEAR(core::wrap_angle(watch.person().heading - core::direction_to(watch.person().position, watch.robot().position)), 0.0, 0.1)
      << "and looks at the robot";
  watch.run_until(started + 35.0);
  EXPECT_LT(watch.person().position.x(), stopped_at.x() - 1.0) << "after its 30 s it walks on";
}

/// The closest the person came to the robot driving east along y = 2 past them, centre to centre.
double closest_pass(const json& behaviour) {
  Watch watch(scene(behaviour, {{"x", 6}, {"y", 2.8}, {"theta", 3.14159}}, {{"x", 1}, {"y", 2}, {"theta", 0}}, kRobotDrivesEast));
  double closest = 1e9;
  while (watch.robot().position.x() < 8.5 && watch.session.time() < 50.0) {
    watch.session.tick();
    closest = std::min(closest, watch.distance());
  }
  return closest;
}

TEST(Behaviours, TheScaredOneKeepsAway) {
  const double regular = closest_pass("regular"), scared = closest_pass("scared");
  EXPECT_GT(scared, regular + 0.5) << "regular " << regular << " m, scared " << scared << " m";
  EXPECT_GT(scared, 1.5);
}

TEST(Behaviours, TheCuriousOneComesUpToTheRobotAndFollowsIt) {
  const json steps = json::parse(R"([{"name": "stand", "actions": [{"agent": "p", "wait": {"duration": 15}}, {"agent": "r", "wait": {"duration": 15}}]},
                                     {"name": "drive", "actions": [{"agent": "r", "goto": {"pose": {"x": 2, "y": 8}}}]}])");
  Watch watch(scene("curious", {{"x", 8}, {"y", 2}, {"theta", 3.14159}}, {{"x", 2}, {"y", 2}, {"theta", 1.5708}}, steps));
  watch.run_until(15.0);
  EXPECT_GE(watch.reaction_started(), 0.0) << "it sees the robot at once";
  EXPECT_NEAR(watch.distance(), 1.5, 0.3) << "it stops 1.5 m from the robot";
  const Vec2 there = watch.person().position;
  watch.run_until(35.0);
  EXPECT_GT(watch.robot().position.y(), 5.0) << "the robot drove north";
  EXPECT_GT((watch.person().position - there).norm(), 2.0) << "it follows";
  EXPECT_LT(watch.distance(), 2.2);
}

TEST(Behaviours, TheThreateningOneStandsInTheRobotsWay) {
  Watch watch(scene("threatening", {{"x", 5}, {"y", 4}, {"theta", -2.5}}, {{"x", 1}, {"y", 2}, {"theta", 0}}, kRobotDrivesEast));
  watch.run_until(10.0);
  const double started = watch.reaction_started();
  ASSERT_GT(started, 0.0);
  watch.run_until(started + 6.0);
  const Vec2 offset = watch.person().position - watch.robot().position;
  const Vec2 ahead = core::heading_vector(watch.robot().heading);
  EXPECT_NEAR(offset.dot(ahead), 1.4, 0.4) << "1.4 m in front of the robot";
  EXPECT_LT(std::abs(ahead.x() * offset.y() - ahead.y() * offset.x()), 0.4) << "on its way";
}

/// The least surface-to-surface gap between the person walking east along y = 2.6 and the robot
/// standing at (5, 2).
double closest_gap(const json& behaviour) {
  const json steps = json::parse(R"([{"name": "go", "actions": [{"agent": "p", "goto": {"pose": {"x": 9, "y": 2.6}}}]}])");
  Watch watch(scene(behaviour, {{"x", 1}, {"y", 2.6}, {"theta", 0}}, {{"x", 5}, {"y", 2}, {"theta", 3.14159}}, steps));
  double gap = 1e9;
  while (!watch.session.state().finished) {
    watch.session.tick();
    gap = std::min(gap, watch.distance() - 0.6);
  }
  EXPECT_GT(watch.person().position.x(), 8.5) << "it got there";
  return gap;
}

TEST(Behaviours, TheImpassiveOnePassesTheRobotAsAnObstacleTheRegularOneKeepsItsSpace) {
  const double regular = closest_gap("regular"), impassive = closest_gap("impassive");
  EXPECT_GT(regular, humans::kPersonalSpaceFromRobots - 0.05);
  EXPECT_LT(impassive, regular - 0.1);
  EXPECT_GT(impassive, humans::kLimbClearance - 0.05) << "its feet clear the robot";
}

TEST(Behaviours, TheRegularOneDoesNotReactAndACommandChangesTheBehaviour) {
  Watch watch(scene("regular", {{"x", 9}, {"y", 3}, {"theta", 3.14159}}, {{"x", 2}, {"y", 2}, {"theta", 0}}, kWalkWest));
  watch.run_until(3.0);
  EXPECT_LT(watch.reaction_started(), 0.0);
  testing::command(watch.session, "p", "behaviour surprised");
  EXPECT_EQ(watch.person().reaction.behaviour.type, humans::BehaviourType::regular) << "a command acts at the next tick";
  watch.run_until(8.0);
  EXPECT_EQ(watch.person().reaction.behaviour.type, humans::BehaviourType::surprised);
  EXPECT_DOUBLE_EQ(watch.person().reaction.behaviour.detection_distance, 4.0);
  EXPECT_GE(watch.reaction_started(), 3.0);
  EXPECT_THROW(testing::command(watch.session, "p", "behaviour grumpy"), core::Error);
}

TEST(Behaviours, AScenarioOverridesTheDefaults) {
  const auto model = testing::load_valid(scene({{"type", "curious"}, {"distance", 2.5}, {"once", false}}, {{"x", 8}, {"y", 2}},
                                               {{"x", 2}, {"y", 2}}, json::array()));
  ASSERT_TRUE(model);
  const humans::Behaviour& curious = model->agents[0].behaviour;
  EXPECT_EQ(curious.type, humans::BehaviourType::curious);
  EXPECT_DOUBLE_EQ(curious.distance, 2.5);
  EXPECT_FALSE(curious.once);
  EXPECT_DOUBLE_EQ(curious.detection_distance, 10.0) << "the rest stays HuNavSim's";
  scenario::LoadOptions options;
  EXPECT_FALSE(scenario::load_scenario(scene("grumpy", {{"x", 8}, {"y", 2}}, {{"x", 2}, {"y", 2}}, json::array()), options).errors.empty());
}

}  // namespace
}  // namespace hrisim::sim
