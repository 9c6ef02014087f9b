// Robots with a model inside a session: built-in controllers, sensors and contact events.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "robots/controllers.hpp"
#include "sim/session.hpp"
#include "support/events.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// The test room with one HSR and `extra` merged over it; a human waits long enough to keep it running.
std::shared_ptr<const scenario::Model> with_hsr(const json& robot, const json& extra = json::object()) {
  json scenario = testing::room_scenario(extra);
  json hsr = {{"id", "hsr"}, {"model", "hsr"}, {"start", {{"x", 2}, {"y", 2}, {"theta", 0}}}};
  hsr.merge_patch(robot);
  scenario["robots"] = json::array({hsr});
  if (!scenario.contains("humans")) scenario["humans"] = json::array({{{"id", "ana"}, {"start", {{"x", 8.5}, {"y", 8.5}}}}});
  scenario["steps"] = json::array({{{"name", "wait"}, {"actions", json::array({{{"agent", scenario["humans"][0]["id"]}, {"wait", {{"duration", 55}}}}})}}});
  return testing::load_valid(scenario);
}

using testing::events_of;

TEST(RobotSession, GoalControllerDrivesAroundTheTableToTheGoal) {
  Session session(with_hsr({{"controller", {{"type", "goal"}, {"goal", {{"pose", {{"x", 8}, {"y", 5}}}}}}}}), 1);
  const AgentId hsr = session.agent_id("hsr");
  double closest_to_table = 1e9;
  while (events_of<sim::events::RobotGoalReached>(session).empty() && session.time() < 50.0) {
    session.tick();
    const Vec2 p = session.state().agents[session.index_of(hsr)].position;
    closest_to_table = std::min(closest_to_table, (p - Vec2(std::clamp(p.x(), 4.4, 5.6), std::clamp(p.y(), 4.6, 5.4))).norm());
    ASSERT_LE(session.robot_runtime(hsr)->robot.twist().linear, 0.8 / 3.6 + 0.02) << "HSR's 0.8 km/h";
  }
  ASSERT_EQ(events_of<sim::events::RobotGoalReached>(session).size(), 1u);
  EXPECT_LE((session.state().agents[session.index_of(hsr)].position - Vec2(8, 5)).norm(), 0.2 + 0.01);
  EXPECT_GT(closest_to_table, 0.215 - 0.05) << "the footprint stays off the table";
  // 6 m and the detour at 0.22 m/s.
  EXPECT_GT(session.time(), 6.0 / 0.222);
}

