// Sitting on a chair's seat (an obstacle's anchor) and carrying a movable object in the hand: the
// person plans to the chair's front, steps back onto it and sits with the body on the seat, stands up
// and steps off before walking on, one person per seat; picks a cup off a table within reach, carries
// it in the right hand and puts it down where the scenario says. Bad references are refused at load,
// each at its pointer.
#include <gtest/gtest.h>

#include <algorithm>

#include "scenario/reaching.hpp"
#include "sim/carrying.hpp"
#include "sim/seats.hpp"
#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// The room with a chair facing +x (its seat at its centre), a low table with a cup on it, and the
/// people and steps given.
json furnished(const json& humans, const json& steps) {
  json document = testing::room_scenario({{"time_limit", 60}});
  document["world"]["obstacles"] = json::parse(R"([
    {"name": "chair", "mesh": "chair", "height": 0.9, "box": {"x": 2, "y": 5, "length": 0.5, "width": 0.5},
     "anchors": {"seat": {"x": 0, "y": 0, "theta": 0}}},
    {"name": "table", "height": 0.75, "box": {"x": 7, "y": 5, "length": 1.2, "width": 0.8}, "anchors": {"east_end": {"x": 0.4, "y": 0}}}
  ])");
  document["objects"] = json::parse(R"([{"name": "cup", "shape": {"kind": "cylinder", "radius": 0.035, "length": 0.1}, "mass": 0.2,
                                        "pose": {"x": 6.8, "y": 5.2, "z": 0.8}}])");
  document["humans"] = humans;
  document["steps"] = steps;
  return document;
}

json person(const char* id, double x, double y) { return {{"id", id}, {"start", {{"x", x}, {"y", y}}}, {"preferred_speed", 1.2}}; }

/// The time of the first event of kind `Kind` about `subject`, or -1.
template <class Kind>
double event_time(const Session& session, const std::string& subject) {
  for (const Event& event : session.state().events) {
    if (event.is<Kind>() && event.subject == subject) return event.time;
  }
  return -1.0;
}

void run_until(Session& session, double time) {
  while (session.time() < time - 1e-9 && !session.state().finished) session.tick();
}

const json kSitThenLeave = json::parse(R"([
  {"name": "sit", "actions": [{"agent": "p", "sit_on": {"obstacle": "chair"}}]},
  {"name": "rest", "actions": [{"agent": "p", "wait": {"duration": 3}}]},
  {"name": "leave", "actions": [{"agent": "p", "goto": {"pose": {"x": 8, "y": 8}}}]}
])");

TEST(Sitting, ThePersonReachesTheSeatAndSitsOnIt) {
  Session session(testing::load_valid(furnished(json::array({person("p", 8, 2)}), kSitThenLeave)), 1);
  const int p = session.index_of(session.agent_id("p"));
  const scenario::Seat& seat = session.model().seats[session.model().find_seat("chair", "")];
  while (event_time<events::SatDown>(session, "p") < 0 && session.time() < 30) session.tick();
  ASSERT_GE(event_time<events::SatDown>(session, "p"), 0.0) << "never sat down";
  const AgentState& self = session.state().agents[p];
  EXPECT_EQ(self.seating.phase, SeatPhase::seated);
  EXPECT_NEAR((self.position - scenario::seat_spot(seat)).norm(), 0.0, 1e-9);
  EXPECT_NEAR(core::wrap_angle(self.heading - seat.pose.theta), 0.0, 1e-6);
  // The body rests on the seat: the hips over its centre, at sitting height.
  const humans::BodyCapsules& body = HumanBodies(session.model()).of(session.model(), session.state(), p);
  const Eigen::Vector3d hips = body[static_cast<int>(humans::BodyPart::torso)].from;
  EXPECT_LT((hips.head<2>() - seat.pose.position()).norm(), 0.12) << hips.transpose();
  EXPECT_GT(hips.z(), 0.35);
  EXPECT_LT(hips.z(), 0.65);
  EXPECT_EQ(session.state().current_step, 1) << "the sit_on action is done once seated";
}

