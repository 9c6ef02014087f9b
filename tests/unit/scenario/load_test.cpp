#include "scenario/load.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "support/scenarios.hpp"
#include "support/temp_dir.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::json;
using testing::room_scenario;

/// Errors of a document, as "pointer: message" lines.
std::vector<std::string> errors_of(const json& document) {
  const LoadResult result = load_scenario(document, {});
  EXPECT_EQ(result.model == nullptr, !result.errors.empty());
  std::vector<std::string> lines;
  for (const auto& e : result.errors) lines.push_back(e.pointer + ": " + e.message);
  return lines;
}

::testing::AssertionResult has_error(const std::vector<std::string>& errors, const std::string& pointer,
                                     const std::string& fragment) {
  for (const std::string& line : errors) {
    if (line.starts_with(pointer + ": ") && line.find(fragment) != std::string::npos) return ::testing::AssertionSuccess();
  }
  std::string all;
  for (const std::string& line : errors) all += "\n  " + line;
  return ::testing::AssertionFailure() << "no error at " << pointer << " mentioning '" << fragment << "' in:" << all;
}

const json kPeople = json::parse(R"({
  "locations": {"door": {"x": 1, "y": 1, "theta": 1.57}},
  "social_spaces": {"sofa": {"x": 8, "y": 8, "slots": [{"x": 0, "y": 0}, {"x": 0.7, "y": 0}]}},
  "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}, {"id": "ben", "start": {"x": 3, "y": 2}}],
  "robots": [{"id": "robot", "start": {"x": 2, "y": 8}}],
  "routines": {"fetch": [{"goto": {"location": "door"}}, {"wait": {"duration": 1}}]},
  "steps": [{"name": "go", "actions": [{"agent": "ana", "routine": "fetch"}, {"agent": "ben", "goto": {"social_space": "sofa"}}]}],
  "async": [{"routine": "fetch"}],
  "requests": [{"time": 3, "routine": "fetch"}]
})");

TEST(LoadScenario, CompilesTheModel) {
  const auto model = testing::load_valid(room_scenario(kPeople));
  ASSERT_TRUE(model);
  EXPECT_EQ(model->name, "room");
  EXPECT_DOUBLE_EQ(model->dt, kDefaultDt);
  EXPECT_DOUBLE_EQ(model->time_limit, 60.0);
  ASSERT_EQ(model->agents.size(), 3u);
  EXPECT_EQ(model->agents[2].kind, AgentKind::robot);
  EXPECT_DOUBLE_EQ(model->agents[0].radius, kDefaultAgentRadius);
  EXPECT_FALSE(model->agents[0].preferred_speed) << "drawn per session";
  EXPECT_DOUBLE_EQ(model->locations[0].radius, kDefaultGoalRadius);
  EXPECT_TRUE(model->social_spaces[0].slots[1].position().isApprox(Vec2(8.7, 8.0)));
  ASSERT_EQ(model->steps.size(), 1u);
  EXPECT_EQ(model->steps[0].actions[0].kind, Action::Kind::run_routine);
  EXPECT_EQ(model->steps[0].actions[0].agent, 0);
  EXPECT_EQ(model->routines[0].actions[0].kind, Action::Kind::go_to_location);
  EXPECT_EQ(model->requests[0].robot, 2);
  EXPECT_TRUE(model->grid.blocked(Vec2(5.0, 5.0))) << "the table is in the grid";
  EXPECT_TRUE(model->grid.blocked(Vec2(0.0, 5.0))) << "so are the walls";
}

TEST(LoadScenario, DefaultsFollowThePapers) {
  const auto model = testing::load_valid(room_scenario(kPeople));
  EXPECT_DOUBLE_EQ(model->orca.neighbour_distance, 2.0);
  EXPECT_EQ(model->orca.max_neighbours, 5);
  EXPECT_DOUBLE_EQ(model->orca.time_horizon, 2.0);
  EXPECT_DOUBLE_EQ(model->orca.obstacle_horizon, 1.0);
  EXPECT_DOUBLE_EQ(model->social_force.desired_factor, 1.0);
  EXPECT_DOUBLE_EQ(model->social_force.social_factor, 2.1);
  EXPECT_DOUBLE_EQ(model->social_force.obstacle_factor, 10.0);
  EXPECT_DOUBLE_EQ(model->social_force.obstacle_sigma, 0.8);
  EXPECT_DOUBLE_EQ(model->social_force.relaxation_time, 0.5);
  EXPECT_DOUBLE_EQ(model->social_force.lambda, 2.0);
  EXPECT_DOUBLE_EQ(model->social_force.gamma, 0.35);
  EXPECT_DOUBLE_EQ(model->social_force.n, 2.0);
  EXPECT_DOUBLE_EQ(model->social_force.n_prime, 3.0);
  EXPECT_DOUBLE_EQ(model->social_force.neighbour_distance, 4.0);
  EXPECT_DOUBLE_EQ(model->replan_distance, kDefaultReplanDistance);
  EXPECT_EQ(model->agents[0].avoidance, humans::LocalAvoidance::orca);
}

