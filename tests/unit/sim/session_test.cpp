#include "sim/session.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <set>

#include "core/error.hpp"
#include "episode/episode.hpp"
#include "support/commands.hpp"
#include "support/events.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;
using scenario::Model;

std::shared_ptr<const Model> model_of(const std::string& extra) {
  auto model = testing::load_valid(testing::room_scenario(json::parse(extra)));
  if (!model) throw std::runtime_error("invalid test scenario");
  return model;
}

using testing::events_of;

double step_duration(const Session& session, int step) {
  const StepRecord& record = session.state().steps[step];
  return static_cast<double>(record.finished_tick - record.started_tick) * session.model().dt;
}

TEST(Session, GotoReachesTheLocationAndTakesItsHeading) {
  episode::Episode session_run(model_of(R"({
    "locations": {"window": {"x": 8, "y": 2, "theta": 1.5708, "radius": 0.2}},
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}, "preferred_speed": 1.2}],
    "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"location": "window"}}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  const AgentState& ana = session.state().agents[0];
  EXPECT_LE((ana.position - Vec2(8, 2)).norm(), 0.2 + 1e-9);
  EXPECT_NEAR(ana.heading, 1.5708, kHeadingTolerance);
  // 6 m at 1.2 m/s, plus the acceleration, the slow-down before the goal and the final turn.
  EXPECT_GT(step_duration(session, 0), 6.0 / 1.2);
  EXPECT_LT(step_duration(session, 0), 6.0 / 1.2 + 3.0);
}

TEST(Session, GotoWalksAroundTheTable) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ana", "start": {"x": 3, "y": 5}, "preferred_speed": 1.3}],
    "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 7, "y": 5}}}]}]})"), 1);
  Session& session = session_run.session();
  // The table covers [4.4, 5.6] × [4.6, 5.4]; ana's disc (0.3 m) must stay off it.
  double closest_to_table = 1e9;
  while (!session.state().finished) {
    session.tick();
    const Vec2 p = session.state().agents[0].position;
    const Vec2 on_table(std::clamp(p.x(), 4.4, 5.6), std::clamp(p.y(), 4.6, 5.4));
    closest_to_table = std::min(closest_to_table, (p - on_table).norm());
  }
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_GT(closest_to_table, 0.3 - 0.05) << "within half a grid cell of the planned clearance";
}

