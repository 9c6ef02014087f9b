#include "scenario/import.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <limits>
#include <tuple>
#include <fstream>
#include <sstream>

#include "episode/episode.hpp"
#include "scenario/load.hpp"
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

// Files other projects published (../shared/external/SOURCES.md).
const std::filesystem::path kElevatorGoals = kShared / "external/imhus/elevator_goals.xml";
const std::filesystem::path kCorridor = kShared / "external/pedsim/corridor.xml";

ImportOptions bundled(std::string scenario = "") {
  return {std::move(scenario), std::nullopt, {std::filesystem::path(HRISIM_SOURCE_DIR) / "scenarios"}, "test.xml", {}, ""};
}

TEST(ImportImhus, OwnFixtureBecomesANativeScenario) {
  const ImportResult imported = import_imhus(read(kFixtures / "imhus/office.xml"), bundled());
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->name, "meeting");
  ASSERT_EQ(model->agents.size(), 4u);
  EXPECT_EQ(model->agents[0].id, "ann");
  EXPECT_TRUE(model->agents[0].start.position().isApprox(Vec2(4, -3))) << "agents start at their first goto";
  EXPECT_EQ(model->agents[3].kind, AgentKind::robot);
  EXPECT_TRUE(model->agents[3].start.position().isApprox(Vec2(6.5, 0))) << "the robot starts at initial_pose_robot";
  ASSERT_EQ(model->steps.size(), 3u);
  EXPECT_EQ(model->steps[1].name, "huddle_up");
  EXPECT_EQ(model->steps[1].actions[2].kind, Action::Kind::run_routine);
  ASSERT_EQ(model->async_routines.size(), 1u);
  EXPECT_EQ(model->routines[model->async_routines[0]].name, "fetch_coffee");
  EXPECT_DOUBLE_EQ(model->routines[model->find_routine("fetch_coffee")].actions[1].value, 2.0) << "'2.' is a number";
  // Slots p1, p2, p3 are taken in the order of their numbers, not of the file.
  const SocialSpace& huddle = model->social_spaces[0];
  EXPECT_TRUE(huddle.slots[0].position().isApprox(Vec2(6.8, -6)));
  EXPECT_TRUE(huddle.slots[2].position().isApprox(Vec2(6, -6.8)));
  // relativeX is along the map's x axis: board (5.5, -2) + 1 m = (6.5, -2) whatever the pose's heading.
  const Action& to_board = model->steps[2].actions[0];
  const Pose2 goal = core::compose(model->locations[to_board.target].pose, to_board.pose);
  EXPECT_NEAR(goal.x, 6.5, 1e-9);
  EXPECT_NEAR(goal.y, -2.0, 1e-9);
  EXPECT_FALSE(model->doors.empty()) << "map_name 'elevator' brings the bundled elevator world";
}

TEST(ImportImhus, ScenarioByName) {
  const ImportResult solo = import_imhus(read(kFixtures / "imhus/office.xml"), bundled("solo"));
  EXPECT_TRUE(has_message(solo.warnings, 0, "human 'ann' takes no part in scenario 'solo'"));
  const auto model = load_imported(solo);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->name, "solo");
  EXPECT_EQ(model->agents.size(), 2u) << "cy and the robot";
  EXPECT_EQ(model->steps[0].actions[0].kind, Action::Kind::go_to_pose);
  const ImportResult missing = import_imhus(read(kFixtures / "imhus/office.xml"), bundled("party"));
  EXPECT_TRUE(has_message(missing.errors, 27, "no scenario 'party' (the file has: meeting, solo)"));
}

TEST(ImportImhus, ErrorsNameTheLine) {
  std::string xml = read(kFixtures / "imhus/office.xml");
  auto replace = [&](const std::string& from, const std::string& to) { xml.replace(xml.find(from), from.size(), to); };
  replace(R"(poseID="window"/>)", R"(poseID="kitchen"/>)");
  replace(R"(<hi entityID="ann" taskID="greet"/>)", R"(<hi entityID="zed" taskID="dance"/>)");
  replace(R"(duration="1")", R"(duration="soon")");
  replace(R"(<publish_action topic="/office/greeting" msg="hello"/>)", R"(<publish_action topic="/office/greeting"/>)");
  replace(R"(socialSpaceID="huddle"/>
        <goto_action entityID="bo")", R"(socialSpaceID="circle"/>
        <goto_action entityID="bo")");
  const ImportResult result = import_imhus(xml, bundled());
  EXPECT_TRUE(has_message(result.errors, 34, "<goto_action>: unknown pose 'kitchen'"));
  EXPECT_TRUE(has_message(result.errors, 51, "unknown entity 'zed'"));
  EXPECT_TRUE(has_message(result.errors, 30, "attribute 'duration' must be a number, got 'soon'"));
  EXPECT_TRUE(has_message(result.errors, 31, "missing attribute 'msg'"));
  EXPECT_TRUE(has_message(result.errors, 49, "unknown social space 'circle'"));
}

