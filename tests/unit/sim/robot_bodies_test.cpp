// Robots have bodies: walls, furniture and people stop them. Each robot with a drive is driven at its
// top speed into every face of every wall and obstacle of each bundled scenario's map; its base never
// sinks deeper than 1 cm, it ends against the face (it was not stopped early) and the contact is an event.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <set>

#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// Deepest a robot's base may sink into anything solid, m (the bound).
constexpr double kAllowedPenetration = 0.01;
/// The robot starts this far from the face it drives into, m.
constexpr double kStartDistance = 1.0;

/// Signed distance from a point to a polygon's boundary: negative inside.
double signed_distance(const Vec2& p, const std::vector<Vec2>& polygon) {
  double nearest = 1e9;
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vec2 &a = polygon[j], &b = polygon[i];
    const double t = std::clamp((p - a).dot(b - a) / std::max((b - a).squaredNorm(), 1e-12), 0.0, 1.0);
    nearest = std::min(nearest, (p - (a + t * (b - a))).norm());
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x())) inside = !inside;
  }
  return inside ? -nearest : nearest;
}

json bundled(const std::string& name) {
  std::ifstream file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + name + ".json");
  return json::parse(file);
}

/// The map of a bundled scenario, with its places (elevators name their cabins' social spaces).
json map_of(const std::string& name) {
  const json bundled_document = bundled(name);
  json map = {{"world", bundled_document["world"]}};
  for (const char* key : {"locations", "social_spaces"}) {
    if (bundled_document.contains(key)) map[key] = bundled_document[key];
  }
  return map;
}

/// The map with one robot and nobody else; null when the start is not free.
std::shared_ptr<const scenario::Model> alone(const json& map, const std::string& model, const Pose2& start) {
  json document = {{"name", "alone"},
                         {"time_limit", 60},
                         {"robots", {{{"id", "robot"}, {"model", model}, {"start", {{"x", start.x}, {"y", start.y}, {"theta", start.theta}}},
                                      {"controller", {{"type", "teleop"}}}}}},
                         {"steps", {{{"name", "wait"}, {"actions", {{{"agent", "robot"}, {"wait", {{"duration", 50}}}}}}}}}};
  document.merge_patch(map);
  scenario::LoadOptions options;
  options.limits.confine_files = false;
  return scenario::load_scenario(document, options).model;
}

class WallsStopRobots : public ::testing::TestWithParam<std::string> {};

TEST_P(WallsStopRobots, AtTopSpeedIntoEveryFace) {
  const json map = map_of(GetParam());
  const auto empty = [&] {
    json document = {{"name", "map"}, {"steps", json::array()}};
    document.merge_patch(map);
    scenario::LoadOptions options;
    options.limits.confine_files = false;
    const scenario::LoadResult loaded = scenario::load_scenario(document, options);
    for (const auto& error : loaded.errors) ADD_FAILURE() << error.pointer << ": " << error.message;
    return loaded.model;
  }();
  ASSERT_TRUE(empty);
  for (const std::string model : {"hsr", "artos"}) {
    int faces = 0;
    for (const scenario::Obstacle& obstacle : empty->obstacles) {
      for (std::size_t i = 0; i < obstacle.polygon.size(); ++i) {
        const Vec2 a = obstacle.polygon[i], b = obstacle.polygon[(i + 1) % obstacle.polygon.size()];
        if ((b - a).norm() < 0.5) continue;  // a wall's end: no room to face it squarely
        const Vec2 middle = 0.5 * (a + b), normal = core::left_normal((b - a).normalized());
        for (const double side : {1.0, -1.0}) {
          const Vec2 start = middle + side * kStartDistance * normal;
          const auto model_here = alone(map, model, {start.x(), start.y(), core::direction_to(start, middle)});
          if (!model_here) continue;  // inside something, or outside the map
          Session session(model_here, 1);
          const AgentId robot = session.agent_id("robot");
          const RobotRuntime& runtime = *session.robot_runtime(robot);
          const double radius = model_here->agents[session.index_of(robot)].radius;
          double room = 1e9;
          for (const scenario::Obstacle& other : empty->obstacles) room = std::min(room, signed_distance(start, other.polygon) - radius);
          if (room < 0.05) continue;  // no room to start here
          const double top_speed = runtime.robot.description().drive->params.max_linear_speed;
          session.command_robot_twist(robot, {top_speed, 0.0});
          double deepest = 0.0;
          for (int tick = 0; tick < static_cast<int>(2.0 / top_speed / model_here->dt); ++tick) {
            session.tick();
            const Vec2 at = session.state().agents[session.index_of(robot)].position;
            for (const scenario::Obstacle& other : empty->obstacles) deepest = std::min(deepest, signed_distance(at, other.polygon) - radius);
          }
          const Vec2 at = session.state().agents[session.index_of(robot)].position;
          const std::string where = GetParam() + " " + model + " into " + obstacle.name + " face " + std::to_string(i) + " side " + std::to_string(side);
          EXPECT_GE(deepest, -kAllowedPenetration) << where << " start " << start.transpose() << " end " << at.transpose();
          // It drove all the way: only the face stopped it (or, where something else stands closer, that).
          double nearest = 1e9;
          for (const scenario::Obstacle& other : empty->obstacles) nearest = std::min(nearest, signed_distance(at, other.polygon) - radius);
          EXPECT_LE(nearest, 0.02) << where << ": stopped short";
          bool touched = false;
          for (const Event& event : session.state().events) if (const auto* contact = event.as<events::ContactStart>()) touched |= contact->with == "map";
          EXPECT_TRUE(touched) << where;
          ++faces;
        }
      }
    }
    EXPECT_GT(faces, 3) << GetParam() << " " << model;
  }
}