TEST(Session, StepActionsStartTogetherAndTheStepEndsWithTheLast) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}, {"id": "ben", "start": {"x": 2, "y": 8}}],
    "steps": [
      {"name": "waits", "actions": [{"agent": "ana", "wait": {"duration": 1}}, {"agent": "ben", "wait": {"duration": 2.5}}]},
      {"name": "short", "actions": [{"agent": "ana", "wait": {"duration": 0.5}}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_NEAR(step_duration(session, 0), 2.5, 1e-9);
  EXPECT_NEAR(step_duration(session, 1), 0.5, 1e-9);
  EXPECT_EQ(session.state().steps[1].started_tick, session.state().steps[0].finished_tick);
  EXPECT_EQ(events_of<sim::events::StepStarted>(session).size(), 2u);
  EXPECT_EQ(events_of<sim::events::ScenarioFinished>(session).size(), 1u);
}

TEST(Session, SeveralActionsOfOneAgentInAStepRunInOrder) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}],
    "steps": [{"name": "s", "actions": [{"agent": "ana", "wait": {"duration": 1}}, {"agent": "ana", "wait": {"duration": 2}}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_NEAR(step_duration(session, 0), 3.0, 1e-9);
}

TEST(Session, CompoundTasksRunTheirActionsInOrder) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}],
    "routines": {"inner": [{"wait": {"duration": 1}}, {"publish": {"topic": "/t", "message": "inner"}}],
              "outer": [{"routine": "inner"}, {"wait": {"duration": 0.5}}, {"publish": {"topic": "/t", "message": "outer"}}]},
    "steps": [{"name": "s", "actions": [{"agent": "ana", "routine": "outer"}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  const auto published = events_of<sim::events::Publish>(session);
  ASSERT_EQ(published.size(), 2u);
  EXPECT_EQ(published[0]->as<events::Publish>()->message, "inner");
  EXPECT_NEAR(published[0]->time, 1.0, 1e-9);
  EXPECT_EQ(published[1]->as<events::Publish>()->message, "outer");
  EXPECT_NEAR(published[1]->time, 1.5, 1e-9);
  EXPECT_EQ(published[1]->subject, "ana");
}

TEST(Session, ARepeatedTaskRunsOverAndOverUntilTheTimeLimit) {
  episode::Episode session_run(model_of(R"({
    "time_limit": 20,
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}],
    "routines": {"round": [{"wait": {"duration": 1.5}}, {"publish": {"topic": "/lap", "message": "done"}}]},
    "steps": [{"name": "s", "actions": [{"agent": "ana", "routine": "round", "repeat": true}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  const auto laps = events_of<sim::events::Publish>(session);
  ASSERT_EQ(laps.size(), 13u) << "one lap every 1.5 s for 20 s";
  for (std::size_t k = 0; k < laps.size(); ++k) EXPECT_NEAR(laps[k]->time, 1.5 * static_cast<double>(k + 1), 1e-9);
  EXPECT_EQ(session.state().termination, sim::Termination::timeout) << "its step never ends";
}

TEST(Session, ARoutineRepeatedForeverMustTakeTime) {
  json document = testing::room_scenario(json::parse(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}],
    "routines": {"instant": [{"publish": {"topic": "/t", "message": "x"}}, {"wait": {"duration": 0}}],
              "outer": [{"routine": "instant", "repeat": true}]},
    "steps": [{"name": "s", "actions": [{"agent": "ana", "routine": "instant", "repeat": true}]}]})"));
  EXPECT_EQ(testing::error_at(document, "/steps/0/actions/0/repeat"),
            "routine 'instant' repeats forever without an action that takes time (a goto, a wait, a motion, …)");
  EXPECT_EQ(testing::error_at(document, "/routines/outer/0/repeat"),
            "routine 'instant' repeats forever without an action that takes time (a goto, a wait, a motion, …)");
}

TEST(Session, WaitForAMessageSeesTheLatestOne) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}, {"id": "ben", "start": {"x": 2, "y": 8}}],
    "steps": [
      {"name": "early", "actions": [{"agent": "ben", "publish": {"topic": "/door", "message": "open"}}]},
      {"name": "later", "actions": [{"agent": "ana", "wait": {"topic": "/door", "message": "open"}},
                                    {"agent": "ben", "wait": {"duration": 2}},
                                    {"agent": "ben", "publish": {"topic": "/door", "message": "closed"}},
                                    {"agent": "ben", "wait": {"duration": 1}},
                                    {"agent": "ben", "publish": {"topic": "/door", "message": "open"}}]},
      {"name": "again", "actions": [{"agent": "ana", "wait": {"topic": "/door", "message": "closed"}}]}]})"), 1);
  Session& session = session_run.session();
  session.set_time_limit(20.0);
  session_run.run();
  EXPECT_EQ(session.state().topics.at("/door"), "open");
  // A published state is latched: ana's first wait ends at once; the one for "closed" never does.
  EXPECT_EQ(session.state().current_step, 2);
  EXPECT_EQ(session.state().termination, sim::Termination::timeout);
  EXPECT_EQ(events_of<sim::events::TimeLimit>(session)[0]->subject, "again");
}