TEST(RobotSession, TeleopDrivesTheBaseAndDiscRobotsRefuseTwists) {
  Session session(with_hsr({{"controller", {{"type", "teleop"}}}}), 1);
  const AgentId hsr = session.agent_id("hsr");
  session.command_robot_twist(hsr, {0.2, 0.0});
  for (int i = 0; i < 300; ++i) session.tick();
  EXPECT_NEAR(session.state().agents[session.index_of(hsr)].position.x(), 2.0 + 0.2 * (5.0 - 1.0 / 60 - 0.1), 0.01);
  const RobotRuntime& runtime = *session.robot_runtime(hsr);
  // Odometry believes about the same, with its own drift.
  EXPECT_GE(runtime.odometry_reading.tick, 295);
  EXPECT_NEAR(runtime.odometry_reading.pose.x, 0.98, 0.05) << "the odometry frame starts at the robot's start";
  EXPECT_NE(runtime.odometry_reading.pose.x, session.state().agents[session.index_of(hsr)].position.x() - 2.0);
  EXPECT_EQ(session.robot_runtime(session.agent_id("ana")), nullptr);
  Session disc(testing::load_valid(testing::room_scenario(json::parse(R"({
    "robots": [{"id": "box", "start": {"x": 2, "y": 2}}],
    "humans": [{"id": "ana", "start": {"x": 8, "y": 8}}],
    "steps": [{"name": "wait", "actions": [{"agent": "ana", "wait": {"duration": 5}}]}]})"))), 1);
  EXPECT_THROW(disc.command_robot_twist(disc.agent_id("box"), {0.1, 0.0}), core::Error);
}

TEST(RobotSession, BaseLaserSeesAPersonsLegsAsTwoArcs) {
  // Ana stands 1.5 m ahead of the laser, facing the robot: her legs are side by side across the beams.
  Session session(with_hsr({{"controller", {{"type", "idle"}}}},
                           {{"humans", json::array({{{"id", "ana"}, {"start", {{"x", 3.7}, {"y", 2}, {"theta", 3.14159}}}}})}}),
                  1);
  for (int i = 0; i < 3; ++i) session.tick();
  const LaserReading& scan = session.robot_runtime(session.agent_id("hsr"))->lasers.front().reading;
  ASSERT_EQ(scan.ranges.size(), 1081u) << "the UST-20LX class default";
  // 40 Hz on 60 Hz steps: scans after steps 1, 2, 3 (at 0, 0.025 and 0.05 s, each read on the first
  // tick at or after its time), then 5, 6, …
  EXPECT_EQ(scan.tick, 3);
  EXPECT_NEAR(scan.height, 0.1844, 1e-3);
  std::vector<int> runs;
  bool on_leg = false;
  for (int beam = 540 - 120; beam <= 540 + 120; ++beam) {  // ±30° ahead
    const bool leg = scan.ranges[beam] < 2.0;
    if (leg && !on_leg) runs.push_back(0);
    if (leg) ++runs.back();
    on_leg = leg;
  }
  ASSERT_EQ(runs.size(), 2u) << "two legs, the wall showing between them";
  // At 0.18 m the laser cuts an adult's shins: capsules of 0.11 × 0.45 m shoulder width = 0.0495 m
  // radius, 0.09 m either side of her centre. At 1.53 m each spans 2 × asin(0.0495 / 1.53) ≈ 3.7° ≈
  // 15 beams of 0.25°.
  for (const int run : runs) EXPECT_NEAR(run, 15, 2);
}

TEST(RobotSession, TouchingAPersonStartsAndEndsAContact) {
  // Ana stands against the robot's front (she would step aside from an approaching robot).
  Session session(with_hsr({{"controller", {{"type", "teleop"}}}},
                           {{"humans", json::array({{{"id", "ana"}, {"start", {{"x", 2.25}, {"y", 2}, {"theta", 3.14159}}}}})}}),
                  1);
  const AgentId hsr = session.agent_id("hsr");
  session.tick();
  // Her skeleton's capsules — shins, feet, thighs — overlap the HSR's 0.215 m base; each part is its
  // own contact, named by its body part.
  const auto started = events_of<sim::events::ContactStart>(session);
  ASSERT_GE(started.size(), 2u);
  std::set<std::string> parts;
  for (const Event* event : started) {
    EXPECT_EQ(event->subject, "hsr");
    EXPECT_EQ(event->as<events::ContactStart>()->with, "ana");
    parts.insert(event->as<events::ContactStart>()->part);
  }
  EXPECT_TRUE(parts.contains("l_shin") || parts.contains("r_shin"));
  EXPECT_TRUE(std::all_of(parts.begin(), parts.end(), [](const std::string& part) {
    for (int p = 0; p < humans::kBodyPartCount; ++p) {
      if (part == humans::body_part_name(static_cast<humans::BodyPart>(p))) return true;
    }
    return false;
  }));
  session.command_robot_twist(hsr, {-0.2, 0.0});
  for (int i = 0; i < 200; ++i) session.tick();
  // Every contact that started has ended (she may brush the robot again as she steps about).
  const std::size_t touches = events_of<sim::events::ContactStart>(session).size();
  EXPECT_EQ(events_of<sim::events::ContactEnd>(session).size(), touches);
  EXPECT_TRUE(session.robot_runtime(hsr)->contacts.empty());
  // A robot taken out of the session stops sensing and touching; the others go on.
  const RobotRuntime* runtime = session.robot_runtime(hsr);
  const std::int64_t last_scan = runtime->lasers.front().reading.tick;
  session.command_robot_twist(hsr, {0.2, 0.0});
  session.remove_agent(hsr);
  for (int i = 0; i < 200; ++i) session.tick();
  EXPECT_EQ(runtime->lasers.front().reading.tick, last_scan);
  EXPECT_EQ(events_of<sim::events::ContactStart>(session).size(), touches) << "no contacts of a removed robot";
  EXPECT_THROW(session.robot_runtime(hsr), core::Error) << "its id is stale";
}

TEST(RobotSession, PeopleDetectorSeesPeopleButNotThroughTheTable) {
  // The table spans x 4.4–5.6, y 4.6–5.4. Ben stands right behind it as seen from the robot.
  Session session(with_hsr({{"start", {{"x", 2}, {"y", 5}, {"theta", 0}}},
                            {"people_detector", {{"miss_probability", 0.0}, {"position_noise", 0.0}, {"velocity_noise", 0.0}}}},
                           {{"humans", json::array({{{"id", "ana"}, {"start", {{"x", 3}, {"y", 7}}}},
                                                    {{"id", "ben"}, {"start", {{"x", 7}, {"y", 5}}}}})}}),
                  1);
  session.tick();
  const PeopleReading& people = session.robot_runtime(session.agent_id("hsr"))->people;
  EXPECT_EQ(people.tick, 1);
  ASSERT_EQ(people.people.size(), 1u) << "ben is hidden: obstacles are full height";
  EXPECT_EQ(people.people[0].agent, session.index_of(session.agent_id("ana")));
}

TEST(RobotSession, SameSeedSameRunDifferentSeedDifferentNoise) {
  auto run = [](std::uint64_t seed) {
    Session session(with_hsr({{"controller", {{"type", "social"}, {"goal", {{"pose", {{"x", 8}, {"y", 8}}}}}}},
                              {"people_detector", json::object()}},
                             {{"humans", json::array({{{"id", "ana"}, {"start", {{"x", 6}, {"y", 6}}}}})}}),
                    seed);
    for (int i = 0; i < 600; ++i) session.tick();
    return session.state_hash();
  };
  EXPECT_EQ(run(4), run(4));
  EXPECT_NE(run(4), run(5));
}

TEST(RobotSession, RobotDefinitionsAreValidated) {
  auto errors = [](const json& robot) {
    json scenario = testing::room_scenario(json::object());
    scenario["robots"] = json::array({robot});
    std::vector<std::string> pointers;
    for (const auto& error : scenario::load_scenario(scenario, {}).errors) pointers.push_back(error.pointer + " " + error.message);
    return pointers;
  };
  const json start = {{"x", 2}, {"y", 2}};
  auto has = [](const std::vector<std::string>& found, const std::string& prefix) {
    return std::any_of(found.begin(), found.end(), [&](const std::string& e) { return e.rfind(prefix, 0) == 0; });
  };
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "r2d2"}, {"start", start}}), "/robots/0/model unknown robot model 'r2d2'"));
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "hsr"}, {"radius", 0.3}, {"start", start}}), "/robots/0/radius"));
  EXPECT_TRUE(has(errors({{"id", "r"}, {"start", start}, {"controller", {{"type", "idle"}}}}), "/robots/0/controller only a robot with a model"));
  // Without a goal a driving controller only drives the choreography's gotos; a goal must say where.
  EXPECT_TRUE(errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"controller", {{"type", "dwa"}}}}).empty());
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"controller", {{"type", "orca"}, {"goal", {{"radius", 1.0}}}}}}),
                  "/robots/0/controller/goal a goal is a location or a pose"));
  const auto unknown_location = errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"controller", {{"type", "goal"}, {"goal", {{"location", "nowhere"}}}}}});
  EXPECT_TRUE(has(unknown_location, "/robots/0/controller/goal/location"));
  EXPECT_EQ(unknown_location.size(), 1u) << "a goal that is wrong is not also missing";
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"controller", {{"type", "goal"}, {"goal", {{"pose", {{"x", 5}, {"y", 5}}}}}}}}),
                  "/robots/0/controller/goal/pose")) << "inside the table";
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "roman"}, {"start", start}, {"controller", {{"type", "teleop"}}}}), "/robots/0/controller/type"));
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"people_detector", {{"range", -1}}}}), "/robots/0/people_detector/range"));
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"controller", {{"type", "idle"}, {"goal", {{"pose", {{"x", 8}, {"y", 8}}}}}}}}),
                  "/robots/0/controller/goal the idle controller does not drive to a goal"));
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"joints", {{"arm_lift_joint", 2.0}}}}), "/robots/0/joints/arm_lift_joint outside"));
  EXPECT_TRUE(has(errors({{"id", "r"}, {"model", "hsr"}, {"start", start}, {"joints", {{"tail_joint", 0.0}}}}), "/robots/0/joints/tail_joint"));
  // ROMAN cannot be sent anywhere.
  json roman = testing::room_scenario(json::object());
  roman["robots"] = json::array({{{"id", "roman"}, {"model", "roman"}, {"start", start}}});
  roman["steps"] = json::array({{{"name", "go"}, {"actions", json::array({{{"agent", "roman"}, {"goto", {{"pose", {{"x", 8}, {"y", 8}}}}}}})}}});
  const auto roman_errors = scenario::load_scenario(roman, {}).errors;
  ASSERT_EQ(roman_errors.size(), 1u);
  EXPECT_EQ(roman_errors[0].pointer, "/steps/0/actions/0/agent");
}

}  // namespace
}  // namespace hrisim::sim