// Every part of an imported scenario knows the XML line it came from, so that what validation finds
// in it can be said at that line.
TEST(ImportXml, PartsOfTheScenarioKnowTheirLines) {
  const ImportResult pedsim = import_pedsim(read(kFixtures / "pedsim/hall.xml"), bundled());
  EXPECT_EQ(origin_line(pedsim, "/world/walls/2/to"), 6);
  EXPECT_EQ(origin_line(pedsim, "/locations/left"), 8);
  EXPECT_EQ(origin_line(pedsim, "/humans/2/start"), 11) << "the cluster that made the agent";
  EXPECT_EQ(origin_line(pedsim, "/robots/0"), 16);
  EXPECT_EQ(origin_line(pedsim, "/routines/route_1/0/goto/pose"), 12) << "the addwaypoint";
  EXPECT_EQ(origin_line(pedsim, "/routines/route_1/1"), 12) << "the leave at the sink's addwaypoint";
  EXPECT_EQ(origin_line(pedsim, "/steps/0/actions/3/routine"), 17);
  EXPECT_EQ(origin_line(pedsim, "/name"), 0);

  const ImportResult imhus = import_imhus(read(kFixtures / "imhus/office.xml"), bundled());
  EXPECT_EQ(origin_line(imhus, "/humans/1/start"), 6);
  EXPECT_EQ(origin_line(imhus, "/locations/board"), 16);
  EXPECT_EQ(origin_line(imhus, "/social_spaces/huddle/slots/0"), 22) << "p1, the first taken";
  EXPECT_EQ(origin_line(imhus, "/routines/greet/1"), 31);
  int found = 0;
  for (std::size_t s = 0; s < imhus.scenario["steps"].size(); ++s) {
    const auto& actions = imhus.scenario["steps"][s]["actions"];
    for (std::size_t a = 0; a < actions.size(); ++a) {
      EXPECT_FALSE(actions[a].contains("_xml_line")) << "no importer's key is left in the native scenario";
      if (actions[a].value("agent", "") != "bo" || !actions[a].contains("goto") || !actions[a]["goto"].contains("social_space")) continue;
      EXPECT_EQ(origin_line(imhus, "/steps/" + std::to_string(s) + "/actions/" + std::to_string(a) + "/goto"), 50);
      ++found;
    }
  }
  EXPECT_EQ(found, 1);
}

// Malformed XML is said in words at its line, not as TinyXML's error code.
TEST(ImportXml, MalformedXmlIsExplained) {
  const auto error = [](const std::string& xml) {
    const ImportResult result = import_pedsim(xml, bundled());
    return result.errors.empty() ? ImportMessage{} : result.errors.front();
  };
  const ImportMessage unclosed = error("<?xml version=\"1.0\"?>\n<scenario>\n  <agents x=\"1\" y=\"2\">\n    <addwaypoint id=\"a\"/>\n</scenario>\n");
  EXPECT_EQ(unclosed.line, 3);
  EXPECT_EQ(unclosed.message, "malformed XML: <agents> opened at line 3 is never closed (</scenario> at line 5 comes first)");
  EXPECT_EQ(error("<scenario>\n  <waypoint id=\"a\" x=\"1\" y=\"1\"/>\n").message, "malformed XML: <scenario> opened at line 1 is never closed");
  EXPECT_EQ(error("<scenario>\n  <!-- a note\n</scenario>\n").message, "malformed XML: a comment at line 2 is never finished");
  EXPECT_EQ(error("<scenario>\n  <waypoint id=\"a\" x=\"1\"\n").message, "malformed XML: the tag <waypoint> at line 2 is never finished");
  const ImportMessage attribute = error("<scenario>\n  <waypoint id=a x=\"1\"/>\n</scenario>\n");
  EXPECT_EQ(attribute.line, 2);
  EXPECT_EQ(attribute.message, "malformed XML at line 2: an attribute is not name=\"value\"");
}

// Issue 40, finding 9: 200,000 nested elements cost 84 s of CPU before the depth error (each tag's
// line was counted from the start of the text).
TEST(ImportXml, DeepNestingIsRefusedAtItsLineInLinearTime) {
  std::string deep = "<?xml version=\"1.0\"?>\n<scenario>\n";
  for (int i = 0; i < 200000; ++i) deep += "<a>\n";
  std::string closed = deep;
  for (int i = 0; i < 200000; ++i) closed += "</a>";
  closed += "</scenario>\n";
  const auto started = std::chrono::steady_clock::now();
  for (const std::string& xml : {deep, closed}) {
    for (const ImportResult& result : {import_pedsim(xml, bundled()), import_imhus(xml, bundled())}) {
      ASSERT_EQ(result.errors.size(), 1u);
      EXPECT_EQ(result.errors[0].line, 66) << "the 64th <a> is the 65th level";
      EXPECT_EQ(result.errors[0].message, "<a> at line 66 nests more than 64 elements deep; IMHuS and Pedsim files nest at most five");
    }
  }
  // Many sibling tags before a fault: the explanation counts lines as it goes, too.
  std::string siblings = "<scenario>\n";
  for (int i = 0; i < 200000; ++i) siblings += "<waypoint id=\"w\" x=\"1\" y=\"1\"/>\n";
  siblings += "<agent>\n";
  const ImportResult unclosed = import_pedsim(siblings, bundled());
  ASSERT_FALSE(unclosed.errors.empty());
  EXPECT_EQ(unclosed.errors[0].message, "malformed XML: <agent> opened at line 200002 is never closed");
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(5)) << "linear, not quadratic";
  // 64 levels are read.
  std::string sixty_four = "<scenario>";
  for (int i = 1; i < 64; ++i) sixty_four += "<a>";
  EXPECT_FALSE(has_message(import_pedsim(sixty_four, bundled()).errors, 1, "nests more than"));
}

TEST(ImportImhus, MalformedXmlAndUnknownMap) {
  const ImportResult broken = import_imhus("<agents>\n  <human id=\"a\">\n</agents>\n", bundled());
  ASSERT_EQ(broken.errors.size(), 1u);
  EXPECT_TRUE(has_message(broken.errors, 2, "malformed XML: <human> opened at line 2 is never closed (</agents> at line 3 comes first)"));
  std::string xml = read(kFixtures / "imhus/office.xml");
  xml.replace(xml.find("name=\"elevator\""), 15, "name=\"moon\"");
  EXPECT_TRUE(has_message(import_imhus(xml, bundled()).errors, 3, "unknown map 'moon'"));
}