/// Final heading of ana (starting at heading 0) after one turning action, and how long it took.
std::pair<double, double> turn(const std::string& action) {
  episode::Episode session_run(model_of(R"({
    "locations": {"door": {"x": 2, "y": 8}},
    "objects": [{"name": "ball", "shape": {"kind": "sphere", "radius": 0.1}, "mass": 0.4, "pose": {"x": 0.5, "y": 2, "z": 0.1}}],
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2, "theta": 0}}, {"id": "ben", "start": {"x": 8, "y": 8}}],
    "steps": [{"name": "turn", "actions": [{"agent": "ana", )" + action + R"(}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end) << action;
  return {session.state().agents[0].heading, step_duration(session, 0)};
}

TEST(Session, TurnAndLookAt) {
  const auto [by, by_duration] = turn(R"("turn": {"by": 1.0})");
  EXPECT_NEAR(by, 1.0, 1e-9);
  EXPECT_NEAR(by_duration, 1.0 / kTurnRate, 2.0 / 60.0) << "turning 1 rad at the named turn rate";
  EXPECT_NEAR(turn(R"("turn": {"to": -2.0})").first, -2.0, 1e-9);
  EXPECT_NEAR(turn(R"("look_at": {"angle": 3.0})").first, 3.0, 1e-9);
  EXPECT_NEAR(turn(R"("look_at": {"location": "door"})").first, std::numbers::pi / 2, 1e-9);
  EXPECT_NEAR(turn(R"("look_at": {"agent": "ben"})").first, std::numbers::pi / 4, 1e-9);
  EXPECT_NEAR(std::abs(turn(R"("look_at": {"object": "ball"})").first), std::numbers::pi, 1e-6) << "IMHuS's LookAt an object: the ball";
  EXPECT_NEAR(turn(R"("look_at": {"object": "table"})").first, std::numbers::pi / 4, 1e-9) << "...or the table's centre (5, 5)";
  EXPECT_NEAR(turn(R"("turn": {"by": 4.0})").first, 4.0 - 2 * std::numbers::pi, 1e-9) << "headings wrap into (-pi, pi]";
}

TEST(Session, LookingAtAnUnknownObjectIsRefusedWhereItIsWritten) {
  const auto errors = scenario::load_scenario(testing::room_scenario(json::parse(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}],
    "steps": [{"name": "look", "actions": [{"agent": "ana", "look_at": {"object": "vase"}}]}]})")), {}).errors;
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].pointer, "/steps/0/actions/0/look_at/object");
  EXPECT_EQ(errors[0].message, "no movable object or obstacle named 'vase'");
}