TEST(LoadScenario, LocomotionParametersAreRead) {
  json document = room_scenario(kPeople);
  document["locomotion"] = json::parse(R"({"avoidance": "social_force", "replan_distance": 2,
    "orca": {"neighbour_distance": 3, "max_neighbours": 7, "time_horizon": 1.5, "obstacle_horizon": 0.5},
    "social_force": {"obstacle_sigma": 0.2, "neighbour_distance": 2}})");
  const auto model = testing::load_valid(document);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->agents[0].avoidance, humans::LocalAvoidance::social_force);
  EXPECT_DOUBLE_EQ(model->replan_distance, 2.0);
  EXPECT_DOUBLE_EQ(model->orca.neighbour_distance, 3.0);
  EXPECT_EQ(model->orca.max_neighbours, 7);
  EXPECT_DOUBLE_EQ(model->orca.time_horizon, 1.5);
  EXPECT_DOUBLE_EQ(model->orca.obstacle_horizon, 0.5);
  EXPECT_DOUBLE_EQ(model->social_force.obstacle_sigma, 0.2);
  EXPECT_DOUBLE_EQ(model->social_force.neighbour_distance, 2.0);
  EXPECT_DOUBLE_EQ(model->social_force.social_factor, 2.1) << "unset parameters keep their defaults";
}

TEST(LoadScenario, ACrowdPresetSetsItsParametersAndTheSectionsKeysOverrideIt) {
  json document = room_scenario(kPeople);
  document["locomotion"] = json::parse(R"({"preset": "calibrated", "headway": {"horizon": 3}})");
  const auto calibrated = testing::load_valid(document);
  ASSERT_TRUE(calibrated);
  EXPECT_DOUBLE_EQ(calibrated->headway.time_gap, humans::kCalibratedTimeGap);
  EXPECT_DOUBLE_EQ(calibrated->headway.horizon, 3.0) << "the section's own key wins";
  EXPECT_DOUBLE_EQ(calibrated->personal_space.from_people, 0.0);
  EXPECT_DOUBLE_EQ(calibrated->social_force.obstacle_sigma, humans::kCalibratedObstacleSigma);
  document["locomotion"] = json::parse(R"({"preset": "crowdnav", "orca": {"time_horizon": 4}})");
  const auto crowdnav = testing::load_valid(document);
  ASSERT_TRUE(crowdnav);
  EXPECT_DOUBLE_EQ(crowdnav->orca.neighbour_distance, 10.0);
  EXPECT_DOUBLE_EQ(crowdnav->orca.time_horizon, 4.0);
  EXPECT_DOUBLE_EQ(crowdnav->personal_space.from_robots, 0.0);
  EXPECT_DOUBLE_EQ(crowdnav->headway.time_gap, 0.0);
  document["locomotion"] = json::parse(R"({"preset": "weidmann", "headway": {"time_gap": -1}})");
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/locomotion/preset", "")) << "an unknown preset is named at its pointer";
  EXPECT_TRUE(has_error(errors, "/locomotion/headway/time_gap", ""));
}

TEST(LoadScenario, InvalidJsonNamesLineAndColumn) {
  const LoadResult result = load_scenario_text("{\n  \"name\": \"x\",\n  \"world\": {,\n}", {});
  ASSERT_EQ(result.errors.size(), 1u);
  EXPECT_NE(result.errors[0].message.find("line 3, column 13"), std::string::npos) << result.errors[0].message;
}

