#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>

#include "support/hunav_yaml.hpp"
#include "episode/episode.hpp"
#include "scenario/import.hpp"
#include "sim/session.hpp"
#include "support/imports.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::json;
using testing::has_message;
using testing::kFixtures;
using testing::kShared;
using testing::load_imported;
using testing::no_reference_file;
using testing::read;

const std::filesystem::path kLobbyAgents = kFixtures / "hunav/lobby_agents.yaml";
const std::filesystem::path kLobbyMap = kFixtures / "maps/lobby.yaml";
const std::filesystem::path kCafeAgents = kShared / "external/hunav/agents.yaml";
const std::filesystem::path kCafeMap = kShared / "external/hunav/maps/map_cafe2.yaml";

/// Maps anywhere, as the command line reads a user's files.
LoadOptions unconfined() {
  LoadOptions options;
  options.limits.confine_files = false;
  return options;
}

ImportOptions with_map(const std::filesystem::path& map) {
  ImportOptions options;
  options.map = map;
  options.source_name = "agents.yaml";
  return options;
}

/// Metres each agent walks in each `window` seconds of a run to the time limit of `seconds`.
std::vector<std::vector<double>> distance_per_window(const std::shared_ptr<const Model>& model, double seconds, double window) {
  episode::Episode run(model, 1);
  sim::Session& session = run.session();
  session.set_time_limit(seconds);
  std::vector<std::vector<double>> walked(model->agents.size(), std::vector<double>(static_cast<std::size_t>(seconds / window + 0.5), 0.0));
  std::vector<Vec2> last;
  for (const auto& agent : session.state().agents) last.push_back(agent.position);
  while (!run.over()) {
    run.tick();
    const auto slot = std::min(static_cast<std::size_t>((session.state().tick - 1) * model->dt / window), walked[0].size() - 1);
    for (std::size_t a = 0; a < model->agents.size(); ++a) {
      walked[a][slot] += (session.state().agents[a].position - last[a]).norm();
      last[a] = session.state().agents[a].position;
    }
  }
  EXPECT_EQ(session.state().termination, sim::Termination::timeout) << "cyclic goals run to the time limit";
  return walked;
}

// hrisim's own agents file (tests/fixtures/hunav/lobby_agents.yaml) takes every path of HuNavSim's
// published one and more: behaviours by id and by block (default, custom, random), flow and block
// style, goals walked over and over or once, a group, max_vel and radius.
TEST(ImportHunav, LobbyFixtureBecomesPeopleWithTheirBehavioursGoalsAndGroup) {
  const ImportResult imported = import_hunav(read(kLobbyAgents), with_map(kLobbyMap));
  EXPECT_TRUE(has_message(imported.warnings, 49, "goal_force_factor is not read"));
  EXPECT_TRUE(has_message(imported.warnings, 88, "configuration random normal drawn once at import (seed 1)"));
  EXPECT_EQ(imported.warnings.size(), 2u);
  const json scenario = json::parse(imported.scenario.dump());
  EXPECT_EQ(scenario["world"]["map"], std::filesystem::absolute(kLobbyMap).string());
  EXPECT_EQ(scenario["locomotion"]["social_force"],
            json({{"desired_factor", 2.0}, {"obstacle_factor", 10.0}, {"social_factor", 5.0}, {"obstacle_sigma", 0.2}}));
  const json& humans = scenario["humans"];
  ASSERT_EQ(humans.size(), 5u);
  EXPECT_EQ(humans[0], json::parse(R"({"id": "alice", "start": {"x": -2.0, "y": -1.0, "theta": 0.0}, "radius": 0.3,
                                       "preferred_speed": 1.2, "behaviour": "regular"})"));
  EXPECT_EQ(humans[1]["behaviour"], json::parse(R"({"type": "scared", "duration": 20.0, "detection_distance": 2.5, "speed": 0.8,
                                                    "force_factor": 15.0, "once": false})"))
      << "custom: dist is how far a scared person sees the robot, other_force_factor the push away from it";
  EXPECT_EQ(humans[2]["behaviour"], "impassive");
  EXPECT_EQ(humans[3]["behaviour"], "surprised");
  EXPECT_EQ(humans[4]["radius"], 0.35) << "hunav_loader's default radius";
  const json& erin = humans[4]["behaviour"];
  EXPECT_EQ(erin["type"], "curious");
  EXPECT_GE(erin["speed"].get<double>(), 0.4) << "hunav_loader's least random curious speed";
  EXPECT_GT(erin["distance"].get<double>(), 0.0);
  EXPECT_EQ(import_hunav(read(kLobbyAgents), with_map(kLobbyMap)).scenario, imported.scenario) << "random draws are the same every import";
  EXPECT_EQ(scenario["groups"], json::parse(R"({"group_1": {"members": ["carol", "dave"]}})"));
  EXPECT_EQ(scenario["routines"]["alice_goals"][0]["goto"], json::parse(R"({"pose": {"x": 2.2, "y": -1.0}, "radius": 0.3})"));
  EXPECT_EQ(scenario["steps"][0]["actions"], json::parse(R"([{"agent": "alice", "routine": "alice_goals", "repeat": true},
                                                              {"agent": "bob", "routine": "bob_goals", "repeat": true},
                                                              {"group": "group_1", "routine": "carol_goals"}])"))
      << "erin has no goals; the group walks its first member's once";
  ASSERT_TRUE(load_imported(imported, unconfined()));
}