TEST(Session, SocialSpaceSlotsAreTakenInOrder) {
  episode::Episode session_run(model_of(R"({
    "social_spaces": {"bench": {"x": 5, "y": 8, "slots": [{"x": -1, "y": 0}, {"x": 0, "y": 0}, {"x": 1, "y": 0}]}},
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}, {"id": "ben", "start": {"x": 5, "y": 2}},
               {"id": "cat", "start": {"x": 8.5, "y": 8}}],
    "steps": [{"name": "sit", "actions": [{"agent": "ana", "goto": {"social_space": "bench"}},
                                          {"agent": "ben", "goto": {"social_space": "bench"}}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  // cat stands within two radii of slot 2 (6, 8)? No: 2.5 m away, so slots 0 and 1 go to ana and ben.
  EXPECT_LE((session.state().agents[0].position - Vec2(4, 8)).norm(), 0.2 + 1e-9);
  EXPECT_LE((session.state().agents[1].position - Vec2(5, 8)).norm(), 0.2 + 1e-9);
  EXPECT_EQ(session.state().agents[0].reservation.slot.value, 0);
  EXPECT_EQ(session.state().agents[1].reservation.slot.value, 1);
}

TEST(Session, OccupiedSlotIsSkipped) {
  episode::Episode session_run(model_of(R"({
    "social_spaces": {"bench": {"x": 5, "y": 8, "slots": [{"x": -1, "y": 0}, {"x": 0, "y": 0}]}},
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}, {"id": "sitter", "start": {"x": 4.2, "y": 8}}],
    "steps": [{"name": "sit", "actions": [{"agent": "ana", "goto": {"social_space": "bench"}}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_LE((session.state().agents[0].position - Vec2(5, 8)).norm(), 0.2 + 1e-9)
      << "slot 0 has someone within two radii, so ana takes slot 1";
}

TEST(Session, ALocationHoldsOnePerson) {
  episode::Episode session_run(model_of(R"({
    "locations": {"spot": {"x": 5, "y": 8}},
    "humans": [{"id": "ana", "start": {"x": 2, "y": 8}}, {"id": "ben", "start": {"x": 8, "y": 8}}],
    "steps": [
      {"name": "first", "actions": [{"agent": "ana", "goto": {"location": "spot"}}]},
      {"name": "both", "actions": [{"agent": "ben", "goto": {"location": "spot"}},
                                   {"agent": "ana", "wait": {"duration": 3}},
                                   {"agent": "ana", "goto": {"pose": {"x": 2, "y": 2}}}]}]})"), 1);
  Session& session = session_run.session();
  double ben_closest_while_ana_there = 1e9;
  while (!session.state().finished) {
    session.tick();
    const State& state = session.state();
    if (state.current_step == 1 && state.agents[0].reservation.location.value == 0) {
      ben_closest_while_ana_there = std::min(ben_closest_while_ana_there, (state.agents[1].position - Vec2(5, 8)).norm());
    }
  }
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_GT(ben_closest_while_ana_there, 2.0) << "ben waits until ana leaves the spot";
  EXPECT_LE((session.state().agents[1].position - Vec2(5, 8)).norm(), 0.2 + 1e-9);
}

const char* kRequestScenario = R"({
  "humans": [{"id": "near", "start": {"x": 3, "y": 2}}, {"id": "nearest", "start": {"x": 2.5, "y": 2}},
             {"id": "far", "start": {"x": 8, "y": 8}}],
  "robots": [{"id": "robot", "start": {"x": 1, "y": 2}}],
  "routines": {"press": [{"look_at": {"agent": "robot"}}, {"publish": {"topic": "/button", "message": "pressed"}}]},
  "async": [{"routine": "press"}],
  "steps": [{"name": "idle", "actions": [{"agent": "far", "wait": {"duration": 40}}]}]})";

TEST(Requests, TheClosestIdleHumanWithinThreeMetresAnswers) {
  episode::Episode session_run(model_of(kRequestScenario), 1);
  Session& session = session_run.session();
  session.request(session.agent_id("robot"), 0);
  session.set_time_limit(5.0);
  session_run.run();
  const auto accepted = events_of<sim::events::RequestAccepted>(session);
  ASSERT_EQ(accepted.size(), 1u);
  EXPECT_EQ(accepted[0]->subject, "nearest");
  EXPECT_EQ(accepted[0]->tick, 0);
  EXPECT_EQ(session.state().topics.at("/button"), "pressed");
}

TEST(Requests, BusyHumansDoNotAnswerAndTheRequestIsRetriedThenDropped) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "busy", "start": {"x": 3, "y": 2}}, {"id": "far", "start": {"x": 8, "y": 8}}],
    "robots": [{"id": "robot", "start": {"x": 1, "y": 2}}],
    "routines": {"press": [{"publish": {"topic": "/button", "message": "pressed"}}]},
    "async": [{"routine": "press"}],
    "steps": [{"name": "work", "actions": [{"agent": "busy", "wait": {"duration": 12}}, {"agent": "far", "wait": {"duration": 50}}]}]})"), 1);
  Session& session = session_run.session();
  session.request(session.agent_id("robot"), 0);
  session.set_time_limit(20.0);
  session_run.run();
  const auto accepted = events_of<sim::events::RequestAccepted>(session);
  ASSERT_EQ(accepted.size(), 1u) << "busy becomes idle at 12 s; the retry at 15 s finds it";
  EXPECT_NEAR(accepted[0]->time, 15.0, 1e-9);

  episode::Episode nobody_run(model_of(R"({
    "humans": [{"id": "far", "start": {"x": 8, "y": 8}}],
    "robots": [{"id": "robot", "start": {"x": 1, "y": 2}}],
    "routines": {"press": [{"publish": {"topic": "/button", "message": "pressed"}}]},
    "async": [{"routine": "press"}],
    "steps": [{"name": "s", "actions": [{"agent": "far", "wait": {"duration": 50}}]}]})"), 1);
  Session& nobody = nobody_run.session();
  nobody.request(nobody.agent_id("robot"), 0);
  nobody.set_time_limit(40.0);
  nobody_run.run();
  const auto dropped = events_of<sim::events::RequestDropped>(nobody);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_NEAR(dropped[0]->time, kRequestTimeout, 1e-9);
  EXPECT_TRUE(events_of<sim::events::RequestAccepted>(nobody).empty());
}

TEST(Requests, UnknownAsyncTaskIsDroppedAtOnce) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}],
    "robots": [{"id": "robot", "start": {"x": 1, "y": 2}}],
    "routines": {"dance": [{"wait": {"duration": 1}}]},
    "steps": []})"), 1);
  Session& session = session_run.session();
  session.request(session.agent_id("robot"), 0);
  const auto dropped = events_of<sim::events::RequestDropped>(session);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0]->tick, 0);
}

TEST(Requests, ScriptedRequestsFireAtTheirTime) {
  json extra = json::parse(kRequestScenario);
  extra["requests"] = json::parse(R"([{"time": 2.0, "routine": "press"}])");
  episode::Episode session_run(testing::load_valid(testing::room_scenario(extra)), 1);
  Session& session = session_run.session();
  session.set_time_limit(5.0);
  session_run.run();
  const auto requests = events_of<sim::events::Request>(session);
  ASSERT_EQ(requests.size(), 1u);
  EXPECT_NEAR(requests[0]->time, 2.0, 1e-9);
}