// IMHuS's published elevator choreography (reference data, read in place from ../shared/external).
TEST(ImportImhus, RealElevatorFileImportsCompletely) {
  if (!std::filesystem::exists(kElevatorGoals)) {
    GTEST_SKIP() << no_reference_file("imhus/elevator_goals.xml", "tests/fixtures/imhus/lift.xml (ImportImhus.LiftFixtureImportsCompletely)");
  }
  const ImportResult imported = import_imhus(read(kElevatorGoals), bundled());
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->name, "take_elevator");
  EXPECT_EQ(model->steps.size(), 10u);
  EXPECT_EQ(model->steps.back().name, "step3");
  EXPECT_EQ(model->agents.size(), 7u);
  EXPECT_EQ(model->routines.size(), 11u);
  EXPECT_EQ(model->async_routines.size(), 2u);
  ASSERT_EQ(model->social_spaces.size(), 3u);
  EXPECT_EQ(model->social_spaces[0].slots.size(), 5u);
  EXPECT_EQ(model->elevators.size(), 1u);
}

struct ElevatorRun {
  bool completed;
  std::string last_step;
  std::vector<std::string> publications;  ///< topic=message in order
  std::vector<std::string> accepted_by;
};

/// Runs an IMHuS file on the bundled elevator world; the robot `robot_id` asks for `task` at each of `request_times`.
ElevatorRun run_elevator(const std::filesystem::path& file, const std::string& robot_id, const std::string& task,
                         const std::vector<double>& request_times, double time_limit) {
  const ImportResult imported = import_imhus(read(file), bundled());
  const auto model = load_imported(imported);
  if (!model) return {};
  episode::Episode session_run(model, 1);
  sim::Session& session = session_run.session();
  const sim::AgentId robot = session.agent_id(robot_id);
  for (double time : request_times) session.schedule_request(time, robot, model->find_routine(task));
  session.set_time_limit(time_limit);
  session_run.run();
  ElevatorRun run{session.state().termination == sim::Termination::scenario_end, "", {}, {}};
  for (const sim::Event& event : session.state().events) {
    if (const auto* published = event.as<sim::events::Publish>()) run.publications.push_back(published->topic + "=" + published->message);
    if (event.is<sim::events::RequestAccepted>()) run.accepted_by.push_back(event.subject);
    if (event.is<sim::events::TimeLimit>()) run.last_step = event.subject;
  }
  return run;
}

TEST(ImportImhus, RealElevatorFileWaitsForTheRobotsRequest) {
  if (!std::filesystem::exists(kElevatorGoals)) {
    GTEST_SKIP() << no_reference_file("imhus/elevator_goals.xml", "tests/fixtures/imhus/lift.xml (ImportImhus.LiftFixtureWaitsForTheRobotsRequest)");
  }
  const ElevatorRun alone = run_elevator(kElevatorGoals, "tiago", "take_robot_floor2", {}, 240.0);
  EXPECT_FALSE(alone.completed);
  EXPECT_EQ(alone.last_step, "step") << "human6 waits for door 1, which nobody opens";
  EXPECT_EQ(alone.publications,
            (std::vector<std::string>{"/elevator/request=door2", "/elevator/request=floor1", "/elevator/request=floor2"}));
}

TEST(ImportImhus, RealElevatorFileCompletesWithRepeatedRobotRequests) {
  if (!std::filesystem::exists(kElevatorGoals)) {
    GTEST_SKIP() << no_reference_file("imhus/elevator_goals.xml",
                                      "tests/fixtures/imhus/lift.xml (ImportImhus.LiftFixtureCompletesWhenAHumanAnswersTheRobot)");
  }
  const ElevatorRun helped = run_elevator(kElevatorGoals, "tiago", "take_robot_floor2", {100.0, 130.0, 160.0}, 240.0);
  EXPECT_TRUE(helped.completed);
  ASSERT_FALSE(helped.accepted_by.empty());
  EXPECT_EQ(helped.accepted_by[0], "human5") << "the idle human nearest the robot on floor 1";
  EXPECT_EQ(helped.publications,
            (std::vector<std::string>{"/elevator/request=door2", "/elevator/request=floor1", "/elevator/request=floor2",
                                      "/elevator/request=door1", "/elevator/request=floor2"}));
}