namespace hrisim::sim {
namespace {

// IMHuS's use case: the HSR rides up with three people and, on floor 2, asks for the button to be
// pressed to call the cabin back; it boards the cabin when it comes, asks to be sent down, and drives
// out on floor 1.
TEST(RobotSession, BundledElevatorRobotRidesUpAndBackDown) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/elevator.json");
  ASSERT_TRUE(loaded.model);
  Session session(loaded.model, 3);
  const AgentId robot = session.agent_id("robot");
  ASSERT_NE(session.robot_runtime(robot), nullptr);
  bool on_floor2 = false;
  while (!session.state().finished) {
    session.tick();
    // The cabin spans x from -1.2 to 1.3; floor 2 is the room at x < -1.2, floor 1 the one at x > 1.3.
    on_floor2 |= session.state().agents[session.index_of(robot)].position.x() < -1.5;
  }
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  EXPECT_TRUE(on_floor2);
  std::vector<std::string> story;
  for (const Event& event : session.state().events) {
    if (event.is<sim::events::RequestAccepted>()) story.push_back(event.as<events::RequestAccepted>()->routine);
    if (event.is<sim::events::ElevatorArrived>()) story.push_back("arrived at " + std::to_string(event.as<events::ElevatorArrived>()->floor + 1));
  }
  ASSERT_GE(story.size(), 4u);
  EXPECT_EQ(std::vector<std::string>(story.end() - 4, story.end()),
            (std::vector<std::string>{"call_elevator_floor2", "arrived at 2", "send_elevator_floor1", "arrived at 1"}));
  for (const Event* accepted : events_of<sim::events::RequestAccepted>(session)) EXPECT_EQ(accepted->as<events::RequestAccepted>()->robot, "robot");
  const Vec2 end = session.state().agents[session.index_of(robot)].position;
  EXPECT_GT(end.x(), 2.3) << "out of the cabin on floor 1: " << end.transpose();
  const RobotRuntime& runtime = *session.robot_runtime(robot);
  EXPECT_GT(runtime.lasers.front().reading.tick, 0);
  EXPECT_GE(runtime.people.tick, session.state().tick - 6) << "10 Hz";
}

}  // namespace
}  // namespace hrisim::sim

