// The benchmark tasks of seed 003 §4.4: each reward term against values worked out by hand, the
// seed's settings as defaults, and each task over a real session.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <set>

#include "core/error.hpp"
#include "scenario/load.hpp"
#include "support/scenarios.hpp"
#include "episode/episode.hpp"
#include "tasks/environment.hpp"
#include "tasks/manipulation.hpp"
#include "tasks/rewards.hpp"

namespace hrisim::tasks {
namespace {

using nlohmann::json;

std::shared_ptr<const scenario::Model> bundled(const std::string& name, const json& patch = json::object()) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + name + ".json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  if (patch.empty()) return loaded.model;
  json document = json::parse(std::ifstream(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + name + ".json"));
  document.merge_patch(patch);
  const auto patched = scenario::load_scenario(document, {});
  for (const auto& e : patched.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  return patched.model;
}

/// An episode of a task scenario, with the names the tests use.
struct TaskRun {
  explicit TaskRun(std::shared_ptr<const scenario::Model> model, std::uint64_t seed = 0)
      : episode(std::move(model), seed), session(episode.session()), environment(*episode.environment()) {}
  double step(std::optional<std::vector<double>> action = std::nullopt) { return episode.step(action); }
  /// The task's d: the gap between the robot's and the human's footprints.
  double distance() const {
    const auto& agents = session.state().agents;
    const auto& task = *session.model().task;
    return (agents[task.human].position - agents[task.robot].position).norm() - bodies();
  }
  /// The human's radius plus the robot's: centres this far apart are touching footprints.
  double bodies() const {
    const auto& task = *session.model().task;
    return session.model().agents[task.human].radius + session.model().agents[task.robot].radius;
  }
  sim::AgentId id(int agent) const { return session.agent_id(session.model().agents[agent].id); }
  episode::Episode episode;
  sim::Session& session;
  Environment& environment;
};

TEST(Rewards, DistanceIsPreviousMinusCurrent) {
  EXPECT_DOUBLE_EQ(distance_reward(3.0, 2.75), 0.25);
  EXPECT_DOUBLE_EQ(distance_reward(2.0, 2.5), -0.5);
  EXPECT_DOUBLE_EQ(distance_reward(1.0, 1.0), 0.0);
}

TEST(Rewards, HumanCollisionBelowTheDistanceOnly) {
  EXPECT_DOUBLE_EQ(human_collision_reward(0.05, 0.1, 20.0), -20.0);
  EXPECT_DOUBLE_EQ(human_collision_reward(0.1, 0.1, 20.0), 0.0);  // "less than 0.1 m"
  EXPECT_DOUBLE_EQ(human_collision_reward(2.0, 0.1, 20.0), 0.0);
}

TEST(Rewards, ObstacleCollisionsEachCostThePenalty) {
  EXPECT_DOUBLE_EQ(obstacle_collision_reward(0, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(obstacle_collision_reward(1, 0.5), -0.5);
  EXPECT_DOUBLE_EQ(obstacle_collision_reward(3, 0.5), -1.5);
}

TEST(Rewards, ProximityFallsLinearlyToZeroAtTheRange) {
  EXPECT_DOUBLE_EQ(proximity_reward(0.0, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(proximity_reward(0.1, 0.5), 0.8);
  EXPECT_DOUBLE_EQ(proximity_reward(0.25, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(proximity_reward(0.5, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(proximity_reward(1.7, 0.5), 0.0);
}

TEST(Rewards, LiftIsTheHeightGained) {
  EXPECT_DOUBLE_EQ(lift_reward(0.55, 0.45), 0.55 - 0.45);
  EXPECT_DOUBLE_EQ(lift_reward(0.40, 0.45), 0.40 - 0.45);
}

TEST(Rewards, MirrorScoresTheSameSideOnly) {
  EXPECT_EQ(mirror_reward(Side::left, Side::left), 1.0);
  EXPECT_EQ(mirror_reward(Side::right, Side::right), 1.0);
  EXPECT_EQ(mirror_reward(Side::right, Side::left), 0.0);
  EXPECT_EQ(mirror_reward(Side::none, Side::left), 0.0);
  EXPECT_EQ(mirror_reward(Side::none, Side::none), 0.0);
}

TEST(TaskDefaults, AreTheSeedsSettings) {
  const auto approach = bundled("approach_human");
  ASSERT_TRUE(approach && approach->task);
  EXPECT_EQ(approach->task->frame_skip, 10);
  EXPECT_EQ(approach->task->max_episode_length, 1536);
  EXPECT_DOUBLE_EQ(approach->dt, 1.0 / 60.0);
  EXPECT_DOUBLE_EQ(approach->time_limit, 1536.0 / 60.0);
  EXPECT_DOUBLE_EQ(approach->task->reach_distance, 0.3);
  EXPECT_DOUBLE_EQ(approach->task->collision_distance, 0.1);
  EXPECT_DOUBLE_EQ(approach->task->collision_penalty, 20.0);
  EXPECT_EQ(approach->task->spawn_min, core::Vec2(-5, -5));
  EXPECT_EQ(approach->task->spawn_max, core::Vec2(5, 5));

  const auto follow = bundled("follow_human");
  ASSERT_TRUE(follow && follow->task);
  ASSERT_EQ(follow->task->walking_styles.size(), 3u);
  EXPECT_EQ(follow->task->walking_styles[0].name, "slow");
  EXPECT_DOUBLE_EQ(follow->task->walking_styles[0].speed, 0.5);
  EXPECT_DOUBLE_EQ(follow->task->walking_styles[1].speed, 1.0);
  EXPECT_DOUBLE_EQ(follow->task->walking_styles[2].speed, 1.4);
  EXPECT_DOUBLE_EQ(follow->task->lead_distance, 1.0);

  const auto apartment = bundled("approach_human_apartment");
  ASSERT_TRUE(apartment && apartment->task);
  EXPECT_EQ(apartment->task->penalised.size(), 18u) << "table 4.1 has 18 rows";
  EXPECT_DOUBLE_EQ(apartment->task->obstacle_penalty, 0.5);

  const auto pick = bundled("pick_and_place");
  ASSERT_TRUE(pick && pick->task);
  EXPECT_EQ(pick->task->frame_skip, 128);
  EXPECT_EQ(pick->task->gripper_frames, 8);
  EXPECT_EQ(pick->task->max_episode_length, 256);
  EXPECT_EQ(pick->task->penalised.size(), 16u) << "table 4.2 lists 16 objects";
  EXPECT_DOUBLE_EQ(pick->task->reward_range, 0.5);
  EXPECT_DOUBLE_EQ(pick->task->place_weight, 2.0);

  const auto mirror = bundled("mirror_gesture");
  ASSERT_TRUE(mirror && mirror->task);
  EXPECT_EQ(mirror->task->frame_skip, 10);
  EXPECT_EQ(mirror->task->max_episode_length, 256);
  EXPECT_DOUBLE_EQ(mirror->task->human_distance, 2.0);
  EXPECT_DOUBLE_EQ(mirror->task->pointing_reach, 0.3);
  EXPECT_EQ(mirror->task->camera, "head_rgbd");
  EXPECT_EQ(mirror->task->image_width, 256);
  EXPECT_EQ(mirror->task->image_height, 256);
}

TEST(TaskSettings, EveryOneCanBeOverridden) {
  const auto model = bundled("approach_human", {{"task", {{"frame_skip", 1}, {"max_episode_length", 600}, {"reach_distance", 0.5},
                                                          {"spawn", {{"min", {1, 1}}, {"max", {2, 2}}}}}}});
  ASSERT_TRUE(model);
  EXPECT_EQ(model->task->frame_skip, 1);
  EXPECT_DOUBLE_EQ(model->time_limit, 10.0);
  TaskRun run(model, 4);
  const core::Vec2 human = run.session.state().agents[model->task->human].position;
  EXPECT_TRUE(human.x() >= 1 && human.x() <= 2 && human.y() >= 1 && human.y() <= 2) << human.transpose();
  run.step(std::vector<double>{0.0, 0.0});
  EXPECT_EQ(run.session.state().tick, 1) << "frame skip 1: one tick per step";
}

TEST(TaskSettings, WrongOnesAreRefusedWithTheirPointer) {
  const auto errors = [](const json& task, const json& extra = json::object()) {
    json document = testing::room_scenario(json{{"humans", {{{"id", "ana"}, {"start", {{"x", 2}, {"y", 2}}}}}},
                                                {"robots", {{{"id", "robot"}, {"model", "hsr"}, {"start", {{"x", 8}, {"y", 2}}}}}}});
    document.erase("time_limit");
    document["task"] = task;
    document.merge_patch(extra);
    std::vector<std::string> lines;
    for (const auto& e : scenario::load_scenario(document, {}).errors) lines.push_back(e.pointer + ": " + e.message);
    return lines;
  };
  const auto has = [](const std::vector<std::string>& lines, const std::string& pointer) {
    return std::any_of(lines.begin(), lines.end(), [&](const std::string& line) { return line.starts_with(pointer + ": "); });
  };
  EXPECT_TRUE(errors({{"name", "approach_human"}}).empty());
  EXPECT_TRUE(has(errors({{"name", "fly_to_the_moon"}}), "/task/name"));
  EXPECT_TRUE(has(errors({{"name", "approach_human"}}, {{"time_limit", 30}}), "/time_limit"));
  EXPECT_TRUE(has(errors({{"name", "approach_human"}, {"penalised", {"table", "piano"}}}), "/task/penalised/1"));
  EXPECT_TRUE(has(errors({{"name", "approach_human"}, {"human", "zoe"}}), "/task/human"));
  EXPECT_TRUE(has(errors({{"name", "approach_human"}, {"frame_skip", 0}}), "/task/frame_skip"));
  EXPECT_TRUE(has(errors({{"name", "approach_human"}, {"spawn", {{"min", {3, 3}}, {"max", {1, 1}}}}}), "/task/spawn"));
  EXPECT_TRUE(has(errors({{"name", "pick_and_place"}}), "/task"));
  EXPECT_TRUE(has(errors({{"name", "pick_and_place"}, {"object", "mug"}, {"target", {{"x", 1}, {"y", 1}}}}), "/task/object"));
  EXPECT_TRUE(has(errors({{"name", "pick_and_place"}, {"frame_skip", 4}, {"gripper_frames", 8}}), "/task/gripper_frames"));
  EXPECT_TRUE(has(errors({{"name", "mirror_gesture"}, {"camera", "tail_cam"}}), "/task/camera"));
  EXPECT_TRUE(has(errors({{"name", "follow_human"}, {"walking_styles", json::object()}}), "/task/walking_styles"));
  // A robot without a model has neither wheels nor an arm.
  EXPECT_TRUE(has(errors({{"name", "approach_human"}}, {{"robots", {{{"id", "robot"}, {"start", {{"x", 8}, {"y", 2}}}}}}}), "/task/robot"));
}

TEST(ApproachHuman, PlacesTheHumanFromTheSeedOnFreeFloorInTheSpawnArea) {
  const auto model = bundled("approach_human");
  std::set<std::pair<double, double>> places;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    TaskRun run(model, seed), again(model, seed);
    const core::Vec2 at = run.session.state().agents[model->task->human].position;
    EXPECT_EQ(at, again.session.state().agents[model->task->human].position) << "same seed, same place";
    EXPECT_TRUE(at.cwiseAbs().maxCoeff() <= 5.0) << at.transpose();
    EXPECT_FALSE(model->grid.blocked(at));
    EXPECT_GT(run.distance(), 0.0) << "clear of the robot";
    places.insert({at.x(), at.y()});
  }
  EXPECT_EQ(places.size(), 20u);
  EXPECT_EQ(TaskRun(model, 0).session.state().agents[model->task->robot].position, core::Vec2(0, 0)) << "the robot at the origin";
}

TEST(ApproachHuman, RewardsTheDistanceGainedAndEndsWithin30Centimetres) {
  const auto model = bundled("approach_human");
  TaskRun run(model, 3);
  const int robot = model->task->robot, human = model->task->human;
  const double start = run.distance();
  const auto& agents = run.session.state().agents;
  // Face the human, then drive at full speed: each 10-tick step's reward is the distance gained.
  const core::Vec2 to = agents[human].position - agents[robot].position;
  run.session.place_agent(run.id(robot), {0, 0, std::atan2(to.y(), to.x())});
  double before = start;
  for (int s = 0; s < 3; ++s) {
    const double reward = run.step(std::vector<double>{0.3, 0.0});
    EXPECT_NEAR(reward, before - run.distance(), 1e-12);
    EXPECT_GT(reward, 0.0);
    before = run.distance();
  }
  EXPECT_EQ(run.session.state().tick, 30);
  EXPECT_FALSE(run.environment.terminated(run.session));
  // Put the robot 0.25 m from the human, facing away, and stop: the step gains before − the distance
  // it ends at (the base still coasts a little), and within 0.3 m the episode is done.
  const core::Vec2 near = agents[human].position - to.normalized() * (0.25 + run.bodies());
  run.session.place_agent(run.id(robot), {near.x(), near.y(), std::atan2(-to.y(), -to.x())});
  const double reward = run.step(std::vector<double>{0.0, 0.0});
  EXPECT_NEAR(run.distance(), 0.25, 0.03);
  EXPECT_NEAR(reward, before - run.distance(), 1e-12);
  EXPECT_TRUE(run.environment.terminated(run.session));
  EXPECT_EQ(run.step(std::vector<double>{0.2, 0.0}), 0.0) << "nothing happens once terminated";
  EXPECT_EQ(run.session.state().tick, 40);
}

TEST(ApproachHuman, ClosestThan10CentimetresCosts20) {
  const auto model = bundled("approach_human");
  TaskRun run(model, 5);
  const core::Vec2 human = run.session.state().agents[model->task->human].position;
  const double before = run.distance();
  run.session.place_agent(run.id(model->task->robot), {human.x() + 0.05 + run.bodies(), human.y(), 0});
  const double reward = run.step(std::vector<double>{0.0, 0.0});
  EXPECT_LT(run.distance(), 0.1);
  EXPECT_NEAR(reward, before - run.distance() - 20.0, 1e-12);
  EXPECT_DOUBLE_EQ(run.environment.info(run.session)["collision_human"].get<double>(), -20.0);
}

TEST(ApproachHuman, RunsOutAfter1536TicksAndRefusesWrongActions) {
  const auto model = bundled("approach_human");
  TaskRun run(model, 1);
  EXPECT_THROW(run.step(std::vector<double>{0.1}), core::Error);
  try {
    run.step(std::vector<double>{0.1, std::nan("")});
    ADD_FAILURE() << "a NaN was taken";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.details().value("pointer", ""), "/action/1");
  }
  EXPECT_EQ(run.session.state().tick, 0) << "a refused action runs no tick";
  int steps = 0;
  while (!run.session.state().finished) {
    run.step(std::vector<double>{0.0, 0.0});
    ++steps;
  }
  EXPECT_EQ(run.session.state().tick, 1536);
  EXPECT_EQ(run.session.state().termination, sim::Termination::timeout);
  EXPECT_EQ(steps, 154) << "153 whole steps of 10 ticks and a last one cut at the limit";
}

TEST(FollowHuman, TheHumanWalksInAStyleFromTheSetAndTheEpisodeRunsToItsEnd) {
  const auto model = bundled("follow_human");
  std::set<std::string> styles;
  for (std::uint64_t seed = 0; seed < 12; ++seed) {
    TaskRun run(model, seed);
    const int human = model->task->human;
    const core::Vec2 start = run.session.state().agents[human].position;
    EXPECT_NEAR((start - core::Vec2(0, 0)).norm(), 1.0, 1e-9) << "1 m ahead of the robot";
    double gained = 0.0;
    for (int s = 0; s < 20; ++s) {
      const double before = run.distance();
      gained = run.step(std::vector<double>{0.0, 0.0});
      // She may pass the standing robot closer than 0.1 m: that step also costs the collision's 20.
      EXPECT_NEAR(gained, before - run.distance() + run.environment.info(run.session)["collision_human"].get<double>(), 1e-12);
    }
    const std::string style = run.environment.info(run.session)["walking_style"];
    styles.insert(style);
    const double speed = run.session.state().agents[human].preferred_speed;
    EXPECT_TRUE(std::any_of(model->task->walking_styles.begin(), model->task->walking_styles.end(),
                            [&](const scenario::WalkingStyle& s) { return s.name == style && s.speed == speed; }));
    EXPECT_GT((run.session.state().agents[human].position - start).norm(), 0.5) << "she walks";
    EXPECT_FALSE(run.environment.terminated(run.session));
  }
  EXPECT_EQ(styles.size(), 3u) << "every style is drawn over 12 seeds";
}

TEST(FollowHuman, NeverTerminatesEvenWhenClose) {
  const auto model = bundled("follow_human");
  TaskRun run(model, 2);
  const core::Vec2 human = run.session.state().agents[model->task->human].position;
  run.session.place_agent(run.id(model->task->robot), {human.x() - 0.2, human.y(), 0});
  run.step(std::vector<double>{0.0, 0.0});
  EXPECT_FALSE(run.environment.terminated(run.session));
}

TEST(ApproachHumanApartment, EachFurnitureTouchedCostsHalfAPoint) {
  const auto model = bundled("approach_human_apartment");
  TaskRun run(model, 0);
  // Back off the dining table's east edge (x = −1) and drive into it.
  run.session.place_agent(run.id(model->task->robot), {-0.65, -0.6, std::numbers::pi});
  std::vector<std::string> touched;
  double reward = 0.0, before = run.distance();
  for (int s = 0; s < 20 && touched.empty(); ++s) {
    before = run.distance();
    reward = run.step(std::vector<double>{0.22, 0.0});
    touched = run.environment.info(run.session)["touched"].get<std::vector<std::string>>();
  }
  ASSERT_FALSE(touched.empty()) << "the robot reached the table";
  EXPECT_NE(std::find(touched.begin(), touched.end(), "table"), touched.end());
  EXPECT_NEAR(reward, before - run.distance() - 0.5 * touched.size(), 1e-9);
}

TEST(ApproachHumanApartment, TheHumanStandsOnFreeFloorInsideTheApartment) {
  const auto model = bundled("approach_human_apartment");
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    TaskRun run(model, seed);
    const core::Vec2 at = run.session.state().agents[model->task->human].position;
    EXPECT_GE(model->field.distance(model->grid, at), model->agents[model->task->human].radius) << at.transpose();
    EXPECT_TRUE(std::abs(at.x()) < 4 && std::abs(at.y()) < 3) << at.transpose();
  }
}

/// The scripted grasp of docs/benchmark.md: arm targets [lift, flex, roll, wrist flex, wrist roll, base roll].
const std::vector<double> kGrasp{0.141, -1.5708, 0, 0, 0, -0.1186}, kOnTarget{0.151, -1.5708, 0, 0, 0, 1.5708 - 0.1186};

std::vector<double> arm(const std::vector<double>& targets) {
  std::vector<double> action{-1, 0};
  action.insert(action.end(), targets.begin(), targets.end());
  return action;
}
std::vector<double> gripper(bool close) { return {1, close ? 1.0 : -1.0, 0, 0, 0, 0, 0, 0}; }

TEST(PickAndPlace, RewardIsTheSumOfItsTermsAndStepsLastTheirFrames) {
  const auto model = bundled("pick_and_place");
  TaskRun run(model, 0);
  const double reward = run.step(gripper(false));
  EXPECT_EQ(run.session.state().tick, 8) << "a gripper step: 8 ticks";
  const json terms = run.environment.info(run.session);
  // At the start the open hand is 16 cm above the cup, and the cup about 1 m from the target.
  EXPECT_NEAR(terms["gripper_object_distance"].get<double>(), 0.16, 0.02);
  EXPECT_NEAR(terms["gripper_object"].get<double>(), 1 - terms["gripper_object_distance"].get<double>() / 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(terms["object_target"].get<double>(), 0.0);
  EXPECT_LT(std::abs(terms["lifting"].get<double>()), 0.01);
  EXPECT_NEAR(reward, terms["gripper_object"].get<double>() + terms["object_target"].get<double>() + terms["lifting"].get<double>() +
                          terms["collision_obstacle"].get<double>(), 1e-12);
  run.step(arm(kGrasp));
  EXPECT_EQ(run.session.state().tick, 128) << "an arm step: 120 ticks";
  EXPECT_LT(run.environment.info(run.session)["gripper_object_distance"].get<double>(), 0.03) << "the cup between the fingers";
  run.step(arm(kGrasp));
  run.step(gripper(true));
  EXPECT_EQ(run.session.state().tick, 256);
  EXPECT_EQ(run.session.state().termination, sim::Termination::timeout) << "256 ticks per episode";
}

// The seed's schedule (§5.3.4): approach 120 ticks, grasp 8, carry 120, and 8 to let go — 256.
TEST(PickAndPlace, TheScriptedGraspPlacesTheCupWithinTheSeedsEpisode) {
  const auto model = bundled("pick_and_place");
  for (std::uint64_t seed = 0; seed < 5; ++seed) {
    TaskRun run(model, seed);
    run.step(arm(kGrasp));
    run.step(gripper(true));
    EXPECT_TRUE(run.environment.info(run.session)["held"].get<bool>()) << "closed on the cup in 8 ticks, seed " << seed;
    run.step(arm(kOnTarget));
    EXPECT_TRUE(run.environment.info(run.session)["held"].get<bool>()) << "carried without slipping, seed " << seed;
    EXPECT_GT(run.environment.info(run.session)["lifting"].get<double>(), 0.005) << "off the table";
    const double reward = run.step(gripper(false));
    const json terms = run.environment.info(run.session);
    EXPECT_EQ(run.session.state().tick, 256);
    EXPECT_FALSE(terms["held"].get<bool>());
    EXPECT_LT(terms["object_target_distance"].get<double>(), 0.03) << "standing on the target, seed " << seed;
    EXPECT_GT(terms["object_target"].get<double>(), 1.85) << "2 × (1 − d / 0.5)";
    EXPECT_TRUE(terms["touched"].empty()) << "nothing on the tables was hit";
    EXPECT_GT(reward, 2.0);
  }
}

TEST(MirrorGesture, TheHumanPointsToASideDrawnFromTheSeedAndFacesTheRobot) {
  const auto model = bundled("mirror_gesture");
  std::set<std::string> sides;
  for (std::uint64_t seed = 0; seed < 10; ++seed) {
    TaskRun run(model, seed);
    run.step(std::vector<double>(6, 0.0));
    const auto& person = run.session.state().agents[model->task->human];
    EXPECT_NEAR((person.position - core::Vec2(2, 0)).norm(), 0.0, 1e-9);
    EXPECT_NEAR(std::abs(core::wrap_angle(person.heading)), std::numbers::pi, 1e-6);
    ASSERT_NE(person.animation.motion, nullptr);
    const std::string side = run.environment.info(run.session)["human_points"];
    EXPECT_EQ(person.animation.motion->name(), "point_" + side);
    sides.insert(side);
  }
  EXPECT_EQ(sides, (std::set<std::string>{"left", "right"}));
}

TEST(MirrorGesture, ScoresOneWhenTheHandPointsToHerSide) {
  const auto model = bundled("mirror_gesture");
  for (std::uint64_t seed = 0; seed < 6; ++seed) {
    TaskRun run(model, seed);
    // The arm stretched forward, turned left by the base roll joint: the hand 0.7 m to the robot's
    // left, which is her right as she faces the robot.
    const std::vector<double> robot_left{0.2, -1.5708, 0, 0, 0, 1.5708};
    double reward = 0.0;
    for (int s = 0; s < 12; ++s) reward = run.step(robot_left);
    const json info = run.environment.info(run.session);
    EXPECT_EQ(info["robot_points"], "right");
    EXPECT_EQ(reward, info["human_points"] == "right" ? 1.0 : 0.0);
  }
  TaskRun rest(model, 0);
  EXPECT_EQ(rest.step(std::vector<double>(6, 0.0)), 0.0) << "the arm hanging down points nowhere";
  EXPECT_EQ(rest.environment.info(rest.session)["robot_points"], "none");
}

TEST(MirrorGesture, ObservesTheHeadCameraAsAnImage) {
  const auto model = bundled("mirror_gesture");
  TaskRun run(model, 0);
  ASSERT_TRUE(run.environment.image());
  EXPECT_EQ(run.environment.image()->camera, "robot.head_rgbd");
  EXPECT_EQ(run.environment.observation_space().shape, (std::vector<int>{256, 256, 5}));
  EXPECT_EQ(run.environment.observation_space().dtype, "float32");
  EXPECT_TRUE(run.environment.observe(run.session).empty());
  EXPECT_EQ(run.environment.action_space().shape, std::vector<int>{6});
}

TEST(Tasks, SameSeedAndActionsGiveTheSameEpisode) {
  for (const char* name : {"approach_human", "follow_human", "approach_human_apartment", "pick_and_place", "mirror_gesture"}) {
    const auto model = bundled(name);
    TaskRun a(model, 7), b(model, 7);
    const std::size_t size = static_cast<std::size_t>(a.environment.action_space().shape[0]);
    for (int s = 0; s < 3; ++s) {
      std::vector<double> action(size);
      for (std::size_t i = 0; i < size; ++i) action[i] = std::sin(1.0 + s + i);
      EXPECT_EQ(a.step(action), b.step(action)) << name;
    }
    EXPECT_EQ(a.session.state_hash(), b.session.state_hash()) << name;
    EXPECT_EQ(a.environment.observe(a.session), b.environment.observe(b.session)) << name;
  }
}

}  // namespace
}  // namespace hrisim::tasks