// hrisim's own lift choreography (tests/fixtures/imhus/lift.xml) takes the importer paths of IMHuS's
// published elevator file: comments and a commented-out agent and <groups>, slots p1..pN out of order, a
// cabin social space the bundled world's elevator clears, compound tasks calling that elevator, step
// actions of any tag with a taskID, a wait_action with event before topic, a relativeX on a turned pose,
// '2.' numbers, two AsyncActions, the robot at initial_pose_robot, a second scenario after the first.
TEST(ImportImhus, LiftFixtureImportsCompletely) {
  const ImportResult imported = import_imhus(read(kFixtures / "imhus/lift.xml"), bundled());
  for (const auto& w : imported.warnings) ADD_FAILURE() << "unexpected warning, line " << w.line << ": " << w.message;
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->name, "ride_up") << "the file's first scenario";
  ASSERT_EQ(model->steps.size(), 5u);
  EXPECT_EQ(model->steps[1].name, "call");
  EXPECT_EQ(model->steps.back().name, "fetch");
  EXPECT_EQ(model->steps[1].actions[0].kind, Action::Kind::run_routine) << "<use_lift taskID=...> runs a compound task";
  ASSERT_EQ(model->agents.size(), 4u) << "kim, lou, max and the robot; ned is commented out";
  EXPECT_EQ(model->agents[2].id, "max");
  EXPECT_TRUE(model->agents[2].start.position().isApprox(Vec2(-7, 2))) << "agents start at their first goto";
  EXPECT_EQ(model->agents[3].id, "rex");
  EXPECT_EQ(model->agents[3].kind, AgentKind::robot);
  EXPECT_TRUE(model->agents[3].start.position().isApprox(Vec2(8.5, -4))) << "the robot starts at initial_pose_robot";
  EXPECT_EQ(model->routines.size(), 4u);
  ASSERT_EQ(model->async_routines.size(), 2u);
  EXPECT_EQ(model->routines[model->async_routines[0]].name, "help_rex");
  EXPECT_EQ(model->routines[model->async_routines[1]].name, "greet");
  EXPECT_DOUBLE_EQ(model->routines[model->find_routine("greet")].actions[1].value, 2.0) << "'2.' is a number";
  const Action& wait_for_door = model->routines[model->find_routine("call_lift1")].actions[2];
  EXPECT_EQ(wait_for_door.kind, Action::Kind::wait_message);
  EXPECT_EQ(wait_for_door.topic, "/elevator/door1_state");
  EXPECT_EQ(wait_for_door.message, "open");
  const Location* button = nullptr;
  for (const Location& location : model->locations) {
    if (location.name == "button1") button = &location;
  }
  ASSERT_NE(button, nullptr);
  EXPECT_DOUBLE_EQ(button->pose.x, 2.0) << "'2.' is a number";
  ASSERT_EQ(model->social_spaces.size(), 2u);
  const SocialSpace* cabin = nullptr;
  for (const SocialSpace& space : model->social_spaces) {
    if (space.name == "elevator") cabin = &space;
  }
  ASSERT_NE(cabin, nullptr);
  ASSERT_EQ(cabin->slots.size(), 3u);
  EXPECT_TRUE(cabin->slots[0].position().isApprox(Vec2(0.5, 0.5))) << "p1 is taken first, though p3 comes first in the file";
  EXPECT_TRUE(cabin->slots[2].position().isApprox(Vec2(-0.5, -0.5)));
  ASSERT_EQ(model->elevators.size(), 1u) << "map_name 'elevator' brings the bundled elevator world";
  ASSERT_EQ(model->elevators[0].social_spaces.size(), 1u);
  EXPECT_EQ(model->social_spaces[model->elevators[0].social_spaces[0]].name, "elevator") << "the elevator clears the file's cabin";
  // relativeX is along the map's x axis: sofa2 (-4, -1.5), turned by 1.57, less 2 m in x is (-6, -1.5).
  const Action& to_sofa = model->steps[3].actions[0];
  const Pose2 goal = core::compose(model->locations[to_sofa.target].pose, to_sofa.pose);
  EXPECT_NEAR(goal.x, -6.0, 1e-9);
  EXPECT_NEAR(goal.y, -1.5, 1e-9);
}

TEST(ImportImhus, LiftFixtureWaitsForTheRobotsRequest) {
  const ElevatorRun alone = run_elevator(kFixtures / "imhus/lift.xml", "rex", "help_rex", {}, 150.0);
  EXPECT_FALSE(alone.completed);
  EXPECT_EQ(alone.last_step, "fetch") << "kim has ridden up; max waits for door 1, which nobody opens";
  EXPECT_TRUE(alone.accepted_by.empty());
  EXPECT_EQ(alone.publications, (std::vector<std::string>{"/elevator/request=door1", "/elevator/request=floor2"}));
}

TEST(ImportImhus, LiftFixtureCompletesWhenAHumanAnswersTheRobot) {
  const ElevatorRun helped = run_elevator(kFixtures / "imhus/lift.xml", "rex", "help_rex", {60.0}, 150.0);
  EXPECT_TRUE(helped.completed);
  EXPECT_EQ(helped.accepted_by, (std::vector<std::string>{"lou"})) << "the idle human within 3 m of the robot";
  EXPECT_EQ(helped.publications,
            (std::vector<std::string>{"/elevator/request=door1", "/elevator/request=floor2", "/elevator/request=floor1"}))
      << "lou calls the lift down to floor 1 for the robot";
}

TEST(ImportPedsim, OwnFixture) {
  const ImportResult imported = import_pedsim(read(kFixtures / "pedsim/hall.xml"), bundled());
  EXPECT_TRUE(imported.warnings.empty()) << "outside, after the sink, is headed for by nobody: no warning that they cannot reach it";
  EXPECT_EQ(imported.scenario["attractions"]["coffee"],
            nlohmann::ordered_json::parse(R"({"x": 6.0, "y": 7.0, "width": 1.0, "height": 1.0, "strength": 1.0})"));
  EXPECT_EQ(origin_line(imported, "/attractions/coffee"), 20);
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  ASSERT_EQ(model->agents.size(), 5u);
  int humans = 0;
  for (const AgentDef& agent : model->agents) {
    if (agent.kind != AgentKind::human) continue;
    ++humans;
    EXPECT_EQ(agent.avoidance, humans::LocalAvoidance::social_force);
  }
  EXPECT_EQ(humans, 4);
  for (int i = 0; i < 3; ++i) {
    const Vec2 start = model->agents[i].start.position();
    EXPECT_GE(start.x(), 2.0);
    EXPECT_LE(start.x(), 4.0);
    EXPECT_GE(start.y(), 3.0);
    EXPECT_LE(start.y(), 5.0);
  }
  EXPECT_EQ(model->agents[3].type, "elder");
  EXPECT_EQ(model->agents[4].kind, AgentKind::robot);
  ASSERT_EQ(model->routines.size(), 2u);
  EXPECT_EQ(model->routines[0].actions.size(), 2u) << "right is a sink: whoever reaches it leaves, so left and outside are never walked";
  EXPECT_EQ(model->locations.size(), 3u) << "a waypoint beyond the walls is kept, as Pedsim keeps it";
  EXPECT_EQ(model->steps[0].actions.size(), 3u + 1) << "each walker cycles through its cluster's route";
  EXPECT_GE(imported.scenario["world"]["bounds"]["max"][0].get<double>(), 21.0) << "the map reaches the waypoint beyond the walls";
  const ImportResult again = import_pedsim(read(kFixtures / "pedsim/hall.xml"), bundled());
  EXPECT_EQ(again.scenario.dump(), imported.scenario.dump()) << "cluster placement is reproducible";
}