TEST(LoadScenario, StructuralErrorsAllAtOnce) {
  json document = room_scenario(kPeople);
  document["colour"] = "blue";
  document["dt"] = -1;
  document["humans"][1]["start"]["x"] = "left";
  document["steps"][0]["actions"][1]["goto"] = {{"social_space", "sofa"}, {"speed", 2}};
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/colour", "unknown key 'colour'"));
  EXPECT_TRUE(has_error(errors, "/dt", "must be greater than 0"));
  EXPECT_TRUE(has_error(errors, "/humans/1/start/x", "expected number, got string"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/1/goto/speed", "unknown key 'speed'"));
  EXPECT_EQ(errors.size(), 4u);
}

TEST(LoadScenario, UnknownReferencesAreNamed) {
  json document = room_scenario(kPeople);
  document["steps"][0]["actions"] = json::parse(R"([
    {"agent": "zoe", "wait": {"duration": 1}},
    {"agent": "ana", "goto": {"location": "kitchen"}},
    {"agent": "ana", "goto": {"social_space": "bench"}},
    {"agent": "ana", "routine": "dance"},
    {"agent": "ana", "look_at": {"agent": "nobody"}}
  ])");
  document["async"] = json::parse(R"([{"routine": "sing"}])");
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/0/agent", "unknown agent 'zoe' (known: ana, ben, robot)"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/1/goto/location", "unknown location 'kitchen' (known: door)"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/2/goto/social_space", "unknown social space 'bench'"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/3/routine", "unknown routine 'dance'"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/4/look_at/agent", "unknown agent 'nobody'"));
  EXPECT_TRUE(has_error(errors, "/async/0/routine", "unknown routine 'sing'"));
  EXPECT_TRUE(has_error(errors, "/requests/0/routine", "no entry of 'async' answers routine 'fetch'"));
}

TEST(LoadScenario, PlacesInsideObstaclesOrOutsideTheMap) {
  json document = room_scenario(kPeople);
  document["world"]["obstacles"].push_back(json::parse(R"({"name": "block", "box": {"x": 2.5, "y": 2.5, "length": 3, "width": 3}})"));
  document["humans"][0]["start"] = {{"x", 2.5}, {"y", 2.5}};
  document["robots"][0]["start"] = {{"x", 20}, {"y", 2}};
  document["locations"]["door"] = {{"x", 0.0}, {"y", 3.0}};
  document["social_spaces"]["sofa"]["slots"][1] = {{"x", -3.0}, {"y", -3.0}};
  document["steps"][0]["actions"][1] = json::parse(R"({"agent": "ben", "goto": {"pose": {"x": 4.9, "y": 4.9}}})");
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/humans/0/start", "human 'ana' at (2.5, 2.5) is inside obstacle \"block\""))
      << "1.5 m inside: farther than a start is moved";
  EXPECT_TRUE(has_error(errors, "/robots/0/start", "outside the map"));
  EXPECT_TRUE(has_error(errors, "/locations/door", "inside obstacle \"wall 3\""));
  EXPECT_TRUE(has_error(errors, "/social_spaces/sofa/slots/1", "slot 1 of social space 'sofa'"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/1/goto/pose", "inside obstacle \"table\""));
}

TEST(LoadScenario, DuplicateIdsAndNames) {
  json document = room_scenario(kPeople);
  document["robots"][0]["id"] = "ana";
  document["world"]["obstacles"].push_back(json::parse(R"({"name": "table", "box": {"x": 2, "y": 5, "length": 1, "width": 1}})"));
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/robots/0/id", "agent id 'ana' is used twice"));
  EXPECT_TRUE(has_error(errors, "/world/obstacles/1/name", "obstacle name 'table' is used twice"));
}

TEST(LoadScenario, AgentsInStepsButNotInRoutines) {
  json document = room_scenario(kPeople);
  document["routines"]["fetch"][0]["agent"] = "ana";
  document["steps"][0]["actions"][1].erase("agent");
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/routines/fetch/0/agent", "do not name an agent"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/1", "missing required key 'agent'"));
}

TEST(LoadScenario, RoutinesMayNotCallThemselves) {
  json document = room_scenario(kPeople);
  document["routines"]["a"] = json::parse(R"([{"routine": "b"}])");
  document["routines"]["b"] = json::parse(R"([{"wait": {"duration": 1}}, {"routine": "a"}])");
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/routines/b/1/routine", "calls itself")) ;
}

