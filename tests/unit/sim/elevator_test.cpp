// The elevator of IMHuS's use case, on hrisim's bundled elevator world (scenarios/maps/elevator.world.json).
#include <gtest/gtest.h>

#include <fstream>

#include "episode/episode.hpp"
#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

json elevator_scenario(const std::string& extra) {
  std::ifstream world_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/maps/elevator.world.json");
  json scenario{{"name", "elevator test"}, {"world", json::parse(world_file)}, {"time_limit", 120}, {"steps", json::array()},
                {"social_spaces", {{"elevator", {{"x", 0}, {"y", 0}, {"slots", json::array({{{"x", 0.5}, {"y", 0.5}}, {{"x", -0.5}, {"y", -0.5}}})}}}}}};
  scenario.merge_patch(json::parse(extra));
  return scenario;
}

struct Timeline {
  std::vector<std::pair<double, std::string>> door_states;  ///< time, "door1 opening" ...
  std::vector<std::pair<double, std::string>> trips;        ///< time, "departed 1->2" / "arrived 2"
};

Timeline timeline_of(const Session& session) {
  Timeline timeline;
  for (const Event& event : session.state().events) {
    if (const auto* door = event.as<events::DoorState>()) {
      timeline.door_states.emplace_back(event.time, event.subject + " " + std::string(phase_name(door->state)));
    } else if (const auto* departed = event.as<events::ElevatorDeparted>()) {
      timeline.trips.emplace_back(event.time, "departed " + std::to_string(departed->from + 1) + "->" + std::to_string(departed->to + 1));
    } else if (const auto* arrived = event.as<events::ElevatorArrived>()) {
      timeline.trips.emplace_back(event.time, "arrived " + std::to_string(arrived->floor + 1));
    }
  }
  return timeline;
}

constexpr double kTick = 1.0 / 60.0;
// Doors are 1.2 m wide: 1.2 / 0.5 m/s = 2.4 s to open or close.
constexpr double kDoorMotion = 1.2 / scenario::kElevatorDoorSpeed;

TEST(Elevator, DoorOpensStaysOpenAndCloses) {
  episode::Episode session_run(testing::load_valid(elevator_scenario(R"({
    "humans": [{"id": "ann", "start": {"x": 2, "y": 1}}],
    "steps": [{"name": "call", "actions": [{"agent": "ann", "publish": {"topic": "/elevator/request", "message": "door1"}},
                                           {"agent": "ann", "wait": {"topic": "/elevator/door1_state", "message": "open"}}]},
              {"name": "linger", "actions": [{"agent": "ann", "wait": {"duration": 25}}]}]})")),
                  1);
  Session& session = session_run.session();
  session.set_time_limit(30.0);
  session_run.run();
  const Timeline timeline = timeline_of(session);
  ASSERT_EQ(timeline.door_states.size(), 4u);
  EXPECT_EQ(timeline.door_states[0].second, "door1 opening");
  EXPECT_EQ(timeline.door_states[1].second, "door1 open");
  EXPECT_NEAR(timeline.door_states[1].first - timeline.door_states[0].first, kDoorMotion, 2 * kTick);
  EXPECT_EQ(timeline.door_states[2].second, "door1 closing");
  EXPECT_NEAR(timeline.door_states[2].first - timeline.door_states[1].first, scenario::kElevatorOpenTime, 2 * kTick);
  EXPECT_EQ(timeline.door_states[3].second, "door1 closed");
  EXPECT_NEAR(timeline.door_states[3].first - timeline.door_states[2].first, kDoorMotion, 2 * kTick);
  EXPECT_TRUE(timeline.trips.empty()) << "the cabin starts at floor 1";
  EXPECT_EQ(session.state().steps[0].finished_tick, static_cast<std::int64_t>(std::llround(timeline.door_states[1].first / kTick)))
      << "the wait for 'open' ends when the door is open";
  EXPECT_EQ(session.state().topics.at("/elevator/door1_state"), "closed");
  EXPECT_EQ(session.state().topics.at("/elevator/door2_state"), "closed");
}