TEST(ImportHunav, LobbyFixtureRunsToTheTimeLimitWithTheCyclicWalkersMoving) {
  const auto model = load_imported(import_hunav(read(kLobbyAgents), with_map(kLobbyMap)), unconfined());
  ASSERT_TRUE(model);
  const auto walked = distance_per_window(model, 90.0, 30.0);
  for (const int cyclic : {0, 1}) {
    for (std::size_t window = 0; window < walked[cyclic].size(); ++window) {
      EXPECT_GT(walked[cyclic][window], 10.0) << model->agents[cyclic].id << " walks on through window " << window;
    }
  }
}

// HuNavSim's published cafe agents and map (reference data, read in place from ../shared/external).
TEST(ImportHunav, RealCafeFileRunsToTheTimeLimitWithEveryPersonMoving) {
  if (!std::filesystem::exists(kCafeAgents)) {
    GTEST_SKIP() << no_reference_file("hunav/agents.yaml", "tests/fixtures/hunav/lobby_agents.yaml (ImportHunav.LobbyFixture*)");
  }
  const ImportResult imported = import_hunav(read(kCafeAgents), with_map(kCafeMap));
  EXPECT_TRUE(imported.warnings.empty());
  const auto model = load_imported(imported, unconfined());
  ASSERT_TRUE(model);
  ASSERT_EQ(model->agents.size(), 5u);
  const auto walked = distance_per_window(model, 300.0, 30.0);
  for (std::size_t a = 0; a < walked.size(); ++a) {
    for (std::size_t window = 0; window < walked[a].size(); ++window) {
      EXPECT_GT(walked[a][window], 20.0) << model->agents[a].id << " in window " << window;
    }
  }
}

TEST(ImportHunav, TheWorldIsFoundByItsNameOrIsOpenGround) {
  ImportOptions by_name;
  by_name.map_search_path = {kFixtures};  // the file's `map: lobby` is kFixtures/maps/lobby.yaml
  const ImportResult found = import_hunav(read(kLobbyAgents), by_name);
  EXPECT_EQ(found.scenario["world"]["map"], "maps/lobby.yaml") << "as the loader looks it up in the same folders";
  LoadOptions load;
  load.map_search_path = {kFixtures};
  EXPECT_TRUE(load_imported(found, load));
  const ImportResult open = import_hunav(read(kLobbyAgents), {});
  EXPECT_TRUE(has_message(open.warnings, 0, "no map for world 'lobby': the people walk on open ground"));
  const auto& bounds = open.scenario["world"]["bounds"];  // 2 m round every start and goal
  EXPECT_NEAR(bounds["min"][0].get<double>(), -4.2, 1e-9);
  EXPECT_NEAR(bounds["min"][1].get<double>(), -3.4, 1e-9);
  EXPECT_NEAR(bounds["max"][0].get<double>(), 4.4, 1e-9);
  EXPECT_NEAR(bounds["max"][1].get<double>(), 3.4, 1e-9);
  EXPECT_TRUE(load_imported(open));
}