TEST(LoadScenario, RequestsNeedARobot) {
  json document = room_scenario(kPeople);
  document["requests"][0]["robot"] = "ana";
  EXPECT_TRUE(has_error(errors_of(document), "/requests/0/robot", "'ana' is not a robot"));
  document["requests"][0].erase("robot");
  document.erase("robots");
  EXPECT_TRUE(has_error(errors_of(document), "/requests/0", "the scenario has none"));
}

TEST(LoadScenario, WorldNeedsAMapOrBounds) {
  json document = room_scenario(kPeople);
  document["world"].erase("bounds");
  EXPECT_TRUE(has_error(errors_of(document), "/world", "needs either 'map'"));
  document = room_scenario(kPeople);
  document["world"]["bounds"]["max"] = {-2, 3};
  EXPECT_TRUE(has_error(errors_of(document), "/world/bounds", "max must be greater than min"));
  document = room_scenario(kPeople);
  document["world"]["map"] = "nowhere.yaml";
  EXPECT_TRUE(has_error(errors_of(document), "/world/map", "map 'nowhere.yaml' not found"));
}

TEST(LoadScenario, MapRelativeToTheScenarioFile) {
  testing::TempDir dir;
  std::ofstream(dir / "m.pgm", std::ios::binary) << "P5\n40 40\n255\n" << std::string(40 * 40, '\xfe');
  std::ofstream(dir / "m.yaml") << "image: m.pgm\nresolution: 0.25\norigin: [0, 0, 0]\n";
  json document = room_scenario(kPeople);
  document["world"] = {{"map", "m.yaml"}};
  std::ofstream(dir / "s.json") << document.dump();
  const LoadResult result = load_scenario_file(dir / "s.json");
  for (const auto& e : result.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  ASSERT_TRUE(result.model);
  EXPECT_EQ(result.model->grid.width(), 40);
  EXPECT_DOUBLE_EQ(result.model->grid.resolution(), 0.25);
}

// hrisim's own SLAM-style map (tests/fixtures/maps/lobby.yaml: two rooms, a doorway, a table, an unscanned
// border) as a scenario's world.map by absolute path: places on its free cells load, places on a wall,
// the table or the border are refused.
TEST(LoadScenario, MapFixtureChecksPlacesAgainstItsCells) {
  json document = json::parse(R"({"name": "lobby map", "world": {}, "steps": [],
    "locations": {"desk_left": {"x": -1.55, "y": 0.45}, "desk_right": {"x": 1.55, "y": -0.95},
                  "doorway": {"x": 0.05, "y": 0.05}},
    "social_spaces": {"chat": {"x": -1.55, "y": -0.45, "slots": [{"x": 0.4, "y": 0}, {"x": -0.4, "y": 0}]}}})");
  document["world"]["map"] = (std::filesystem::path(HRISIM_SOURCE_DIR) / "tests/fixtures/maps/lobby.yaml").string();
  const auto model = testing::load_valid(document);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->grid.width(), 60);
  EXPECT_EQ(model->grid.height(), 40);
  EXPECT_DOUBLE_EQ(model->grid.resolution(), 0.1);
  EXPECT_TRUE(model->map_from_image);

  document["locations"]["on_table"] = {{"x", 1.65}, {"y", 1.05}};
  document["locations"]["unscanned"] = {{"x", -2.95}, {"y", 0.05}};
  document["locations"]["in_the_wall"] = {{"x", 0.05}, {"y", 1.05}};
  LoadOptions options;
  options.limits.confine_files = false;
  const LoadResult refused = load_scenario(document, options);
  EXPECT_FALSE(refused.model);
  std::vector<std::string> errors;
  for (const auto& e : refused.errors) errors.push_back(e.pointer + ": " + e.message);
  EXPECT_TRUE(has_error(errors, "/locations/on_table", "on an occupied or unknown cell of the map"));
  EXPECT_TRUE(has_error(errors, "/locations/unscanned", "on an occupied or unknown cell of the map"));
  EXPECT_TRUE(has_error(errors, "/locations/in_the_wall", "on an occupied or unknown cell of the map"));
  EXPECT_EQ(errors.size(), 3u);
}