TEST(Elevator, OtherFloorTakesTheTripFirstAndRequestsAreServedInOrder) {
  episode::Episode session_run(testing::load_valid(elevator_scenario(R"({
    "humans": [{"id": "ann", "start": {"x": -2, "y": 1}}],
    "steps": [{"name": "call", "actions": [{"agent": "ann", "publish": {"topic": "/elevator/request", "message": "door2"}},
                                           {"agent": "ann", "publish": {"topic": "/elevator/request", "message": "floor1"}},
                                           {"agent": "ann", "publish": {"topic": "/elevator/request", "message": "basement"}},
                                           {"agent": "ann", "wait": {"duration": 50}}]}]})")),
                  1);
  Session& session = session_run.session();
  session.set_time_limit(60.0);
  session_run.run();
  const Timeline timeline = timeline_of(session);
  ASSERT_GE(timeline.trips.size(), 4u);
  EXPECT_EQ(timeline.trips[0].second, "departed 1->2");
  EXPECT_EQ(timeline.trips[1].second, "arrived 2");
  const double trip = scenario::kElevatorTravelTime + scenario::kElevatorSettleTime;
  EXPECT_NEAR(timeline.trips[1].first - timeline.trips[0].first, trip, 2 * kTick);
  EXPECT_EQ(timeline.door_states[0].second, "door2 opening");
  // floor1 was queued behind door2: the open door closes at once and the cabin goes back.
  EXPECT_EQ(timeline.door_states[2].second, "door2 closing");
  EXPECT_NEAR(timeline.door_states[2].first - timeline.door_states[1].first, 0.0, 2 * kTick);
  EXPECT_EQ(timeline.trips[2].second, "departed 2->1");
  EXPECT_EQ(timeline.trips[3].second, "arrived 1");
  EXPECT_EQ(session.state().events.end() != std::find_if(session.state().events.begin(), session.state().events.end(),
                                                          [](const Event& e) { return e.is<sim::events::ElevatorIgnoredRequest>(); }),
            true);
}

TEST(Elevator, ClosedDoorsAreWalls) {
  episode::Episode session_run(testing::load_valid(elevator_scenario(R"({
    "humans": [{"id": "ann", "start": {"x": 3, "y": 0}}],
    "steps": [{"name": "in", "actions": [{"agent": "ann", "goto": {"pose": {"x": 0, "y": 0}}}]}]})")),
                  1);
  Session& session = session_run.session();
  session.set_time_limit(20.0);
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::timeout);
  EXPECT_GT(session.state().agents[0].position.x(), 1.3) << "ann never passes the closed door";
  const auto unreachable = std::count_if(session.state().events.begin(), session.state().events.end(),
                                         [](const Event& e) { return e.is<sim::events::GoalUnreachable>(); });
  EXPECT_EQ(unreachable, 1);
}

TEST(Elevator, RidersGoInRideAndLeaveOnTheOtherFloor) {
  episode::Episode session_run(testing::load_valid(elevator_scenario(R"({
    "humans": [{"id": "ann", "start": {"x": 3, "y": 0.5}}],
    "routines": {"ride_up": [
      {"publish": {"topic": "/elevator/request", "message": "door1"}},
      {"wait": {"topic": "/elevator/door1_state", "message": "open"}},
      {"goto": {"social_space": "elevator"}},
      {"publish": {"topic": "/elevator/request", "message": "floor2"}},
      {"wait": {"topic": "/elevator/door2_state", "message": "open"}},
      {"goto": {"pose": {"x": -4, "y": 0}}}]},
    "steps": [{"name": "ride", "actions": [{"agent": "ann", "routine": "ride_up"}]}]})")),
                  1);
  Session& session = session_run.session();
  session.set_time_limit(80.0);
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_LT(session.state().agents[0].position.x(), -3.5) << "ann is on floor 2";
  EXPECT_EQ(session.state().agents[0].reservation.space.value, -1) << "the cabin slot was released when the door closed";
}