namespace hrisim::sim {
namespace {

/// The HSR's hand points forward over a side table with a cup of this mass standing between its
/// open fingers, its centre 1.75 cm short of the fingertips, or `farther` beyond that (m).
Session hand_around_a_cup(double mass, double farther) {
  json scenario = testing::room_scenario(json::parse(R"({
    "world": {"obstacles": [{"name": "table", "box": {"x": 5, "y": 5, "length": 1.2, "width": 0.8}},
                            {"name": "side_table", "box": {"x": 2.75, "y": 2.078, "length": 0.3, "width": 0.4}, "height": 0.556}]},
    "humans": [{"id": "ana", "start": {"x": 8.5, "y": 8.5}}],
    "steps": [{"name": "wait", "actions": [{"agent": "ana", "wait": {"duration": 55}}]}]})"));
  scenario["objects"] = json::array({{{"name", "cup"}, {"shape", {{"kind", "cylinder"}, {"radius", 0.03}, {"length", 0.1}}}, {"mass", mass},
                                      {"pose", {{"x", 2.685 + farther}, {"y", 2.078}, {"z", 0.606}}}}});
  // arm_lift 0.3 m, arm horizontal, wrist straight: the hand points along +x at 0.606 m, its fingers
  // open either side of y = 2.078.
  scenario["robots"] = json::array({{{"id", "hsr"}, {"model", "hsr"}, {"start", {{"x", 2}, {"y", 2}}},
                                     {"joints", {{"arm_lift_joint", 0.3}, {"arm_flex_joint", -1.5708}, {"hand_motor_joint", 1.2}}}}});
  Session session(testing::load_valid(scenario), 1);
  for (int i = 0; i < 30; ++i) session.tick();
  EXPECT_NEAR(session.object_pose(0).translation().z(), 0.606, 0.005) << "resting on the side table";
  return session;
}

// Closing the gripper holds the cup (both fingers touch it within their friction cones), lifting the
// arm lifts it, and after putting it down, opening the gripper leaves it standing there.
TEST(RobotSession, GripperGraspsLiftsAndReleasesACup) {
  Session session = hand_around_a_cup(0.2, 0.0);
  const AgentId hsr = session.agent_id("hsr");
  session.command_robot_gripper(hsr, true);
  for (int i = 0; i < 8 && events_of<sim::events::Grasp>(session).empty(); ++i) session.tick();
  ASSERT_EQ(events_of<sim::events::Grasp>(session).size(), 1u) << "within the seed's 8-tick gripper step";
  EXPECT_EQ(events_of<sim::events::Grasp>(session)[0]->as<events::Grasp>()->object, "cup");
  const RobotRuntime& runtime = *session.robot_runtime(hsr);
  const robots::Robot& robot = runtime.robot;
  const int gripper = robot.joint_index("hand_motor_joint");
  for (int i = 0; i < 30; ++i) session.tick();
  EXPECT_DOUBLE_EQ(robot.joint_position(gripper), runtime.grip_position) << "the fingers rest on the cup";
  EXPECT_GT(robot.joint_position(gripper), robot.description().gripper->closed + 0.5);
  session.command_robot_joints(hsr, "arm", {0.5, -1.5708, 0.0, 0.0, 0.0, 0.0});
  for (int i = 0; i < 120; ++i) session.tick();
  EXPECT_GT(session.object_pose(0).translation().z(), 0.606 + 0.15) << "lifted with the arm";
  // Put it back down and let go: it stands on the table again, not kicked by the opening fingers.
  session.command_robot_joints(hsr, "arm", {0.3, -1.5708, 0.0, 0.0, 0.0, 0.0});
  for (int i = 0; i < 120; ++i) session.tick();
  EXPECT_TRUE(events_of<sim::events::Release>(session).empty()) << "held until the gripper opens";
  EXPECT_TRUE(events_of<sim::events::Slip>(session).empty());
  const Eigen::Vector3d put_down = session.object_pose(0).translation();
  session.command_robot_gripper(hsr, false);
  for (int i = 0; i < 120; ++i) session.tick();
  ASSERT_EQ(events_of<sim::events::Release>(session).size(), 1u);
  EXPECT_EQ(events_of<sim::events::Release>(session)[0]->as<events::Release>()->object, "cup");
  EXPECT_NEAR(session.object_pose(0).translation().z(), 0.606, 0.01) << "standing on the side table";
  EXPECT_LT((session.object_pose(0).translation() - put_down).head<2>().norm(), 0.01) << "where it was put down";
}

// The world with a movable object is built again from the state every kPhysicsRebuildInterval: a cup
// held up in the air stays in the hand through it, and a copy of the session taken then (the only
// ticks one can be) goes on bit for bit as the session does — the grasp made again from the state.
TEST(RobotSession, AHeldCupStaysHeldThroughTheWorldsRebuildAndACopyThenGoesOnBitForBit) {
  Session session = hand_around_a_cup(0.2, 0.0);
  const AgentId hsr = session.agent_id("hsr");
  session.command_robot_gripper(hsr, true);
  for (int i = 0; i < 30; ++i) session.tick();
  ASSERT_EQ(events_of<sim::events::Grasp>(session).size(), 1u);
  session.command_robot_joints(hsr, "arm", {0.5, -1.5708, 0.0, 0.0, 0.0, 0.0});
  const std::int64_t every = std::llround(kPhysicsRebuildInterval / session.model().dt);
  std::optional<Session::Copy> copy;
  while (!copy) {
    ASSERT_LE(session.state().tick, every) << "no copy by the first rebuild";
    session.tick();
    copy = session.copy();
  }
  EXPECT_EQ(session.state().tick, every) << "a world with an object is copied only when just built again";
  ASSERT_GE(session.robot_runtime(hsr)->held_object, 0);
  const Eigen::Vector3d lifted = session.object_pose(0).translation();
  EXPECT_GT(lifted.z(), 0.606 + 0.15) << "lifted with the arm";
  Session restored(session.shared_model(), std::move(*copy), session.state().events);
  EXPECT_EQ(restored.state_hash(), session.state_hash());
  // Down again, through the next rebuild: both the same at every tick, the cup held all along.
  session.command_robot_joints(hsr, "arm", {0.3, -1.5708, 0.0, 0.0, 0.0, 0.0});
  restored.command_robot_joints(restored.agent_id("hsr"), "arm", {0.3, -1.5708, 0.0, 0.0, 0.0, 0.0});
  for (std::int64_t t = 0; t < every + 10; ++t) {
    session.tick();
    restored.tick();
    ASSERT_EQ(restored.state_hash(), session.state_hash()) << "tick " << session.state().tick;
  }
  EXPECT_TRUE(events_of<sim::events::Slip>(session).empty());
  EXPECT_TRUE(events_of<sim::events::Release>(session).empty());
  EXPECT_NEAR(session.object_pose(0).translation().z(), 0.606, 0.01) << "put down on the side table, still in the hand";
}

// A cup heavier than the HSR's payload (1.3 kg) is gripped, but slips out once the arm lifts it.
TEST(RobotSession, ACupHeavierThanThePayloadSlipsOutOfTheGrip) {
  Session session = hand_around_a_cup(1.6, 0.0);
  const AgentId hsr = session.agent_id("hsr");
  session.command_robot_gripper(hsr, true);
  for (int i = 0; i < 30; ++i) session.tick();
  ASSERT_EQ(events_of<sim::events::Grasp>(session).size(), 1u);
  session.command_robot_joints(hsr, "arm", {0.5, -1.5708, 0.0, 0.0, 0.0, 0.0});
  for (int i = 0; i < 120; ++i) session.tick();
  ASSERT_EQ(events_of<sim::events::Slip>(session).size(), 1u);
  EXPECT_EQ(events_of<sim::events::Slip>(session)[0]->as<events::Slip>()->object, "cup");
  EXPECT_EQ(session.robot_runtime(hsr)->held_object, -1);
  EXPECT_EQ(events_of<sim::events::Grasp>(session).size(), 1u) << "no new grasp until the gripper opens";
  EXPECT_LT(session.object_pose(0).translation().z(), 0.606 + 0.02) << "it stayed on the table or fell";
}

// The wrist sensor weighs what the hand holds; the base IMU feels gravity at rest and the base's turn.
TEST(RobotSession, WristSensorWeighsTheHeldCup) {
  Session session = hand_around_a_cup(0.2, 0.0);
  const AgentId hsr = session.agent_id("hsr");
  const RobotRuntime& runtime = *session.robot_runtime(hsr);
  ASSERT_EQ(runtime.imus.size(), 1u);
  ASSERT_EQ(runtime.force_torque_sensors.size(), 1u);
  const ImuReading& imu = runtime.imus[0].reading;
  const ForceTorqueReading& wrist = runtime.force_torque_sensors[0].reading;
  EXPECT_EQ(imu.tick, session.state().tick);
  EXPECT_NEAR(imu.linear_acceleration.z(), 9.81, 0.1) << "gravity, felt as the floor pushing up";
  EXPECT_NEAR(imu.linear_acceleration.head<2>().norm(), 0.0, 0.1);
  EXPECT_NEAR(imu.angular_velocity.norm(), 0.0, 0.01);
  EXPECT_NEAR(wrist.force.norm(), 0.0, 0.2) << "an empty hand";
  session.command_robot_gripper(hsr, true);
  for (int i = 0; i < 20; ++i) session.tick();
  session.command_robot_joints(hsr, "arm", {0.4, -1.5708, 0.0, 0.0, 0.0, 0.0});
  for (int i = 0; i < 120; ++i) session.tick();
  ASSERT_EQ(runtime.held_object, 0);
  // In the map frame the hand bears the cup's weight, 0.2 kg × 9.81 m/s² down, 9.5 cm ahead of the
  // sensor (the arm's jitter and the sensor's noise averaged over 30 ticks).
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  for (int i = 0; i < 30; ++i) {
    session.tick();
    const Eigen::Matrix3d to_map = runtime.robot.sensor_pose(*runtime.force_torque_sensors[0].mount).rotation();
    force += to_map * wrist.force / 30.0;
    torque += to_map * wrist.torque / 30.0;
  }
  EXPECT_NEAR(force.z(), -0.2 * 9.81, 0.1);
  EXPECT_NEAR(force.head<2>().norm(), 0.0, 0.1);
  EXPECT_NEAR(torque.norm(), 0.2 * 9.81 * 0.095, 0.03) << "the weight's moment about the wrist";
  session.command_robot_twist(hsr, {0.0, 0.5});
  for (int i = 0; i < 60; ++i) session.tick();
  EXPECT_NEAR(imu.angular_velocity.z(), 0.5, 0.05) << "turning at 0.5 rad/s";
}

// Grasped at the fingertips, the fingers meet the cup (radius 3 cm) where the line between them leaves
// the friction cones (μ 0.5: 26.6° from the surface normal): with its centre 2.25 cm beyond the tips
// the fingers' corners touch it 49° off, and it is squeezed out; 0.25 cm beyond, 5° off, it is held.
TEST(RobotSession, FingersHoldACupOnlyWithinTheirFrictionCones) {
  for (const auto& [farther, held] : {std::pair{0.04, false}, std::pair{0.02, true}}) {
    Session session = hand_around_a_cup(0.2, farther);
    const AgentId hsr = session.agent_id("hsr");
    session.command_robot_gripper(hsr, true);
    for (int i = 0; i < 60; ++i) session.tick();
    EXPECT_EQ(events_of<sim::events::Grasp>(session).size(), held ? 1u : 0u) << farther;
    session.command_robot_joints(hsr, "arm", {0.5, -1.5708, 0.0, 0.0, 0.0, 0.0});
    for (int i = 0; i < 120; ++i) session.tick();
    EXPECT_EQ(session.object_pose(0).translation().z() > 0.606 + 0.15, held) << "lifted with the arm: " << farther;
  }
}

}  // namespace
}  // namespace hrisim::sim

