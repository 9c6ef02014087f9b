// The audit's wrong answer (issue 40): a run with another controller type dropped the scenario's goal,
// so a robot that never moved "succeeded". A swap now keeps what the scenario gave its robot.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "runs/episode.hpp"
#include "runs/spec.hpp"
#include "scenario/model.hpp"

namespace hrisim::runs {
namespace {

using nlohmann::json;

const std::filesystem::path kScenarios = std::filesystem::path(HRISIM_SOURCE_DIR) / "scenarios";
const char* const kDrivingTypes[] = {"goal", "social", "dwa", "orca", "social_force"};

json read_scenario(const std::filesystem::path& file) {
  std::ifstream in(file);
  return json::parse(in);
}

RunRequest request_for(const json& document, json controller) {
  RunRequest request;
  request.scenario_id = "test";
  request.document = document;
  request.seeds = {1};
  request.controller = std::move(controller);
  return request;
}

const scenario::AgentDef& first_robot(const scenario::Model& model) {
  for (const scenario::AgentDef& agent : model.agents) {
    if (agent.kind == scenario::AgentKind::robot) return agent;
  }
  throw std::runtime_error("no robot");
}

TEST(ControllerSwap, ATypeChangeKeepsTheGoalOnEveryBundledScenarioWithOne) {
  int scenarios_with_goal = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kScenarios)) {
    if (entry.path().extension() != ".json") continue;
    const json document = read_scenario(entry.path());
    const json own = scenario_controller(document);
    if (!own.is_object() || !own.contains("goal")) continue;
    ++scenarios_with_goal;
    const scenario::LoadResult as_written = scenario::load_scenario(document, {});
    ASSERT_TRUE(as_written.model) << entry.path();
    const auto& goal = first_robot(*as_written.model).controller.goal;
    ASSERT_TRUE(goal) << entry.path();
    for (const char* type : kDrivingTypes) {
      const RunSpec spec = make_run_spec(request_for(document, {{"type", type}}));
      const scenario::RobotController& swapped = first_robot(*spec.model).controller;
      ASSERT_TRUE(swapped.goal) << entry.path() << " with " << type;
      EXPECT_EQ(swapped.goal->position(), goal->position()) << entry.path() << " with " << type;
      EXPECT_EQ(swapped.goal_radius, first_robot(*as_written.model).controller.goal_radius) << entry.path() << " with " << type;
      EXPECT_EQ(spec.config["effective_controller"]["goal"], own["goal"]);
      EXPECT_EQ(spec.config["effective_controller"]["type"], type);
      EXPECT_EQ(spec.config["controller"], json({{"type", type}})) << "the request is kept as asked";
    }
  }
  EXPECT_GE(scenarios_with_goal, 3) << "apartment, corridor_navigation and crossing_navigation have goals";
}

TEST(ControllerSwap, ARequestChangesOnlyWhatItGives) {
  const json document = read_scenario(kScenarios / "apartment.json");  // goal: living_room within 0.3 m
  EXPECT_EQ(effective_controller(document, {{"type", "dwa"}}), json::parse(R"({"type":"dwa","goal":{"location":"living_room","radius":0.3}})"));
  EXPECT_EQ(effective_controller(document, {{"type", "dwa"}, {"goal", {{"location", "kitchen"}}}}),
            json::parse(R"({"type":"dwa","goal":{"location":"kitchen","radius":0.3}})"))
      << "another place keeps the arrival radius";
  EXPECT_EQ(effective_controller(document, {{"type", "dwa"}, {"goal", {{"location", "kitchen"}, {"radius", 1.0}}}}),
            json::parse(R"({"type":"dwa","goal":{"location":"kitchen","radius":1.0}})"));
  EXPECT_EQ(effective_controller(document, {{"type", "dwa"}, {"goal", nullptr}}), json({{"type", "dwa"}})) << "null removes the goal";
  EXPECT_EQ(effective_controller(document, {{"type", "idle"}}), json({{"type", "idle"}})) << "idle takes no goal";
  EXPECT_EQ(effective_controller(document, {{"type", "teleop"}}), json({{"type", "teleop"}}));
  const json search = read_scenario(kScenarios / "apartment_search.json");
  EXPECT_EQ(effective_controller(search, {{"type", "search"}, {"strategy", "sweep"}}),
            json::parse(R"({"type":"search","person":"anna","strategy":"sweep"})"));
  EXPECT_EQ(effective_controller(search, {{"type", "goal"}}), json({{"type", "goal"}})) << "a goal controller has no person to search";
}

TEST(ControllerSwap, AGoalGivenToAControllerThatTakesNoneIsStillRefusedAtItsPointer) {
  const json document = read_scenario(kScenarios / "apartment.json");
  try {
    make_run_spec(request_for(document, {{"type", "idle"}, {"goal", {{"location", "kitchen"}}}}));
    FAIL() << "accepted";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.details()["pointer"], "/controller/goal");
  }
}

TEST(ControllerSwap, AReplayOfARunStoredBeforeEffectiveControllersReplacesTheControllerWhole) {
  // Such a run's robot had exactly the controller asked for: {"type": "social"} without a goal.
  const json document = read_scenario(kScenarios / "corridor_navigation.json");
  const RunSpec old_run = make_run_spec(replay_request(document, {}, {{"controller", {{"type", "social"}}}}, 1));
  EXPECT_FALSE(first_robot(*old_run.model).controller.goal);
  const RunSpec new_run = make_run_spec(request_for(document, {{"type", "social"}}));
  const RunSpec replayed = make_run_spec(replay_request(document, {}, new_run.config, 1));
  ASSERT_TRUE(first_robot(*replayed.model).controller.goal);
  EXPECT_EQ(replayed.config["effective_controller"], new_run.config["effective_controller"]);
}

TEST(ControllerSwap, TheSocialRobotOfCorridorNavigationDrivesToItsGoal) {
  // The audit's reproduction: `--controller '{"type":"social"}'` travelled 0.04 m and succeeded.
  const json document = read_scenario(kScenarios / "corridor_navigation.json");
  const RunSpec spec = make_run_spec(request_for(document, {{"type", "social"}}));
  const EpisodeResult result = run_episode(spec.model, 1, {});
  const auto metric = [&](const std::string& key) {
    for (const storage::MetricValue& value : result.record.metrics) {
      if (value.key == key) return value;
    }
    throw std::runtime_error("no metric " + key);
  };
  ASSERT_TRUE(metric("path_length").value);
  EXPECT_GT(*metric("path_length").value, 5.0) << "the robot drives down the corridor";
  ASSERT_TRUE(metric("final_distance_to_target").value) << "the goal is there";
  if (metric("success").value == 1.0) {
    EXPECT_LE(*metric("final_distance_to_target").value, 0.3 + 1e-9) << "success means at the goal";
  }
}

}  // namespace
}  // namespace hrisim::runs