/// The errors of importing `yaml`.
std::vector<ImportMessage> errors_of(const std::string& yaml, const ImportOptions& options = {}) { return import_hunav(yaml, options).errors; }

const char* const kHeader = "hunav_loader:\n  ros__parameters:\n";

TEST(ImportHunav, FaultsAreSaidAtTheirLines) {
  const std::string agent = "    agents: [a]\n    a:\n      init_pose: {x: 1, y: 1}\n";
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    agents: [a]\n    a:\n      init_pose: {x: 1, y: two}\n"), 5,
                          "a.init_pose: y must be a number, got 'two'"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + agent + "      behavior: 9\n"), 6, "behavior must be 1 (regular) … 6 (threatening)"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + agent + "      behavior: {type: 3, configuration: 7}\n"), 6,
                          "configuration must be 0 (default), 1 (custom), 2 (random normal) or 3 (random uniform)"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + agent + "      goals: [g0]\n"), 6, "goal 'g0' has no block"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + agent + "      cyclic_goals: maybe\n"), 6, "cyclic_goals must be true or false"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + agent + "      radius: 3\n"), 6, "radius must be more than 0 and at most 1 m"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + agent + "      group_id: 1.5\n"), 6, "group_id must be a group's number"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    agents: [a]\n    a:\n      goals: []\n"), 5, "a: 'init_pose' must be a block with x and y"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    agents: [a, a]\n    a:\n      init_pose: {x: 1, y: 1}\n"), 3, "agent 'a' is listed twice"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    agents:\n      - b\n"), 4, "agent 'b' has no block of its parameters"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    map: cafe\n"), 3, "'agents' must list the agents' names"));
  EXPECT_TRUE(has_message(errors_of("hunav_loader:\n  ros__parameters:\n    agents: [a\n    b: 1\n"), 4, "malformed YAML at line 4"));
  EXPECT_TRUE(has_message(errors_of("image: map.pgm\nresolution: 0.05\n"), 1, "this is a ROS map YAML: give it with --map"));
  EXPECT_TRUE(has_message(errors_of("people:\n  - a\n"), 1, "not a HuNavSim agents file"));
  EXPECT_TRUE(has_message(errors_of("- 1\n- 2\n"), 1, "a HuNavSim agents file is a YAML mapping"));
  EXPECT_TRUE(has_message(errors_of("agents: [a]\na: {init_pose: {x: 1, y: \xff}}\n"), 2, "the document is not UTF-8 (byte"));
  EXPECT_TRUE(has_message(errors_of(std::string(100000, '[')), 0, "nests more than 64 levels deep"));
  EXPECT_TRUE(has_message(errors_of([] {
    std::string dashes;
    for (int i = 0; i < 20000; ++i) dashes += "- ";
    return dashes + "x\n";
  }()), 0, "nests more than 64 levels deep"));
  ImportOptions few;
  few.limits.max_people = 1;
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    agents: [a, b]\n", few), 3, "more than the 1 people a scenario may hold"));
  ImportOptions missing_map;
  missing_map.map = "/nonexistent/map.yaml";
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + agent, missing_map), 0, "map /nonexistent/map.yaml does not exist"));
}