TEST(ImportPedsim, ErrorsNameTheLine) {
  std::string xml = read(kFixtures / "pedsim/hall.xml");
  xml.replace(xml.find(R"(<addwaypoint id="outside"/>)"), 27, R"(<addwaypoint id="nowhere"/>)");
  xml.replace(xml.find(R"(x2="12" y2="0")"), 14, R"(x2="twelve" y2="0")");
  xml.replace(xml.find(R"(type="3")"), 8, R"(type="7")");
  const ImportResult result = import_pedsim(xml, bundled());
  EXPECT_TRUE(has_message(result.errors, 14, "unknown waypoint 'nowhere'"));
  EXPECT_TRUE(has_message(result.errors, 4, "attribute 'x2' must be a number"));
  EXPECT_TRUE(has_message(result.errors, 17, "type must be 0 (adult), 1 (child), 2 (robot) or 3 (elder)"));
}

/// How many times each agent arrives at a location other than the one it last reached, over `seconds`
/// of an episode (a Pedsim walker cycling through a route of two places makes more than two).
std::vector<int> arrivals(const std::shared_ptr<const Model>& model, double seconds) {
  episode::Episode run(model, 1);
  sim::Session& session = run.session();
  session.set_time_limit(seconds);
  std::vector<int> count(model->agents.size(), 0), last(model->agents.size(), -1);
  while (!run.over()) {
    run.tick();
    for (std::size_t a = 0; a < model->agents.size(); ++a) {
      for (std::size_t l = 0; l < model->locations.size(); ++l) {
        const Location& place = model->locations[l];
        if (static_cast<int>(l) == last[a] || (session.state().agents[a].position - place.pose.position()).norm() > place.radius + 0.05) continue;
        last[a] = static_cast<int>(l);
        ++count[a];
      }
    }
  }
  EXPECT_EQ(session.state().termination, sim::Termination::timeout) << "a looping route runs to the time limit";
  return count;
}

/// People coming and going over `seconds` of an episode: how many entered (a source's later rounds),
/// how many left (at a sink), and the most in the scene at once.
struct Flow {
  int entered = 0, left = 0, most = 0;
};

Flow flow(const std::shared_ptr<const Model>& model, double seconds) {
  episode::Episode run(model, 1);
  sim::Session& session = run.session();
  session.set_time_limit(seconds);
  Flow counted;
  while (!run.over()) {
    run.tick();
    const auto& agents = session.state().agents;
    counted.most = std::max(counted.most, static_cast<int>(std::count_if(agents.begin(), agents.end(), [](const sim::AgentState& a) { return a.active; })));
  }
  for (const sim::Event& event : session.state().events) {
    counted.entered += event.is<sim::events::Entered>();
    counted.left += event.is<sim::events::Left>();
  }
  return counted;
}

// Pedsim's published corridor (reference data, read in place): a source adding 8 walkers every 5 s who
// walk east, then west into a sink.
TEST(ImportPedsim, RealCorridorImportsAndRuns) {
  if (!std::filesystem::exists(kCorridor)) {
    GTEST_SKIP() << no_reference_file("pedsim/corridor.xml", "tests/fixtures/pedsim/passage.xml (ImportPedsim.PassageFixtureImportsAndRuns)");
  }
  const ImportResult imported = import_pedsim(read(kCorridor), bundled());
  EXPECT_TRUE(has_message(imported.warnings, 17, "the robot agent's route is not walked"));
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->agents.size(), 8u * 60 + 1) << "the source's 8 at the start and in each 5 s of the 300 s, and the robot";
  EXPECT_EQ(model->locations.size(), 4u) << "robot_goal, beyond the walls, is kept";
  const Flow passed = flow(model, 60.0);
  EXPECT_EQ(passed.entered, 8 * 11) << "rounds at 5, 10, …, 55 s";
  EXPECT_GE(passed.left, 8 * 4) << "walkers reach the sink 20 m on and leave";
  EXPECT_LT(passed.most, 8 * 9) << "the corridor does not fill up: people leave as others come";
}

// hrisim's own passage (tests/fixtures/pedsim/passage.xml) takes the importer paths of Pedsim's published
// corridor: comments, a <source> cluster, source and sink waypoints, a robot with a route, a waypoint
// outside the walls. Its source adds six walkers every 5 s; they walk to the far end, a sink, and leave.
TEST(ImportPedsim, PassageFixtureImportsAndRuns) {
  const ImportResult imported = import_pedsim(read(kFixtures / "pedsim/passage.xml"), bundled());
  EXPECT_TRUE(has_message(imported.warnings, 17, "the robot agent's route is not walked"));
  EXPECT_EQ(imported.warnings.size(), 1u) << "a source waypoint (b=1) means nothing to pedsim_ros either";
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  ASSERT_EQ(model->agents.size(), 6u * 60 + 1);
  for (int i = 0; i < 6 * 60; ++i) {
    const AgentDef& walker = model->agents[i];
    EXPECT_EQ(walker.kind, AgentKind::human);
    EXPECT_EQ(walker.avoidance, humans::LocalAvoidance::social_force);
    EXPECT_DOUBLE_EQ(walker.enters_at, 5.0 * (i / 6)) << "round " << i / 6;
    const Vec2 start = walker.start.position();
    EXPECT_GE(start.x(), 2.0);
    EXPECT_LE(start.x(), 5.0);
    EXPECT_GE(start.y(), 1.5);
    EXPECT_LE(start.y(), 6.5);
  }
  const AgentDef& robot = model->agents.back();
  EXPECT_EQ(robot.id, "robot_0");
  EXPECT_EQ(robot.kind, AgentKind::robot);
  EXPECT_TRUE(robot.start.position().isApprox(Vec2(6, 7.2)));
  EXPECT_EQ(model->locations.size(), 3u) << "far, back, and dock beyond the walls";
  ASSERT_EQ(model->routines.size(), 1u);
  ASSERT_EQ(model->routines[0].actions.size(), 2u) << "to far, then leave: back, after the sink, is never walked";
  EXPECT_EQ(model->routines[0].actions[1].kind, Action::Kind::leave);
  EXPECT_EQ(origin_line(imported, "/routines/route_1/1"), 23) << "the leave at the sink's addwaypoint";
  const Flow passed = flow(model, 60.0);
  EXPECT_EQ(passed.entered, 6 * 11);
  EXPECT_GE(passed.left, 6 * 5) << "the far end is 12 m on";
  EXPECT_LT(passed.most, 6 * 8);
}