// IMHuS's own elevator map loads through a scenario, and its published poses are in free space.
TEST(LoadScenario, ImhusElevatorMapWithItsPoses) {
  const std::filesystem::path map = std::filesystem::path(HRISIM_SHARED_DIR) / "external/imhus/elevator_map/elevator.yaml";
  if (!std::filesystem::exists(map)) {
    GTEST_SKIP() << "no ../shared/external/imhus/elevator_map beside the project: the project's own fixture "
                    "tests/fixtures/maps/lobby.yaml covers this path (LoadScenario.MapFixtureChecksPlacesAgainstItsCells)";
  }
  json document = json::parse(R"({"name": "elevator map", "world": {}, "steps": [],
    "locations": {"initial_pose1": {"x": 5, "y": -2}, "elevator_door1_button": {"x": 2, "y": 1},
                  "center_floor2": {"x": -5, "y": 0}, "printer_floor2": {"x": -7.5, "y": 0}},
    "social_spaces": {"elevator": {"x": 0, "y": 0, "slots": [{"x": 0.5, "y": 0.5}, {"x": 0.5, "y": -0.5},
                      {"x": -0.5, "y": -0.5}, {"x": -0.5, "y": 0.5}, {"x": 0, "y": 0}]}}})");
  document["world"]["map"] = map.string();
  const auto model = testing::load_valid(document);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->grid.width(), 325);
}

TEST(LoadScenario, BundledScenariosAreValid) {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(HRISIM_SOURCE_DIR) + "/scenarios")) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    const LoadResult result = load_scenario_file(entry.path());
    for (const auto& e : result.errors) ADD_FAILURE() << entry.path() << " " << e.pointer << ": " << e.message;
  }
  EXPECT_GE(count, 4);
}


TEST(LoadScenario, GroupsAndAttitudesAreChecked) {
  json document = room_scenario(kPeople);
  document["groups"] = json::parse(R"({"duo": {"members": ["ana", "zoe"]}})");
  document["steps"][0]["actions"] = json::parse(R"([
    {"group": "duo", "publish": {"topic": "/t", "message": "m"}},
    {"group": "trio", "goto": {"location": "door"}},
    {"agent": "ana", "group": "duo", "goto": {"location": "door"}},
    {"agent": "ana", "harass": {"robot": "ben", "duration": 5}},
    {"agent": "ana", "stop_and_look": {"robot": "nobody", "duration": 5}},
    {"agent": "ben", "form_group": {"group": "new", "members": ["ana", "ana"]}}
  ])");
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/groups/duo/members/1", "unknown agent 'zoe'"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/0/group", "a group can be given goto, routine, wait, look_at, turn, motion or say"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/1/group", "unknown group 'trio' (known: duo, new)"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/2", "an agent or a group, not both"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/3/harass/robot", "'ben' is not a robot"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/4/stop_and_look/robot", "unknown agent 'nobody'"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/5/form_group/members/1", "'ana' is listed twice"));
}

TEST(LoadScenario, AttitudeDefaults) {
  json document = room_scenario(kPeople);
  document["steps"][0]["actions"] = json::parse(R"([
    {"agent": "ana", "harass": {"robot": "robot", "duration": 5}},
    {"agent": "ben", "stop_and_look": {"robot": "robot", "duration": 5}}])");
  const auto model = testing::load_valid(document);
  ASSERT_TRUE(model);
  EXPECT_DOUBLE_EQ(model->steps[0].actions[0].radius, kHarassDistance);
  EXPECT_DOUBLE_EQ(model->steps[0].actions[1].radius, kStopAndLookDistance);
}


TEST(LoadScenario, OnlyRobotsMakeRequests) {
  json document = room_scenario(kPeople);
  document["steps"][0]["actions"] = json::parse(R"([{"agent": "ana", "request": {"routine": "fetch"}},
                                                     {"agent": "robot", "request": {"routine": "nothing"}}])");
  const auto errors = errors_of(document);
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/0/agent", "only a robot makes requests"));
  EXPECT_TRUE(has_error(errors, "/steps/0/actions/1/request/routine", "unknown routine 'nothing'"));
}


// 0.3 + 0.8 · ln(10 / (1.34 / 0.5)) = 1.354 m with pedsim's parameters and hrisim's human radius.
TEST(LoadScenario, StandoffOfSocialForceHumans) {
  EXPECT_NEAR(social_force_standoff(humans::SocialForceParams{}, 0.3, 1.34), 1.354, 1e-3);
  EXPECT_DOUBLE_EQ(social_force_standoff(humans::SocialForceParams{.obstacle_factor = 1.0}, 0.3, 1.34), 0.3)
      << "a drive stronger than the wall force gets all the way";
}