TEST(ImportHunav, YamlAliasesThatMultiplyWorkAreRefusedAtTheirLine) {
  const std::string bomb = testing::aliased_goals(100, 10000);
  EXPECT_LT(bomb.size(), 64u * 1024u);
  const auto started = std::chrono::steady_clock::now();
  const ImportResult refused = import_hunav(bomb, {});
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(5)) << "56 s before the expansion was bounded";
  ASSERT_EQ(refused.errors.size(), 1u);
  const ImportMessage& error = refused.errors[0];
  EXPECT_NE(error.message.find("the YAML expands to more than 200000 nodes by line " + std::to_string(error.line)), std::string::npos) << error.message;
  EXPECT_NE(error.message.find("an alias counts each time it is used"), std::string::npos) << error.message;
  EXPECT_GE(error.line, 8) << "at an alias that takes the file past the limit, not at the anchor";
  EXPECT_LE(error.line, 106);
  EXPECT_TRUE(refused.scenario.is_null()) << "nothing imported";
  // Aliases as such are fine: the same file of fewer people and goals imports, every goal walked.
  const ImportResult small = import_hunav(testing::aliased_goals(10, 100), {});
  ASSERT_TRUE(small.errors.empty()) << small.errors[0].message;
  EXPECT_EQ(small.scenario["humans"].size(), 10u);
  EXPECT_EQ(small.scenario["routines"]["a9_goals"].size(), 100u);
  // A document whose aliases refer to themselves is bounded too.
  const ImportResult cycle = import_hunav(std::string(kHeader) + "    agents: [a]\n    a: &a {init_pose: {x: 1, y: 1}, more: [*a]}\n", {});
  ASSERT_FALSE(cycle.errors.empty());
}

TEST(ImportHunav, FlowNestingOnOneLineIsCountedBeforeParsing) {
  // `[[[…]]]` closed on its own line was not counted: only the brackets still open at a line's end were.
  const auto nested = [](int levels) { return std::string(static_cast<std::size_t>(levels), '[') + std::string(static_cast<std::size_t>(levels), ']') + "\n"; };
  EXPECT_TRUE(has_message(errors_of(nested(65)), 0, "nests more than 64 levels deep"));
  EXPECT_TRUE(has_message(errors_of(nested(100000)), 0, "nests more than 64 levels deep"));
  EXPECT_TRUE(has_message(errors_of("agents: {a: {b: {c: " + nested(62) + "}}}\n"), 0, "nests more than 64 levels deep"));
  EXPECT_FALSE(has_message(errors_of(nested(20)), 0, "nests more than")) << "20 levels are read";
}

TEST(ImportHunav, ACustomWatcherWithoutDistNeverSeesTheRobotAndIsWarnedAbout) {
  const ImportResult imported = import_hunav(std::string(kHeader) +
                                                 "    agents: [a]\n"
                                                 "    a:\n"
                                                 "      init_pose: {x: 0, y: 0}\n"
                                                 "      behavior: {type: 3, configuration: 1, duration: 10}\n",
                                             {});
  EXPECT_TRUE(has_message(imported.warnings, 6, "a.behavior: dist is not given (0): a surprised person with a custom configuration then never sees the robot"));
  EXPECT_EQ(imported.scenario["humans"][0]["behaviour"]["detection_distance"], 0.0);
}

TEST(ImportHunav, UnknownKeysAndGroupsWithOtherGoalsAreWarnedAbout) {
  const ImportResult imported = import_hunav(std::string(kHeader) +
                                                 "    agents: [a, b]\n"
                                                 "    a: {group_id: 2, init_pose: {x: 0, y: 0}, goals: [g0], g0: {x: 3, y: 0}, colour: red}\n"
                                                 "    b: {group_id: 2, init_pose: {x: 0, y: 1}, goals: [g0], g0: {x: 3, y: 2}}\n",
                                             {});
  EXPECT_TRUE(imported.errors.empty());
  EXPECT_TRUE(has_message(imported.warnings, 4, "a: unknown key 'colour' ignored"));
  EXPECT_TRUE(has_message(imported.warnings, 5, "b: walks with group 2, whose goals are a's (its first member's); its own are not walked"));
}