ImportOptions few_people(int people) {
  ImportOptions options = bundled();
  options.limits.max_people = people;
  return options;
}

TEST(ImportPedsim, ASourcesRoundsAreCutToThePeopleLimitWithAWarning) {
  const ImportResult imported = import_pedsim(read(kFixtures / "pedsim/passage.xml"), few_people(40));
  EXPECT_TRUE(has_message(imported.warnings, 22, "this source adds 6 people every 5 s: only the first 5 of its 59 rounds fit"));
  EXPECT_EQ(imported.scenario["humans"].size(), 6u * 6);
}

/// Distance from p to the nearest of the file's walls (the native scenario's `walls`).
double wall_distance(const nlohmann::ordered_json& scenario, const Vec2& p) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& wall : scenario["world"]["walls"]) {
    const Vec2 a(wall["from"][0].get<double>(), wall["from"][1].get<double>()), b(wall["to"][0].get<double>(), wall["to"][1].get<double>());
    nearest = std::min(nearest, (core::closest_point_on_segment(p, a, b) - p).norm());
  }
  return nearest;
}

// What real pedsim_ros files do that hrisim refused (issue 21), in hrisim's own fixture: a waypoint
// centred on a wall, one without r, a queue as a waypoint and with addqueue, a cluster over a wall,
// an agent and a waypoint beyond the outermost obstacle, a robot with a route.
TEST(ImportPedsim, RealFilesHabitsImportAndRun) {
  const ImportResult imported = import_pedsim(read(kFixtures / "pedsim/bookshop.xml"), bundled());
  EXPECT_TRUE(has_message(imported.warnings, 27, "the robot agent's route is not walked"));
  EXPECT_EQ(imported.warnings.size(), 1u);
  // The queue is a waiting line (its direction 0°: people face +x, the line runs back towards -x),
  // joined by addqueue and addwaypoint alike.
  EXPECT_EQ(imported.scenario["queues"]["info_desk"], nlohmann::ordered_json::parse(R"({"x": 3.0, "y": 2.0, "theta": 0.0})"));
  EXPECT_EQ(imported.scenario["routines"]["route_1"][2], nlohmann::ordered_json::parse(R"({"queue": "info_desk"})"));
  EXPECT_EQ(imported.scenario["routines"]["route_2"][0], nlohmann::ordered_json::parse(R"({"queue": "info_desk"})"));
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  const auto location = [&](const std::string& name) {
    for (const Location& l : model->locations) {
      if (l.name == name) return l;
    }
    ADD_FAILURE() << "no location " << name;
    return Location{};
  };
  // The goal of the waypoint centred on the wall is the free point of its disc nearest the centre.
  const Location exit = location("shop_exit");
  EXPECT_GE(wall_distance(imported.scenario, exit.pose.position()), 0.4 - 1e-9);
  EXPECT_LE((exit.pose.position() - Vec2(9, 3)).norm(), 0.45);
  EXPECT_NEAR(location("till").radius, 0.2, 1e-12) << "no r: Pedsim's 0, reached within the least radius";
  EXPECT_TRUE(location("info_desk").pose.position().isApprox(Vec2(3, 2)));
  EXPECT_TRUE(location("yard").pose.position().isApprox(Vec2(16, 4))) << "beyond the outer wall, kept";
  for (const AgentDef& agent : model->agents) {
    if (agent.id == "agent_5") {
      EXPECT_TRUE(agent.start.position().isApprox(Vec2(16, 4))) << "an agent beyond the outer wall is kept where it is";
      continue;
    }
    EXPECT_GE(wall_distance(imported.scenario, agent.start.position()), 0.4 - 1e-9) << agent.id << " is drawn again off the wall";
  }
  EXPECT_EQ(model->steps[0].actions.size(), 4u + 1 + 1) << "each person cycles through their cluster's route; the robot's route is not walked";
  const std::vector<int> reached = arrivals(model, 120.0);
  for (int walker = 0; walker < 4; ++walker) EXPECT_GE(reached[walker], 4) << "agent_" << walker << " goes round shop_exit, till and info_desk more than once";
}