// An agent placed on a wall or an obstacle, as files made for simulators that push it out have them,
// starts at the nearest spot within 1 m where its body fits, and the loader says so.
TEST(LoadScenario, MovesAStartOnAnObstacleToTheNearestSpotWhereTheBodyFitsAndWarns) {
  json document = room_scenario(json::parse(R"({"humans": [{"id": "ana", "start": {"x": 5.1, "y": 5.3}}]})"));
  const LoadResult result = load_scenario(document, {});
  ASSERT_TRUE(result.model) << (result.errors.empty() ? "" : result.errors[0].message);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_EQ(result.warnings[0].pointer, "/humans/0/start");
  EXPECT_NE(result.warnings[0].message.find("human 'ana' at (5.1, 5.3) is on a wall or an obstacle: moved to ("), std::string::npos)
      << result.warnings[0].message;
  const Vec2 start = result.model->agents[0].start.position();
  EXPECT_GT(start.y(), 5.4 + 0.3 - 1e-9) << "north of the table (4.4..5.6 × 4.6..5.4), the nearest side, clear by the radius";
  EXPECT_LT((start - Vec2(5.1, 5.3)).norm(), 0.5);
  EXPECT_TRUE(result.model->planner.traversable(result.model->grid.index(result.model->grid.cell_of(start)), result.model->agents[0].radius));
}

TEST(LoadScenario, WarnsAboutGoalsSocialForceHumansCannotReach) {
  json document = room_scenario(json::parse(R"({
    "locations": {"by_the_wall": {"x": 0.9, "y": 5}, "open": {"x": 3, "y": 2}},
    "humans": [{"id": "sf", "start": {"x": 2, "y": 2}, "avoidance": "social_force"}, {"id": "orca", "start": {"x": 2, "y": 8}}],
    "steps": [{"name": "go", "actions": [{"agent": "sf", "goto": {"location": "open"}},
                                         {"agent": "orca", "goto": {"location": "by_the_wall"}}]},
              {"name": "wall", "actions": [{"agent": "sf", "goto": {"pose": {"x": 9.1, "y": 5}}}]}]})"));
  const LoadResult result = load_scenario(document, {});
  ASSERT_TRUE(result.model) << "warnings do not make a scenario invalid";
  ASSERT_EQ(result.warnings.size(), 1u) << "only goals of social-force humans, and only the one too near a wall";
  EXPECT_EQ(result.warnings[0].pointer, "/steps/1/actions/0/goto/pose");
  EXPECT_NE(result.warnings[0].message.find("may stop about 1.35 m away"), std::string::npos) << result.warnings[0].message;
}

// A wait for a message that no publish action and no elevator door sends would hold its step until
// the time limit, silently: it is said at load.
TEST(LoadScenario, WarnsAboutWaitsForMessagesNothingSends) {
  json document = room_scenario(json::parse(R"({
    "humans": [{"id": "ana", "start": {"x": 2, "y": 2}}, {"id": "ben", "start": {"x": 2, "y": 8}}],
    "routines": {"signal": [{"publish": {"topic": "bell", "message": "ring"}}]},
    "steps": [{"name": "wait", "actions": [{"agent": "ana", "wait": {"topic": "bell", "message": "ring"}},
                                           {"agent": "ben", "routine": "signal"},
                                           {"agent": "ben", "wait": {"topic": "bell", "message": "toll"}},
                                           {"agent": "ana", "wait": {"topic": "/elevator/lift_door_state", "message": "open"}}]}]})"));
  const LoadResult result = load_scenario(document, {});
  ASSERT_TRUE(result.model) << "warnings do not make a scenario invalid";
  ASSERT_EQ(result.warnings.size(), 2u) << "the bell rings: waiting for it is fine";
  EXPECT_EQ(result.warnings[0].pointer, "/steps/0/actions/2/wait");
  EXPECT_NE(result.warnings[0].message.find("waits for 'toll' on topic 'bell', which is published there but never with that message"), std::string::npos)
      << result.warnings[0].message;
  EXPECT_EQ(result.warnings[1].pointer, "/steps/0/actions/3/wait");
  EXPECT_NE(result.warnings[1].message.find("nothing in the scenario publishes (no publish action, no elevator door)"), std::string::npos)
      << result.warnings[1].message;
}

}  // namespace
}  // namespace hrisim::scenario