INSTANTIATE_TEST_SUITE_P(Maps, WallsStopRobots,
                         ::testing::Values("corridor_passing", "conversation_group", "queue", "elevator", "apartment", "pick_and_place", "family_day", "tea_break"));

TEST(DoorsStopRobots, AClosedElevatorDoorStopsTheHsrAtItsSlab) {
  // The elevator's floor-1 door spans x = 1.3, y −0.6…0.6, and stays shut while nobody calls the cabin.
  const auto model = alone(map_of("elevator"), "hsr", {2.4, 0.0, std::numbers::pi});
  ASSERT_TRUE(model);
  Session session(model, 1);
  const AgentId robot = session.agent_id("robot");
  session.command_robot_twist(robot, {1.0, 0.0});
  for (int tick = 0; tick < static_cast<int>(8.0 / model->dt); ++tick) session.tick();
  const double radius = model->agents[session.index_of(robot)].radius;
  const double slab = 1.3 + 0.5 * scenario::kDefaultWallThickness;
  const double x = session.state().agents[session.index_of(robot)].position.x();
  EXPECT_GE(x - radius, slab - kAllowedPenetration) << "not through the door";
  EXPECT_LE(x - radius, slab + 0.02) << "stopped by the door, not before";
  bool touched = false;
  for (const Event& event : session.state().events) if (const auto* contact = event.as<events::ContactStart>()) touched |= contact->part == "door1";
  EXPECT_TRUE(touched);
}

TEST(PeopleStopRobots, ARobotDrivingAtAStandingPersonStopsAgainstHer) {
  json document = testing::room_scenario({{"humans", {{{"id", "ana"}, {"start", {{"x", 5}, {"y", 2}}}}}},
                                          {"robots", {{{"id", "robot"}, {"model", "artos"}, {"start", {{"x", 2}, {"y", 2}, {"theta", 0}}},
                                                       {"controller", {{"type", "teleop"}}}}}}});
  document["steps"] = json::array({{{"name", "wait"}, {"actions", {{{"agent", "ana"}, {"wait", {{"duration", 50}}}}}}}});
  Session session(testing::load_valid(document), 1);
  const AgentId robot = session.agent_id("robot"), ana = session.agent_id("ana");
  session.set_rooted(ana, true);
  session.command_robot_twist(robot, {1.0, 0.0});
  const double radius = session.model().agents[session.index_of(robot)].radius;
  double closest = 1e9;
  for (int tick = 0; tick < 200; ++tick) {
    session.tick();
    closest = std::min(closest, (session.state().agents[session.index_of(robot)].position - session.state().agents[session.index_of(ana)].position).norm());
  }
  // Her torso is a capsule of about 0.15 m round her centre line: the base stops at it, not through her.
  EXPECT_GT(closest, radius + 0.1);
  EXPECT_LT(closest, radius + 0.35) << "stopped by her, not before";
  EXPECT_LT(session.state().agents[session.index_of(robot)].position.x(), 5.0);
  bool touched = false;
  for (const Event& event : session.state().events) if (const auto* contact = event.as<events::ContactStart>()) touched |= contact->with == "ana";
  EXPECT_TRUE(touched);
}

TEST(PeopleReactToTouch, ATouchedPersonStepsBackAndLooksAtTheRobot) {
  // The robot starts a hand's breadth behind her and drives on: people avoid robots, so only one this
  // close and this fast reaches her.
  json document = testing::room_scenario({{"humans", {{{"id", "ana"}, {"start", {{"x", 5}, {"y", 2}, {"theta", 0}}}}}},
                                          {"robots", {{{"id", "robot"}, {"model", "artos"}, {"start", {{"x", 4.3}, {"y", 2}, {"theta", 0}}},
                                                       {"controller", {{"type", "teleop"}}}}}}});
  document["steps"] = json::array({{{"name", "wait"}, {"actions", {{{"agent", "ana"}, {"wait", {{"duration", 50}}}}}}}});
  Session session(testing::load_valid(document), 1);
  const AgentId robot = session.agent_id("robot");
  const int ana = session.index_of(session.agent_id("ana")), artos = session.index_of(robot);
  session.command_robot_twist(robot, {1.0, 0.0});
  const auto startled = [&] { return std::count_if(session.state().events.begin(), session.state().events.end(), [](const Event& e) { return e.is<sim::events::Startled>(); }); };
  while (startled() == 0 && session.time() < 10.0) session.tick();
  ASSERT_EQ(startled(), 1) << "the robot reached her";
  session.command_robot_twist(robot, {0.0, 0.0});
  const auto gap = [&] { return (session.state().agents[ana].position - session.state().agents[artos].position).norm(); };
  const double touching = gap();
  for (int tick = 0; tick < static_cast<int>(3.0 / session.model().dt); ++tick) session.tick();
  EXPECT_GT(gap(), touching + 0.3) << "she stepped back";
  const AgentState& her = session.state().agents[ana];
  EXPECT_LT(std::abs(core::wrap_angle(core::direction_to(her.position, session.state().agents[artos].position) - her.heading)), 0.2) << "she looks at it";
  const auto event = std::find_if(session.state().events.begin(), session.state().events.end(), [](const Event& e) { return e.is<sim::events::Startled>(); });
  EXPECT_EQ(event->subject, "ana");
  EXPECT_EQ(event->as<events::Startled>()->robot, "robot");
  EXPECT_TRUE(event->as<events::Startled>()->stepped_back);
}

}  // namespace
}  // namespace hrisim::sim