TEST(Sitting, ThePersonStandsUpAndStepsOffBeforeWalkingOn) {
  Session session(testing::load_valid(furnished(json::array({person("p", 8, 2)}), kSitThenLeave)), 1);
  const int p = session.index_of(session.agent_id("p"));
  run_until(session, 40);
  const double sat = event_time<events::SatDown>(session, "p"), stood = event_time<events::StoodUp>(session, "p");
  ASSERT_GE(sat, 0.0);
  ASSERT_GE(stood, 0.0) << "never stood up";
  EXPECT_GE(stood - sat, 3.0 + humans::builtin_motion("stand_up")->duration() - 1e-9) << "rests 3 s, then stands up";
  EXPECT_TRUE(session.state().finished) << "walked to (8, 8) after leaving the seat";
  EXPECT_LT((session.state().agents[p].position - Vec2(8, 8)).norm(), scenario::kDefaultGoalRadius + 0.05);
  EXPECT_EQ(session.state().agents[p].seating.seat, sim::SeatIndex());
}

TEST(Sitting, OnePersonPerSeat) {
  const json steps = json::parse(R"([{"name": "both", "actions": [
    {"agent": "p", "sit_on": {"obstacle": "chair"}},
    {"agent": "q", "routine": "sit_a_while"}]}])");
  json document = furnished(json::array({person("p", 4, 5), person("q", 8, 8)}), steps);
  document["routines"] = json::parse(R"({"sit_a_while": [{"wait": {"duration": 1}}, {"sit_on": {"obstacle": "chair"}}]})");
  document["steps"][0]["actions"][0] = json::parse(R"({"agent": "p", "routine": "sit_then_go"})");
  document["routines"]["sit_then_go"] = json::parse(R"([{"sit_on": {"obstacle": "chair"}}, {"wait": {"duration": 2}}, {"goto": {"pose": {"x": 2, "y": 8}}}])");
  Session session(testing::load_valid(document), 3);
  run_until(session, 50);
  const double q_sat = event_time<events::SatDown>(session, "q");
  ASSERT_GE(event_time<events::StoodUp>(session, "p"), 0.0);
  ASSERT_GE(q_sat, 0.0) << "q never got the seat";
  EXPECT_GT(q_sat, event_time<events::StoodUp>(session, "p")) << "q sits only once p has left the seat";
}

TEST(Sitting, StandUpMotionLeavesTheSeatAndIsNotPlayedTwice) {
  const json steps = json::parse(R"([
    {"name": "sit", "actions": [{"agent": "p", "sit_on": {"obstacle": "chair"}}]},
    {"name": "up", "actions": [{"agent": "p", "motion": {"name": "stand_up"}}]}])");
  Session session(testing::load_valid(furnished(json::array({person("p", 4, 5)}), steps)), 1);
  run_until(session, 30);
  const double stood = event_time<events::StoodUp>(session, "p");
  ASSERT_GE(stood, 0.0);
  EXPECT_TRUE(session.state().finished);
  const StepRecord& up = session.state().steps[1];
  EXPECT_NEAR(static_cast<double>(up.finished_tick) * session.model().dt, stood, 2 * session.model().dt) << "the motion ends with leaving the seat";
}

TEST(Sitting, ASeatedPersonDoesNotTurnOnTheSeat) {
  const json steps = json::parse(R"([
    {"name": "sit", "actions": [{"agent": "p", "sit_on": {"obstacle": "chair"}}]},
    {"name": "look", "actions": [{"agent": "p", "look_at": {"agent": "q"}}, {"agent": "p", "turn": {"by": 1.5}}]},
    {"name": "stay", "actions": [{"agent": "p", "wait": {"duration": 2}}]}])");
  Session session(testing::load_valid(furnished(json::array({person("p", 4, 5), person("q", 2, 8)}), steps)), 1);
  const int p = session.index_of(session.agent_id("p"));
  while (session.state().current_step < 2 && session.time() < 30) session.tick();
  ASSERT_EQ(session.state().current_step, 2) << "looking and turning are over at once";
  run_until(session, session.time() + 1);
  EXPECT_EQ(session.state().agents[p].seating.phase, SeatPhase::seated);
  EXPECT_NEAR(core::wrap_angle(session.state().agents[p].heading), 0.0, 1e-6) << "still facing the seat's way";
}