// What validation finds in an imported file is said at the line the part at fault came from.
TEST(ImportHunav, AStartOnAWallOfTheMapIsMovedAndSaidAtItsAgentsLine) {
  const ImportResult imported = import_hunav(std::string(kHeader) +
                                                 "    agents: [a, b]\n"
                                                 "    a: {init_pose: {x: -2, y: 0}}\n"
                                                 "    b: {init_pose: {x: 0.0, y: 1.5}}\n",
                                             with_map(kLobbyMap));
  ASSERT_TRUE(imported.errors.empty());
  // Moved to the nearest spot where the body fits (as HuNavSim's Gazebo would push it out), and said
  // at the agent's line.
  const LoadResult loaded = load_scenario(json::parse(imported.scenario.dump()), unconfined());
  ASSERT_TRUE(loaded.errors.empty()) << loaded.errors[0].pointer << ": " << loaded.errors[0].message;
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_EQ(loaded.warnings[0].pointer, "/humans/1/start") << loaded.warnings[0].message;
  EXPECT_NE(loaded.warnings[0].message.find("moved to"), std::string::npos) << loaded.warnings[0].message;
  EXPECT_EQ(origin_line(imported, loaded.warnings[0].pointer), 5);
}

// HuNavSim 2 names goals once, in global_goals, and behaviours by name.
TEST(ImportHunav, HunavSim2GlobalGoalsAndNamedBehavioursAreRead) {
  const ImportResult imported = import_hunav(std::string(kHeader) +
                                             "    global_goals:\n"
                                             "      1: {x: 2, y: 1}\n"
                                             "      2: {x: 2, y: 3}\n"
                                             "    agents: [a, b]\n"
                                             "    a: {init_pose: {x: 0, y: 0}, behavior: {type: Scared, configuration: 0}, goals: [1, 2]}\n"
                                             "    b: {init_pose: {x: 0, y: 2}, behavior: {type: 1}, goals: [2, 3], 3: {x: 4, y: 4}}\n",
                                             ImportOptions{});
  ASSERT_TRUE(imported.errors.empty()) << imported.errors[0].line << ": " << imported.errors[0].message;
  const auto model = load_imported(imported, unconfined());
  ASSERT_TRUE(model);
  EXPECT_EQ(model->agents[0].behaviour.type, humans::BehaviourType::scared);
  EXPECT_EQ(model->agents[1].behaviour.type, humans::BehaviourType::regular);
  const json scenario = json::parse(imported.scenario.dump());
  EXPECT_NE(scenario.dump().find("\"x\":2.0,\"y\":1.0"), std::string::npos) << "a's first goal, from global_goals: " << scenario.dump();
  EXPECT_NE(scenario.dump().find("\"x\":4.0,\"y\":4.0"), std::string::npos) << "b's own goal block still reads";
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    global_goals: {1: {x: 1, y: 1}}\n    agents: [a]\n    a: {init_pose: {x: 0, y: 0}, goals: [7]}\n"),
                          5, "goal '7' has no block (7: {x: …, y: …}) here or in global_goals"));
  EXPECT_TRUE(has_message(errors_of(std::string(kHeader) + "    agents: [a]\n    a: {init_pose: {x: 0, y: 0}, behavior: {type: Grumpy}}\n"), 4,
                          "or its name (Regular … Threatening)"));
}

TEST(ImportHunav, RealHunavSim2OfficeFileRunsWithItsPeopleWalking) {
  const std::filesystem::path agents = kShared / "external/hunav2/office_agents.yaml", map = kShared / "external/hunav2/office.yaml";
  if (!std::filesystem::exists(agents)) {
    GTEST_SKIP() << no_reference_file("hunav2/office_agents.yaml", "ImportHunav.HunavSim2GlobalGoalsAndNamedBehavioursAreRead");
  }
  const ImportResult imported = import_hunav(read(agents), with_map(map));
  ASSERT_TRUE(imported.errors.empty()) << imported.errors[0].line << ": " << imported.errors[0].message;
  const auto model = load_imported(imported, unconfined());
  ASSERT_TRUE(model);
  ASSERT_EQ(model->agents.size(), 8u);
  const auto walked = distance_per_window(model, 120.0, 30.0);
  int walking = 0;
  for (const auto& windows : walked) walking += std::all_of(windows.begin(), windows.end(), [](double metres) { return metres > 10.0; });
  EXPECT_GE(walking, 8 * 9 / 10) << "at least 90 % walk their routes all along";
}

}  // namespace
}  // namespace hrisim::scenario