const char* kCrowd = R"({
  "humans": [{"id": "a", "start": {"x": 1, "y": 1}}, {"id": "b", "start": {"x": 9, "y": 9}},
             {"id": "c", "start": {"x": 1, "y": 9}, "avoidance": "social_force"}, {"id": "d", "start": {"x": 9, "y": 1}}],
  "steps": [{"name": "swap", "actions": [
    {"agent": "a", "goto": {"pose": {"x": 9, "y": 8.5}}}, {"agent": "b", "goto": {"pose": {"x": 1, "y": 1.5}}},
    {"agent": "c", "goto": {"pose": {"x": 9, "y": 1.5}}}, {"agent": "d", "goto": {"pose": {"x": 1, "y": 8.5}}}]}]})";

std::vector<std::uint64_t> hashes(std::uint64_t seed) {
  episode::Episode session_run(model_of(kCrowd), seed);
  Session& session = session_run.session();
  std::vector<std::uint64_t> result;
  for (int i = 0; i < 900; ++i) {
    session.tick();
    result.push_back(session.state_hash());
  }
  return result;
}

TEST(Determinism, SameSeedSameHashesEveryStep) {
  const auto first = hashes(7);
  EXPECT_EQ(first, hashes(7));
  EXPECT_EQ(first, hashes(7));
}

TEST(Determinism, AnotherSeedDrawsOtherSpeeds) {
  EXPECT_NE(hashes(7).back(), hashes(8).back());
}

TEST(Determinism, TimeIsTicksTimesDt) {
  episode::Episode session_run(model_of(kCrowd), 1);
  Session& session = session_run.session();
  for (int i = 0; i < 1000; ++i) session.tick();
  EXPECT_EQ(session.time(), 1000 * session.model().dt);
}

TEST(Session, DrawnSpeedsFollowTheNamedDistribution) {
  json many = json::parse(R"({"humans": [], "steps": []})");
  for (int i = 0; i < 400; ++i) {
    many["humans"].push_back({{"id", "h" + std::to_string(i)}, {"start", {{"x", 1 + (i % 40) * 0.2}, {"y", 1 + (i / 40) * 0.2}}}});
  }
  episode::Episode session_run(testing::load_valid(testing::room_scenario(many)), 3);
  Session& session = session_run.session();
  double sum = 0, sum_squares = 0;
  for (const AgentState& agent : session.state().agents) {
    EXPECT_GE(agent.preferred_speed, scenario::kPreferredSpeedMin);
    EXPECT_LE(agent.preferred_speed, scenario::kPreferredSpeedMax);
    sum += agent.preferred_speed;
    sum_squares += agent.preferred_speed * agent.preferred_speed;
  }
  const double mean = sum / 400, stddev = std::sqrt(sum_squares / 400 - mean * mean);
  EXPECT_NEAR(mean, scenario::kPreferredSpeedMean, 0.04);
  EXPECT_NEAR(stddev, scenario::kPreferredSpeedStddev, 0.04);
}


TEST(Groups, APairWalksSideBySide) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ann", "start": {"x": 1.5, "y": 5, "theta": 0}, "preferred_speed": 1.2},
               {"id": "bo", "start": {"x": 1.5, "y": 4.3, "theta": 0}, "preferred_speed": 1.3}],
    "groups": {"pair": {"members": ["ann", "bo"]}},
    "steps": [{"name": "walk", "actions": [{"group": "pair", "goto": {"pose": {"x": 3, "y": 8.5, "theta": 0}}}]}]})"), 1);
  Session& session = session_run.session();
  double farthest_apart = 0.0;
  while (!session.state().finished) {
    session.tick();
    farthest_apart = std::max(farthest_apart, (session.state().agents[0].position - session.state().agents[1].position).norm());
  }
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_LT(farthest_apart, 1.5) << "bo keeps beside ann all the way";
  const Vec2 ann = session.state().agents[0].position, bo = session.state().agents[1].position;
  EXPECT_LE((ann - Vec2(3, 8.5)).norm(), 0.2 + 1e-9);
  // Facing +x at the goal, bo's spot is kFormationSpacing to ann's right (−y).
  EXPECT_NEAR((bo - (ann + Vec2(0, -scenario::kFormationSpacing))).norm(), 0.0, kHoldTolerance);
}