TEST(Sitting, SeatsAreCheckedAtLoad) {
  const json sit = json::parse(R"([{"name": "s", "actions": [{"agent": "p", "sit_on": {"obstacle": "sofa"}}]}])");
  const json humans = json::array({person("p", 8, 2)});
  EXPECT_EQ(testing::error_at(furnished(humans, sit), "/steps/0/actions/0/sit_on/obstacle"), "no obstacle named 'sofa'");
  json anchor = sit;
  anchor[0]["actions"][0]["sit_on"] = {{"obstacle", "chair"}, {"anchor", "left"}};
  EXPECT_EQ(testing::error_at(furnished(humans, anchor), "/steps/0/actions/0/sit_on/anchor"), "obstacle 'chair' has no anchor 'left' (it has: seat)");
  json no_seat = sit;
  no_seat[0]["actions"][0]["sit_on"] = {{"obstacle", "table"}};
  EXPECT_EQ(testing::error_at(furnished(humans, no_seat), "/steps/0/actions/0/sit_on/obstacle"), "obstacle 'table' has no anchor 'seat' (it has: east_end)");
  // A chair facing the wall it stands against.
  json blocked = furnished(humans, sit);
  blocked["world"]["obstacles"][0] = json::parse(R"({"name": "sofa", "box": {"x": 0.4, "y": 5, "length": 0.5, "width": 0.5}, "anchors": {"seat": {"x": 0, "y": 0, "theta": 3.14159}}})");
  EXPECT_NE(testing::error_at(blocked, "/steps/0/actions/0/sit_on").find("seat 'sofa' cannot be reached: its front"), std::string::npos);
  json robot = furnished(humans, sit);
  robot["robots"] = json::array({{{"id", "r"}, {"start", {{"x", 8}, {"y", 8}}}}});
  robot["steps"][0]["actions"][0] = json::parse(R"({"agent": "r", "sit_on": {"obstacle": "chair"}})");
  EXPECT_EQ(testing::error_at(robot, "/steps/0/actions/0/agent"), "only a human sits");
}

const json kFetchCup = json::parse(R"([
  {"name": "fetch", "actions": [{"agent": "p", "pick_up": {"object": "cup"}}]},
  {"name": "carry", "actions": [{"agent": "p", "goto": {"pose": {"x": 3, "y": 8}}}]},
  {"name": "leave", "actions": [{"agent": "p", "put_down": {"at": [2.5, 8.5]}}]}
])");

TEST(Carrying, ThePersonPicksTheCupUpCarriesItInTheHandAndPutsItDown) {
  Session session(testing::load_valid(furnished(json::array({person("p", 8, 2)}), kFetchCup)), 1);
  const int p = session.index_of(session.agent_id("p"));
  const Eigen::Vector3d on_table = session.state().objects[0].pose.translation();
  while (event_time<events::PickedUp>(session, "p") < 0 && session.time() < 30) session.tick();
  ASSERT_GE(event_time<events::PickedUp>(session, "p"), 0.0) << "never picked the cup up";
  HumanBodies bodies(session.model());
  const auto wrist = [&] { return bodies.of(session.model(), session.state(), p)[static_cast<int>(humans::BodyPart::r_forearm)].to; };
  const Eigen::Vector3d hand = carried_pose(session.model(), session.state(), bodies, p).translation();
  EXPECT_LT((hand - on_table).norm(), 0.1) << "the hand is at the cup when it takes it: " << hand.transpose() << " vs " << on_table.transpose();
  // Carried: it goes where the hand goes.
  for (int k = 0; k < 120; ++k) session.tick();
  EXPECT_EQ(session.state().agents[p].carrying.object.value, 0);
  EXPECT_LT((session.state().objects[0].pose.translation() - wrist()).norm(), kGripOffset + 1e-6);
  EXPECT_GT((session.state().objects[0].pose.translation() - on_table).norm(), 0.5) << "it left the table with the person";
  run_until(session, 40);
  ASSERT_GE(event_time<events::PutDown>(session, "p"), 0.0) << "never put the cup down";
  EXPECT_TRUE(session.state().finished);
  EXPECT_EQ(session.state().agents[p].carrying.object.value, -1);
  const Eigen::Vector3d rests = session.state().objects[0].pose.translation();
  EXPECT_NEAR(rests.x(), 2.5, 0.01);
  EXPECT_NEAR(rests.y(), 8.5, 0.01);
  EXPECT_NEAR(rests.z(), 0.05, 0.005) << "stands upright on the floor";
}