namespace hrisim::sim {
namespace {

/// Closest the robot's centre comes to ana's while driving from (2, 2) to (8, 2) with `controller`,
/// ana standing her ground at (5, 2.6), just clear of its straight way (the blind follower passes her
/// 0.6 m from her centre).
double closest_approach(const std::string& controller) {
  Session session(with_hsr({{"controller", {{"type", controller}, {"goal", {{"pose", {{"x", 8}, {"y", 2}}}}}}}},
                           {{"humans", json::array({{{"id", "ana"}, {"start", {{"x", 5}, {"y", 2.6}, {"theta", 3.14159}}}}})}}),
                  1);
  const AgentId hsr = session.agent_id("hsr"), ana = session.agent_id("ana");
  // The distance is the controller's doing: she would keep her limbs' clearance from the robot even
  // without a personal space.
  session.set_rooted(ana, true);
  double closest = 1e9;
  for (int i = 0; i < 60 * 40 && events_of<sim::events::RobotGoalReached>(session).empty(); ++i) {
    session.tick();
    closest = std::min(closest, (session.state().agents[session.index_of(hsr)].position -
                                 session.state().agents[session.index_of(ana)].position).norm());
  }
  EXPECT_EQ(events_of<sim::events::RobotGoalReached>(session).size(), 1u) << controller;
  return closest;
}

TEST(RobotSession, SocialControllerKeepsMoreDistanceThanThePathFollower) {
  const double social = closest_approach("social"), plain = closest_approach("goal");
  EXPECT_GT(social, plain + 0.1) << "the social robot yields";
  EXPECT_GT(social, 0.215 + robots::kSocialStopDistance - 0.1);
}

}  // namespace
}  // namespace hrisim::sim