// A waypoint centred on an outer wall has free points inside and outside; the goal is the one the
// walkers heading there can reach (the nearest to the centre, outside at (10.4, 3), is not).
TEST(ImportPedsim, AGoalAcrossAWallIsPutWhereItsWalkersCanGetTo) {
  const std::string xml = R"(<scenario>
  <obstacle x1="0" y1="0" x2="10" y2="0"/>
  <obstacle x1="10" y1="0" x2="10" y2="6"/>
  <obstacle x1="10" y1="6" x2="0" y2="6"/>
  <obstacle x1="0" y1="6" x2="0" y2="0"/>
  <waypoint id="back_door" x="10" y="3" r="1.5"/>
  <waypoint id="desk" x="3" y="3" r="0.5"/>
  <waypoint id="roof" x="11.5" y="3" r="0.5"/>
  <agent x="5" y="3" n="2" dx="1" dy="1" type="0">
    <addwaypoint id="back_door"/>
    <addwaypoint id="desk"/>
  </agent>
  <agent x="5" y="2" n="1" type="0">
    <addwaypoint id="roof"/>
  </agent>
</scenario>)";
  const ImportResult imported = import_pedsim(xml, bundled());
  EXPECT_TRUE(has_message(imported.warnings, 8, "waypoint 'roof': no free point of its disc can be reached from where the agents heading there start"));
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  const Location& door = model->locations[0];
  ASSERT_EQ(door.name, "back_door");
  EXPECT_LT(door.pose.position().x(), 10.0 - 0.4 + 1e-9) << "inside, where the walkers are";
  EXPECT_LE((door.pose.position() - Vec2(10, 3)).norm(), 0.6) << "near the centre";
  const std::vector<int> reached = arrivals(model, 60.0);
  for (int walker = 0; walker < 2; ++walker) EXPECT_GE(reached[walker], 3) << "agent_" << walker << " goes between the back door and the desk";
}

// libpedsim's own examples: a <welcome> root, no obstacles at all.
TEST(ImportPedsim, WelcomeRootWithoutObstacles) {
  const std::string xml = read(kFixtures / "pedsim/welcome.xml");
  EXPECT_EQ(detect_xml_format(xml), "pedsim");
  const ImportResult imported = import_pedsim(xml, bundled());
  EXPECT_TRUE(has_message(imported.warnings, 1, "no <obstacle>: the map is open ground"));
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->agents.size(), 6u);
  EXPECT_LE(imported.scenario["world"]["bounds"]["min"][0].get<double>(), -24.0) << "the map takes in the waypoints' discs";
  // The discs are 41 m apart: in 180 s even a walker 2 standard deviations slower than the mean
  // preferred speed (1.34 ± 0.26 m/s) arrives three times.
  const std::vector<int> reached = arrivals(model, 180.0);
  for (int walker = 0; walker < 6; ++walker) EXPECT_GE(reached[walker], 3) << "walker " << walker << " goes between w1 and w2 more than once";
}

// pedsim_ros's parameters (obstacle σ 0.2 m, social factor 5.1) let a walker reach a waypoint 0.6 m
// from a wall; with libpedsim's (σ 0.8 m) the wall holds it about 1.35 m off, and after 10 s without
// progress it is reported stuck instead of stalling silently.
TEST(ImportPedsim, PedsimRosParametersReachWaypointsByWallsAndAJamIsReported) {
  const std::string xml = R"(<scenario>
  <obstacle x1="0" y1="0" x2="10" y2="0"/><obstacle x1="10" y1="0" x2="10" y2="4"/>
  <obstacle x1="10" y1="4" x2="0" y2="4"/><obstacle x1="0" y1="4" x2="0" y2="0"/>
  <waypoint id="by_wall" x="5" y="0.6" r="0.3"/>
  <waypoint id="middle" x="5" y="2.5" r="0.3"/>
  <agent x="2" y="2" n="1"><addwaypoint id="by_wall"/><addwaypoint id="middle"/></agent>
</scenario>)";
  const auto walk = [&](const std::string& dialect) {
    ImportOptions options = bundled();
    options.dialect = dialect;
    const ImportResult imported = import_pedsim(xml, options);
    const auto model = load_imported(imported);
    episode::Episode run(model, 1);
    run.session().set_time_limit(40.0);
    bool reached = false;
    while (!run.over()) {
      run.tick();
      reached |= (run.session().state().agents[0].position - Vec2(5, 0.6)).norm() <= 0.3;
    }
    int stuck = 0;
    for (const sim::Event& event : run.session().state().events) stuck += event.is<sim::events::Stuck>();
    return std::tuple{imported.scenario["locomotion"], reached, stuck};
  };
  const auto [ros_locomotion, ros_reached, ros_stuck] = walk("");
  EXPECT_EQ(ros_locomotion["social_force"]["obstacle_sigma"], kPedsimRosObstacleSigma) << "pedsim_ros's, by default for <scenario>";
  EXPECT_EQ(ros_locomotion["social_force"]["social_factor"], kPedsimRosSocialFactor);
  EXPECT_TRUE(ros_reached);
  EXPECT_EQ(ros_stuck, 0);
  const auto [lib_locomotion, lib_reached, lib_stuck] = walk("libpedsim");
  EXPECT_FALSE(lib_locomotion.contains("social_force")) << "libpedsim's own defaults";
  EXPECT_FALSE(lib_reached) << "the wall holds the walker off";
  EXPECT_EQ(lib_stuck, 1) << "reported once, not every tick";
  ImportOptions unknown = bundled();
  unknown.dialect = "menge";
  EXPECT_TRUE(has_message(import_pedsim(xml, unknown).errors, 0, "unknown Pedsim dialect 'menge' (pedsim_ros or libpedsim)"));
}