TEST(Groups, APairRunsACompoundTaskTogether) {
  // IMHuS's compound tasks given to a group: every member runs the task; its gotos are walked in
  // formation, its other actions by each member.
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ann", "start": {"x": 1.5, "y": 5, "theta": 0}}, {"id": "bo", "start": {"x": 1.5, "y": 4.3, "theta": 0}},
               {"id": "cy", "start": {"x": 8, "y": 2}}],
    "groups": {"pair": {"members": ["ann", "bo"]}},
    "routines": {"visit": [{"goto": {"pose": {"x": 3, "y": 8.5, "theta": 0}}}, {"look_at": {"agent": "cy"}}, {"wait": {"duration": 1}},
                        {"goto": {"pose": {"x": 8, "y": 8.5, "theta": 0}}}]},
    "steps": [{"name": "visit", "actions": [{"group": "pair", "routine": "visit"}]},
              {"name": "greet", "actions": [{"group": "pair", "look_at": {"agent": "cy"}}]}]})"), 1);
  Session& session = session_run.session();
  double farthest_apart = 0.0;
  bool both_faced_cy = false;
  while (!session.state().finished) {
    session.tick();
    const auto& agents = session.state().agents;
    farthest_apart = std::max(farthest_apart, (agents[0].position - agents[1].position).norm());
    // On the way, both look at cy (south-east of them) before the second goto.
    const auto faces_cy = [&](int a) { return std::abs(core::wrap_angle(agents[a].heading - core::direction_to(agents[a].position, agents[2].position))) < 0.05; };
    both_faced_cy |= agents[0].position.x() < 4 && faces_cy(0) && faces_cy(1);
  }
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_TRUE(both_faced_cy) << "each member looks at cy";
  EXPECT_LT(farthest_apart, 1.5) << "bo keeps beside ann on both legs";
  const Vec2 ann = session.state().agents[0].position, bo = session.state().agents[1].position;
  EXPECT_LE((ann - Vec2(8, 8.5)).norm(), 0.2 + 1e-9) << "the leader walked the task's last goto";
  EXPECT_LT((bo - ann).norm(), scenario::kFormationSpacing + 0.3) << "and bo arrived beside her";
}

TEST(Groups, GroupsFormAndDismantleAndTakeSlots) {
  episode::Episode session_run(model_of(R"({
    "social_spaces": {"bench": {"x": 5, "y": 8, "slots": [{"x": -1, "y": 0}, {"x": 0, "y": 0}, {"x": 1, "y": 0}]}},
    "humans": [{"id": "ann", "start": {"x": 2, "y": 2}}, {"id": "bo", "start": {"x": 3, "y": 2}}, {"id": "cy", "start": {"x": 8, "y": 2}}],
    "steps": [
      {"name": "form", "actions": [{"agent": "ann", "form_group": {"group": "friends", "members": ["ann", "bo", "cy"]}}]},
      {"name": "sit", "actions": [{"group": "friends", "goto": {"social_space": "bench"}}]},
      {"name": "part", "actions": [{"agent": "cy", "dismantle_group": "friends"}]},
      {"name": "nobody", "actions": [{"group": "friends", "goto": {"pose": {"x": 2, "y": 2}}}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  std::set<int> slots;
  for (int a = 0; a < 3; ++a) slots.insert(session.state().agents[a].reservation.slot.value);
  EXPECT_EQ(slots, (std::set<int>{0, 1, 2})) << "one slot per member";
  EXPECT_EQ(events_of<sim::events::GroupFormed>(session).size(), 1u);
  EXPECT_EQ(events_of<sim::events::GroupDismantled>(session).size(), 1u);
  EXPECT_EQ(events_of<sim::events::GroupEmpty>(session).size(), 1u) << "a dismantled group has nobody to move";
}

TEST(Attitudes, HarassingHumanStandsInTheRobotsWay) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "pest", "start": {"x": 2, "y": 8}}],
    "robots": [{"id": "robot", "start": {"x": 2, "y": 3, "theta": 0}}],
    "steps": [{"name": "annoy", "actions": [{"agent": "pest", "harass": {"robot": "robot", "duration": 12}}]}]})"), 1);
  Session& session = session_run.session();
  session.command_robot(session.agent_id("robot"), Vec2(0.3, 0.0));
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_NEAR(step_duration(session, 0), 12.0, 1e-9);
  const AgentState& pest = session.state().agents[0];
  const AgentState& robot = session.state().agents[1];
  EXPECT_LT((pest.position - (robot.position + Vec2(scenario::kHarassDistance, 0))).norm(), 0.5)
      << "one metre in front of the moving robot";
  EXPECT_NEAR(core::wrap_angle(pest.heading - std::numbers::pi), 0.0, 0.2) << "facing the robot";
}