TEST(Elevator, DoorWaitsForARiderOnTheWay) {
  // Bo strolls to the cabin from 7 m away at 0.3 m/s: the door, open for 10 s, waits for him (up to
  // kElevatorPassengerHold more), then closes once he is in.
  episode::Episode session_run(testing::load_valid(elevator_scenario(R"({
    "humans": [{"id": "ann", "start": {"x": 2, "y": 1}}, {"id": "bo", "start": {"x": 8, "y": 0.5}, "preferred_speed": 0.3}],
    "steps": [{"name": "call", "actions": [{"agent": "ann", "publish": {"topic": "/elevator/request", "message": "door1"}},
                                           {"agent": "ann", "wait": {"topic": "/elevator/door1_state", "message": "open"}}]},
              {"name": "board", "actions": [{"agent": "bo", "goto": {"social_space": "elevator"}}]},
              {"name": "linger", "actions": [{"agent": "ann", "wait": {"duration": 15}}]}]})")),
                  1);
  Session& session = session_run.session();
  session.set_time_limit(70.0);
  double boarded = -1.0, closing = -1.0;
  while (!session.state().finished) {
    session_run.tick();
    const AgentState& bo = session.state().agents[1];
    if (boarded < 0.0 && !bo.navigation.under_way && bo.position.x() < 1.0) boarded = session.time();
    for (const Event& event : session.state().events) {
      const auto* door = event.as<events::DoorState>();
      if (closing < 0.0 && door && door->state == DoorPhase::closing) closing = event.time;
    }
  }
  const Timeline timeline = timeline_of(session);
  ASSERT_GE(timeline.door_states.size(), 2u);
  const double opened = timeline.door_states[1].first;
  ASSERT_GT(boarded, opened + scenario::kElevatorOpenTime) << "he took longer than the door's open time";
  EXPECT_GE(closing, boarded) << "the door waited for him";
  EXPECT_LT(closing, boarded + 1.0);
}

TEST(Elevator, DoorDoesNotStartClosingOnSomeoneInTheDoorway) {
  Session session(testing::load_valid(elevator_scenario(R"({
    "humans": [{"id": "ann", "start": {"x": 2, "y": 1}}, {"id": "bo", "start": {"x": 3, "y": -0.5}}],
    "steps": [{"name": "call", "actions": [{"agent": "ann", "publish": {"topic": "/elevator/request", "message": "door1"}},
                                           {"agent": "ann", "wait": {"topic": "/elevator/door1_state", "message": "open"}}]},
              {"name": "block", "actions": [{"agent": "bo", "goto": {"pose": {"x": 1.3, "y": 0}, "radius": 0.05}},
                                            {"agent": "bo", "wait": {"duration": 20}},
                                            {"agent": "bo", "goto": {"pose": {"x": 3, "y": -0.5}}}]}]})")),
                  1);
  const int bo = session.index_of(session.agent_id("bo"));
  // The last time bo was within the light curtain's sight of the door's leaves (1.3 ± 0.05 m).
  const double sight = session.model().agents[bo].radius + 0.05 + scenario::kElevatorCurtainReach;
  double in_doorway_until = -1.0;
  while (session.time() < 40.0 && session.state().topics.at("/elevator/door1_state") != "closing") {
    session.tick();
    if (std::abs(session.state().agents[bo].position.x() - 1.3) < sight) in_doorway_until = session.time();
  }
  const Timeline timeline = timeline_of(session);
  ASSERT_EQ(timeline.door_states.size(), 3u);
  ASSERT_EQ(timeline.door_states[2].second, "door1 closing");
  // The door stayed open while bo stood in it, well past its open time, and not a tick longer.
  EXPECT_GT(timeline.door_states[2].first, timeline.door_states[1].first + scenario::kElevatorOpenTime + 5.0);
  EXPECT_NEAR(timeline.door_states[2].first, in_doorway_until + kTick, kTick / 2);
}

TEST(Elevator, DoorReopensForARobotDrivenIntoItAsItCloses) {
  episode::Episode session_run(testing::load_valid(elevator_scenario(R"({
    "humans": [{"id": "ann", "start": {"x": 4, "y": 1}}],
    "robots": [{"id": "hsr", "model": "hsr", "start": {"x": 2.0, "y": 0, "theta": 3.14159}, "controller": {"type": "teleop"}}],
    "steps": [{"name": "call", "actions": [{"agent": "ann", "publish": {"topic": "/elevator/request", "message": "door1"}},
                                           {"agent": "ann", "wait": {"duration": 60}}]}]})")),
                  1);
  Session& session = session_run.session();
  const AgentId hsr = session.agent_id("hsr");
  while (session.state().topics.at("/elevator/door1_state") != "closing" && session.time() < 30.0) session.tick();
  ASSERT_EQ(session.state().topics.at("/elevator/door1_state"), "closing");
  session.command_robot_twist(hsr, {0.3, 0.0});
  for (int i = 0; i < 600; ++i) session.tick();
  const Timeline timeline = timeline_of(session);
  ASSERT_GE(timeline.door_states.size(), 4u);
  EXPECT_EQ(timeline.door_states[3].second, "door1 opening") << "the robot pressed into the closing door";
  EXPECT_LT(session.state().agents[session.index_of(hsr)].position.x(), 1.3) << "it drove on into the cabin";
}

}  // namespace
}  // namespace hrisim::sim