// A scene hundreds of metres across (pedsim_ros's airport) gets a grid coarse enough to build.
TEST(ImportPedsim, LargeScenesGetACoarserGridWithAWarning) {
  const std::string xml = R"(<scenario>
  <obstacle x1="0" y1="0" x2="600" y2="0"/><obstacle x1="600" y1="0" x2="600" y2="400"/>
  <obstacle x1="600" y1="400" x2="0" y2="400"/><obstacle x1="0" y1="400" x2="0" y2="0"/>
  <waypoint id="far" x="590" y="390" r="5"/>
  <agent x="10" y="10" n="1"><addwaypoint id="far"/></agent>
</scenario>)";
  const ImportResult imported = import_pedsim(xml, bundled());
  EXPECT_TRUE(has_message(imported.warnings, 1, "the scene spans 602 x 402 m: its grid gets 0.25 m cells"));
  EXPECT_EQ(imported.scenario["world"]["resolution"], 0.25);
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->grid.resolution(), 0.25);
  const ImportResult small = import_pedsim(read(kFixtures / "pedsim/hall.xml"), bundled());
  EXPECT_FALSE(small.scenario["world"].contains("resolution")) << "a room keeps the default 0.05 m";
}

TEST(DetectXmlFormat, PedsimHasOneScenarioRoot) {
  EXPECT_EQ(detect_xml_format(read(kFixtures / "pedsim/hall.xml")), "pedsim");
  EXPECT_EQ(detect_xml_format(read(kFixtures / "imhus/office.xml")), "imhus");
}


// IMHuS's own files: a placeholder social space without slots (harmless unless used), and agents whose
// initial poses are kept in a scenario of their own (`init`), their chosen scenario only waiting at first.
TEST(ImportImhus, EmptySocialSpacesAndInitialPosesFromAnotherScenario) {
  std::string xml = read(kFixtures / "imhus/office.xml");
  xml.replace(xml.find("  </social_space>"), 0, "    <lobby id=\"lobby\" x=\"2\" y=\"2\">\n      <!-- TODO -->\n    </lobby>\n");
  xml.replace(xml.find("    <solo>"), 0, "    <late>\n      <first>\n        <wait_action entityID=\"ann\" duration=\"1\"/>\n      </first>\n    </late>\n");
  const ImportResult late = import_imhus(xml, bundled("late"));
  EXPECT_TRUE(has_message(late.warnings, 25, "social space 'lobby' has no slots and is left out"));
  const auto model = load_imported(late);
  ASSERT_TRUE(model);
  const int ann = model->find_agent("ann");
  ASSERT_GE(ann, 0);
  EXPECT_TRUE(model->agents[ann].start.position().isApprox(Vec2(4, -3))) << "where meeting's first step puts her";
  EXPECT_EQ(model->find_agent("bo"), -1) << "bo takes no part in 'late'";

  xml.replace(xml.find(R"(<goto_action entityID="bo" socialSpaceID="huddle"/>)"), 52, R"(<goto_action entityID="bo" socialSpaceID="lobby"/>)");
  const ImportResult used = import_imhus(xml, bundled("meeting"));
  EXPECT_TRUE(has_message(used.errors, 53, "social space 'lobby' has no slots (line 25)"));
}

TEST(ImportImhus, GroupsAndARobotChoreographyBesideTheScenario) {
  const ImportResult imported = import_imhus(read(kFixtures / "imhus/duo.xml"), bundled());
  ASSERT_TRUE(imported.scenario.contains("groups"));
  EXPECT_EQ(imported.scenario["groups"]["pair"]["members"], (nlohmann::ordered_json{"ann", "bo"}));
  const auto model = load_imported(imported);
  ASSERT_TRUE(model);
  ASSERT_EQ(model->steps.size(), 3u) << "duo_walk_robot's three steps join duo_walk's two, step by step";
  EXPECT_EQ(model->steps[0].actions.size(), 3u);
  EXPECT_EQ(model->steps[1].actions[0].group, 0);
  EXPECT_EQ(model->steps[2].name, "ask");
  EXPECT_EQ(model->steps[2].actions[0].kind, Action::Kind::request);
  EXPECT_TRUE(model->agents[2].start.position().isApprox(Vec2(7, 2))) << "the robot starts at its first goto";

  episode::Episode session_run(model, 1);
  sim::Session& session = session_run.session();
  session.set_time_limit(120.0);
  session_run.run();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
}

TEST(ImportImhus, GroupsTakeGotoWaitLookAtAndCompoundTasks) {
  const std::string duo = read(kFixtures / "imhus/duo.xml");
  const std::string group_goto = R"(<goto_action entityID="pair" poseID="far_end"/>)";
  const auto with = [&](const std::string& instead) {
    std::string xml = duo;
    return xml.replace(xml.find(group_goto), group_goto.size(), instead);
  };
  // IMHuS's compound tasks for groups and pairs: every member runs the task, keeping together.
  const ImportResult task = import_imhus(with(R"(<together entityID="pair" taskID="wave"/>)"), bundled());
  ASSERT_TRUE(task.errors.empty()) << task.errors.front().message;
  const auto model = load_imported(task);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->steps[1].actions[0].group, 0);
  EXPECT_EQ(model->steps[1].actions[0].kind, Action::Kind::run_routine);
  EXPECT_EQ(model->routines[model->steps[1].actions[0].target].name, "wave");
  const ImportResult wait = import_imhus(with(R"(<wait_action entityID="pair" duration="1"/>)"), bundled());
  EXPECT_TRUE(wait.errors.empty());
  EXPECT_EQ(wait.scenario["steps"][1]["actions"][0]["group"], "pair");

  std::string xml = with(R"(<publish_action entityID="pair" topic="/bell" msg="ring"/>)");
  xml.replace(xml.find(R"(members="ann bo")"), 16, R"(members="ann zed")");
  const ImportResult result = import_imhus(xml, bundled());
  EXPECT_TRUE(has_message(result.errors, 11, "unknown member 'zed' of group 'pair'"));
  EXPECT_TRUE(has_message(result.errors, 38, "a group (pair) can be given a goto_action, wait_action, lookat_action or a compound task (taskID)"));
}

}  // namespace
}  // namespace hrisim::scenario