const char* kStopAndLook = R"({
    "humans": [{"id": "ann", "start": {"x": 1.5, "y": 2}, "preferred_speed": 1.0}],
    "robots": [{"id": "robot", "start": {"x": 5, "y": 3.5}}],
    "steps": [{"name": "walk", "actions": [{"agent": "ann", "stop_and_look": {"robot": "robot", "duration": 8}},
                                           {"agent": "ann", "goto": {"pose": {"x": 8.5, "y": 2}}}]}]})";

TEST(Attitudes, StopAndLookWhenTheRobotComesNear) {
  episode::Episode session_run(model_of(kStopAndLook), 1);
  Session& session = session_run.session();
  session.set_time_limit(6.0);
  session_run.run();
  const AgentState& ann = session.state().agents[0];
  EXPECT_LT((ann.position - Vec2(5, 3.5)).norm(), scenario::kStopAndLookDistance + 0.1) << "stopped near the robot";
  EXPECT_GT((ann.position - Vec2(5, 3.5)).norm(), scenario::kStopAndLookDistance - 0.3);
  EXPECT_LT(ann.velocity.norm(), 0.1);
  EXPECT_NEAR(core::wrap_angle(ann.heading - std::atan2(3.5 - ann.position.y(), 5 - ann.position.x())), 0.0, 0.1)
      << "facing it";
  episode::Episode until_end_run(model_of(kStopAndLook), 1);
  Session& until_end = until_end_run.session();
  until_end_run.run();
  EXPECT_EQ(until_end.state().termination, sim::Termination::scenario_end) << "after the attitude ends she walks on";
  EXPECT_GT(until_end.time(), 8.0);
}

TEST(RobotChoreography, TheRobotWalksAsksAndWaitsForTheOutcome) {
  episode::Episode session_run(model_of(R"({
    "time_limit": 200,
    "humans": [{"id": "ann", "start": {"x": 8, "y": 8}}],
    "robots": [{"id": "robot", "start": {"x": 2, "y": 2}}],
    "routines": {"greet": [{"look_at": {"agent": "robot"}}, {"publish": {"topic": "/greeting", "message": "hi"}}]},
    "async": [{"routine": "greet"}],
    "steps": [
      {"name": "approach", "actions": [{"agent": "robot", "goto": {"pose": {"x": 7, "y": 7}, "radius": 0.5}}]},
      {"name": "ask", "actions": [{"agent": "robot", "request": {"routine": "greet"}}]},
      {"name": "far", "actions": [{"agent": "robot", "goto": {"pose": {"x": 2, "y": 2}, "radius": 0.5}}]},
      {"name": "ask_again", "actions": [{"agent": "robot", "request": {"routine": "greet"}}]}]})"), 1);
  Session& session = session_run.session();
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_EQ(events_of<sim::events::RequestAccepted>(session).size(), 1u) << "ann is within 3 m at the first request";
  EXPECT_EQ(events_of<sim::events::RequestDropped>(session).size(), 1u) << "and far away at the second";
  EXPECT_NEAR(step_duration(session, 1), session.model().dt, 1e-9) << "accepted on the next tick";
  EXPECT_NEAR(step_duration(session, 3), kRequestTimeout, 1e-9) << "waits until it is dropped";
  EXPECT_EQ(session.state().topics.at("/greeting"), "hi");
}