namespace hrisim::sim {
namespace {

TEST(RobotSession, LaserSeesMovableObjectsAndRobotsTouchDiscRobots) {
  json extra = json::parse(R"({
    "objects": [{"name": "crate", "shape": {"kind": "box", "size": [0.4, 0.4, 0.4]}, "mass": 3, "pose": {"x": 3.5, "y": 2, "z": 0.2}}]})");
  json scenario = testing::room_scenario(extra);
  scenario["humans"] = json::array({{{"id", "ana"}, {"start", {{"x", 8.5}, {"y", 8.5}}}}});
  scenario["steps"] = json::array({{{"name", "wait"}, {"actions", json::array({{{"agent", "ana"}, {"wait", {{"duration", 5}}}}})}}});
  scenario["robots"] = json::array({{{"id", "hsr"}, {"model", "hsr"}, {"start", {{"x", 2}, {"y", 2}}}},
                                    {{"id", "cart"}, {"start", {{"x", 2}, {"y", 2.4}}}, {"radius", 0.2}}});
  Session session(testing::load_valid(scenario), 1);
  session.tick();
  const LaserReading& scan = session.robot_runtime(session.agent_id("hsr"))->lasers.front().reading;
  // The crate's near face is at x = 3.3; the laser sits 0.1675 m ahead of the robot's centre.
  EXPECT_NEAR(scan.ranges[540], 3.3 - 2.1675, 0.05);
  const auto started = events_of<sim::events::ContactStart>(session);
  ASSERT_EQ(started.size(), 1u) << "the cart (a robot without a model) is a 0.2 m cylinder in the physics world";
  EXPECT_EQ(started[0]->as<events::ContactStart>()->with, "cart");
  EXPECT_EQ(started[0]->as<events::ContactStart>()->part, "body");
}

}  // namespace
}  // namespace hrisim::sim