TEST(Carrying, ThePersonPutsTheCupOnATablesAnchor) {
  json steps = kFetchCup;
  steps[2]["actions"][0]["put_down"] = {{"on", "table"}, {"anchor", "east_end"}};
  Session session(testing::load_valid(furnished(json::array({person("p", 8, 2)}), steps)), 1);
  run_until(session, 40);
  ASSERT_TRUE(session.state().finished);
  const Eigen::Vector3d rests = session.state().objects[0].pose.translation();
  EXPECT_NEAR(rests.x(), 7.4, 0.01);
  EXPECT_NEAR(rests.y(), 5.0, 0.01);
  EXPECT_NEAR(rests.z(), 0.75 + 0.05, 0.005) << "on the table top";
}

TEST(Carrying, ImpossibleReachesAreSkippedWithTheReason) {
  const json steps = json::parse(R"([{"name": "s", "actions": [{"agent": "p", "put_down": {"at": [2, 2]}}]}])");
  Session session(testing::load_valid(furnished(json::array({person("p", 8, 2)}), steps)), 1);
  run_until(session, 5);
  EXPECT_TRUE(session.state().finished);
  const auto& events = session.state().events;
  const auto skipped = std::find_if(events.begin(), events.end(), [](const Event& e) { return e.is<sim::events::PutDownSkipped>(); });
  ASSERT_NE(skipped, events.end());
  EXPECT_EQ(skipped->as<events::PutDownSkipped>()->reason, "carrying nothing");
}

TEST(Carrying, ASecondPersonWaitsForTheCup) {
  const json steps = json::parse(R"([{"name": "both", "actions": [
    {"agent": "p", "routine": "take_and_leave"}, {"agent": "q", "routine": "take"}]}])");
  json document = furnished(json::array({person("p", 7, 3.5), person("q", 2, 2)}), steps);
  document["routines"] = json::parse(R"({"take_and_leave": [{"pick_up": {"object": "cup"}}, {"put_down": {"at": [8.5, 2]}}],
                                      "take": [{"wait": {"duration": 0.5}}, {"pick_up": {"object": "cup"}}]})");
  Session session(testing::load_valid(document), 2);
  run_until(session, 50);
  ASSERT_TRUE(session.state().finished);
  const double p_put = event_time<events::PutDown>(session, "p"), q_took = event_time<events::PickedUp>(session, "q");
  ASSERT_GE(p_put, 0.0);
  ASSERT_GE(q_took, 0.0);
  EXPECT_GT(q_took, p_put);
  EXPECT_EQ(session.state().agents[session.index_of(session.agent_id("q"))].carrying.object.value, 0);
}

TEST(Carrying, ObjectsAreCheckedAtLoad) {
  const json humans = json::array({person("p", 8, 2)});
  const json pick = json::parse(R"([{"name": "s", "actions": [{"agent": "p", "pick_up": {"object": "mug"}}]}])");
  EXPECT_EQ(testing::error_at(furnished(humans, pick), "/steps/0/actions/0/pick_up/object"), "no movable object named 'mug' (known: cup)");
  json put = json::parse(R"([{"name": "s", "actions": [{"agent": "p", "put_down": {"on": "desk"}}]}])");
  EXPECT_EQ(testing::error_at(furnished(humans, put), "/steps/0/actions/0/put_down/on"), "no obstacle named 'desk'");
  put[0]["actions"][0]["put_down"] = {{"at", {7, 5}}};
  EXPECT_EQ(testing::error_at(furnished(humans, put), "/steps/0/actions/0/put_down/at"), "put_down point at (7, 5) is inside obstacle \"table\"");
  put[0]["actions"][0]["put_down"] = {{"at", {2, 2}}, {"anchor", "east_end"}};
  EXPECT_EQ(testing::error_at(furnished(humans, put), "/steps/0/actions/0/put_down/anchor"), "an anchor belongs to an obstacle: give it with 'on'");
}

TEST(SittingAndCarrying, SameSeedSameLife) {
  json steps = kFetchCup;
  steps.push_back(kSitThenLeave[0]);
  const auto model = testing::load_valid(furnished(json::array({person("p", 8, 2)}), steps));
  Session a(model, 5), b(model, 5);
  for (int k = 0; k < 1800; ++k) {
    a.tick();
    b.tick();
  }
  EXPECT_EQ(state_hash(a.state()), state_hash(b.state()));
  EXPECT_GE(event_time<events::SatDown>(a, "p"), 0.0);
}

}  // namespace
}  // namespace hrisim::sim