TEST(AgentIds, RemovedAgentsLeaveAndTheirIdsGoStale) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ann", "start": {"x": 2, "y": 2}}, {"id": "bo", "start": {"x": 8, "y": 2}}],
    "robots": [{"id": "robot", "start": {"x": 5, "y": 8}}],
    "steps": [{"name": "waits", "actions": [{"agent": "ann", "wait": {"duration": 1}}, {"agent": "bo", "wait": {"duration": 50}}]}]})"), 1);
  Session& session = session_run.session();
  const AgentId bo = session.agent_id("bo");
  EXPECT_EQ(session.index_of(bo), 1);
  EXPECT_EQ(session.agent_ids().size(), 3u);
  EXPECT_THROW(session.agent_id("zoe"), core::Error);
  for (int tick = 0; tick < 120; ++tick) session.tick();
  session.remove_agent(bo);
  EXPECT_THROW(session.index_of(bo), core::Error) << "a stale id fails loudly";
  EXPECT_THROW(session.remove_agent(bo), core::Error);
  EXPECT_THROW(session.command_robot(bo, Vec2::Zero()), core::Error);
  const std::vector<AgentId> left = session.agent_ids();
  ASSERT_EQ(left.size(), 2u);
  EXPECT_EQ(session.index_of(left[0]), 0) << "creation order";
  EXPECT_EQ(session.index_of(left[1]), 2);
  session.tick();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end) << "the step no longer waits for bo";
  EXPECT_FALSE(session.state().agents[1].active);
  EXPECT_EQ(events_of<sim::events::AgentRemoved>(session).size(), 1u);
}

}  // namespace
}  // namespace hrisim::sim

namespace hrisim::sim {
namespace {

TEST(Session, TextualCommandsGoFirstAndTheChoreographyResumes) {
  episode::Episode session_run(model_of(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}, "preferred_speed": 1.2}, {"id": "ben", "start": {"x": 8, "y": 8}}],
    "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 8, "y": 2}}}]}]})"), 1);
  Session& session = session_run.session();
  testing::command(session, "ana", "walk 2 8");
  double closest_to_detour = 1e9;
  while (!session.state().finished && session.time() < 50) {
    session.tick();
    closest_to_detour = std::min(closest_to_detour, (session.state().agents[0].position - Vec2(2, 8)).norm());
  }
  EXPECT_LE(closest_to_detour, scenario::kDefaultGoalRadius + 1e-9) << "walked to the commanded spot first";
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_LE((session.state().agents[0].position - Vec2(8, 2)).norm(), 0.2 + 1e-9) << "then did her step";
  ASSERT_EQ(events_of<sim::events::Command>(session).size(), 1u);
  EXPECT_EQ(events_of<sim::events::Command>(session)[0]->as<events::Command>()->text, "walk 2 8");
}

TEST(Session, BadTextualCommandsSayWhatIsWrong) {
  episode::Episode session_run(model_of(R"({
    "locations": {"door": {"x": 1, "y": 1}},
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}],
    "robots": [{"id": "bot", "start": {"x": 3, "y": 3}}],
    "steps": [{"name": "wait", "actions": [{"agent": "ana", "wait": {"duration": 1}}]}]})"), 1);
  Session& session = session_run.session();
  const AgentId ana = session.agent_id("ana");
  const auto message = [&](AgentId who, const std::string& text) {
    try {
      session.command_human(scenario::parse_human_command(session.model(), session.index_of(who), text), text);
    } catch (const core::Error& e) {
      EXPECT_EQ(e.code(), core::ErrorCode::bad_request) << text;
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(ana, "dance").find("unknown command 'dance'"), std::string::npos);
  EXPECT_NE(message(ana, "walk 5").find("walk: y must be a number"), std::string::npos);
  EXPECT_NE(message(ana, "walk 5 5").find("not free floor"), std::string::npos) << "the table";
  EXPECT_NE(message(ana, "walk 50 5").find("not free floor"), std::string::npos) << "off the map";
  EXPECT_NE(message(ana, "wait -1").find("must not be negative"), std::string::npos);
  EXPECT_NE(message(ana, "wait 2 3").find("unexpected '3'"), std::string::npos);
  EXPECT_NE(message(ana, "look_at nobody").find("no agent, location, object or obstacle named 'nobody'"), std::string::npos);
  EXPECT_NE(message(session.agent_id("bot"), "wait 1").find("is not a human"), std::string::npos);
  EXPECT_EQ(message(ana, "look_at door"), "accepted");
  EXPECT_EQ(message(ana, "look_at bot"), "accepted");
  EXPECT_EQ(message(ana, "look_at table"), "accepted");
  EXPECT_EQ(session.state().commanded.back().kind, scenario::Action::Kind::look_at_object);
  EXPECT_EQ(session.state().commanded.size(), 3u) << "refused commands leave nothing behind";
}

}  // namespace
}  // namespace hrisim::sim
