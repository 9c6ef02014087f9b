// Episode metrics on small hand-built recordings whose values are worked out by hand here.
#include "metrics/episode_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "metrics/definitions.hpp"

namespace hrisim::metrics {
namespace {

constexpr double kDt = 0.1;

Body disc(int agent, double x, double y, double vx = 0.0, double vy = 0.0, double heading = 0.0, double radius = 0.3) {
  return {agent, {x, y}, {vx, vy}, heading, radius, false};
}

/// A step with the robot and the people; obstacles far away unless said otherwise.
Sample sample(std::int64_t tick, Body robot, std::vector<Body> humans, double obstacle_distance = 10.0) {
  Sample s;
  s.tick = tick;
  s.robot = robot;
  s.humans = std::move(humans);
  s.obstacle_distance = obstacle_distance;
  return s;
}

Recording with_robot() {
  Recording r;
  r.dt = kDt;
  r.has_robot = true;
  r.termination = "timeout";
  return r;
}

const MetricValue& metric(const std::vector<MetricValue>& values, const std::string& key) {
  for (const MetricValue& value : values) {
    if (value.key == key) return value;
  }
  throw std::runtime_error("no metric " + key);
}
double value(const std::vector<MetricValue>& values, const std::string& key) {
  const MetricValue& m = metric(values, key);
  if (!m.value) throw std::runtime_error(key + " is null: " + m.null_reason);
  return *m.value;
}

TEST(EpisodeMetrics, EveryDefinitionGetsAValueOrAReasonInOrder) {
  Recording r = with_robot();
  r.samples.push_back(sample(0, disc(0, 0, 0), {}));
  const auto values = compute_episode_metrics(r);
  ASSERT_EQ(values.size(), definitions().size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    EXPECT_EQ(values[i].key, definitions()[i].key);
    EXPECT_NE(values[i].value.has_value(), !values[i].null_reason.empty()) << values[i].key;
    EXPECT_TRUE(!values[i].value || std::isfinite(*values[i].value)) << values[i].key;
  }
}

TEST(EpisodeMetrics, HeadOnApproach) {
  // Robot from x = 0 and a person from x = 10.05 walk towards each other at 1 m/s for 3 s (31 samples).
  // Surface distance 10.05 − 0.6 − 2t = 9.45 − 2t: 3.45 m at the end, under 3.6 m only in the last sample.
  Recording r = with_robot();
  for (int i = 0; i <= 30; ++i) {
    const double t = i * kDt;
    r.samples.push_back(sample(i, disc(0, t, 0, 1.0, 0), {disc(1, 10.05 - t, 0, -1.0, 0, M_PI)}));
  }
  const auto values = compute_episode_metrics(r);
  EXPECT_NEAR(value(values, "minimum_distance_to_people"), 3.45, 1e-12);
  // Mean of 9.45 − 2t over t = 0 … 3: 9.45 − 3.
  EXPECT_NEAR(value(values, "avg_distance_to_closest_person"), 6.45, 1e-12);
  EXPECT_NEAR(value(values, "social_space_intrusions"), 100.0 / 31, 1e-12);
  EXPECT_EQ(value(values, "personal_space_intrusions"), 0.0);
  EXPECT_EQ(value(values, "intimate_space_intrusions"), 0.0);
  // Closing at 2 m/s with 3.45 m to go at the last sample.
  EXPECT_NEAR(value(values, "min_time_to_collision"), 1.725, 1e-12);
  EXPECT_NEAR(value(values, "path_length"), 3.0, 1e-12);
  EXPECT_NEAR(value(values, "avg_robot_linear_speed"), 1.0, 1e-12);
  EXPECT_EQ(value(values, "max_acceleration"), 0.0);
  EXPECT_EQ(value(values, "time_not_moving"), 0.0);
  EXPECT_EQ(value(values, "collisions"), 0.0);
  EXPECT_EQ(value(values, "episode_length"), 30.0);
}

TEST(EpisodeMetrics, APersonCrossingInFront) {
  // The robot drives along +x at 1 m/s from (0, 0); a person walks along +y at 1 m/s from (3, −3):
  // they would meet at (3, 0) at t = 3 s, but the episode ends at t = 2 s. At time t the centres are
  // (3 − t, −3 + t) apart: √2·(3 − t), so the closest surface distance is at the end, √2 − 0.6.
  Recording r = with_robot();
  for (int i = 0; i <= 20; ++i) {
    const double t = i * kDt;
    r.samples.push_back(sample(i, disc(0, t, 0, 1, 0), {disc(1, 3, -3 + t, 0, 1, M_PI / 2)}));
  }
  const auto values = compute_episode_metrics(r);
  EXPECT_NEAR(value(values, "minimum_distance_to_people"), std::sqrt(2.0) - 0.6, 1e-12);
  // Relative velocity (−1, 1) closes the gap √2·(3 − t) at √2 m/s, touching 0.6 m earlier:
  // at the last step (3 − 2) − 0.6/√2 s.
  EXPECT_NEAR(value(values, "min_time_to_collision"), 1.0 - 0.6 / std::sqrt(2.0), 1e-12);
  EXPECT_EQ(value(values, "collisions"), 0.0);
  EXPECT_GT(value(values, "danger_fear_cost"), 0.0) << "closing in all the time";
  EXPECT_EQ(value(values, "danger_panic_cost"), 0.0) << "on a collision course, not one that misses";
  EXPECT_EQ(metric(values, "episode_reward").null_reason, "the scenario defines no benchmark task");
}

TEST(EpisodeMetrics, AContactLastingSeveralStepsCountsOnce) {
  // A still robot; the person touches it (surface distance 0) at steps 2–6, leaves, comes back at 9–10.
  Recording r = with_robot();
  for (int i = 0; i <= 12; ++i) {
    const bool touching = (i >= 2 && i <= 6) || (i >= 9 && i <= 10);
    const bool arriving = i == 2 || i == 9;
    r.samples.push_back(sample(i, disc(0, 0, 0), {disc(1, touching ? 0.6 : 2.0, 0, arriving ? -0.5 : 0.0, 0)}));
  }
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(value(values, "collisions"), 2.0);
  EXPECT_NEAR(value(values, "contact_time"), 7 * kDt, 1e-12);
  EXPECT_EQ(value(values, "person_on_robot_collisions"), 2.0) << "the robot stood still";
  EXPECT_EQ(value(values, "robot_on_person_collisions"), 0.0);
  EXPECT_EQ(value(values, "minimum_distance_to_people"), 0.0);
  EXPECT_NEAR(value(values, "intimate_space_intrusions"), 100.0 * 7 / 13, 1e-12);
  EXPECT_NEAR(value(values, "discomfort_frequency"), 100.0 * 7 / 13, 1e-12);
  EXPECT_EQ(value(values, "min_time_to_collision"), 0.0);
}

TEST(EpisodeMetrics, PhysicsContactCountsEvenAtADistanceAndBlameFollowsMotion) {
  // The robot drives into a still person; the physics reports contact at 5 cm surface distance.
  Recording r = with_robot();
  for (int i = 0; i <= 4; ++i) {
    Body person = disc(1, 1.0, 0);
    person.touching_robot = i >= 3;
    r.samples.push_back(sample(i, disc(0, 0.1 * i, 0, 1.0, 0), {person}));
  }
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(value(values, "collisions"), 1.0);
  EXPECT_EQ(value(values, "robot_on_person_collisions"), 1.0);
  EXPECT_EQ(value(values, "person_on_robot_collisions"), 0.0);
}

TEST(EpisodeMetrics, ARobotThatNeverMoves) {
  Recording r = with_robot();
  for (int i = 0; i < 20; ++i) r.samples.push_back(sample(i, disc(0, 1, 1, 0, 0, 0.5), {disc(1, 5, 1)}));
  const auto values = compute_episode_metrics(r);
  EXPECT_NEAR(value(values, "time_not_moving"), 20 * kDt, 1e-12);
  EXPECT_EQ(value(values, "path_length"), 0.0);
  EXPECT_EQ(value(values, "avg_robot_linear_speed"), 0.0);
  EXPECT_EQ(value(values, "avg_robot_angular_speed"), 0.0);
  EXPECT_EQ(value(values, "cumulative_heading_changes"), 0.0);
  EXPECT_FALSE(metric(values, "min_time_to_collision").value) << "nobody moves: they never meet";
}

TEST(EpisodeMetrics, NoHumansAtAll) {
  Recording r = with_robot();
  for (int i = 0; i < 5; ++i) r.samples.push_back(sample(i, disc(0, 0.1 * i, 0, 1, 0), {}));
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(metric(values, "minimum_distance_to_people").null_reason, "no human was present");
  EXPECT_FALSE(metric(values, "avg_distance_to_closest_person").value);
  EXPECT_EQ(value(values, "social_space_intrusions"), 0.0);
  EXPECT_EQ(value(values, "collisions"), 0.0);
  EXPECT_EQ(metric(values, "success").null_reason,
            "the robot has no navigation goal, no search and no part in the choreography: nothing it was asked to do can succeed");
}

TEST(EpisodeMetrics, ARobotWithoutGoalOrPartHasNoSuccessWhenTheChoreographyCompletes) {
  // The audit's wrong answer: a controller swap had dropped the robot's goal; the people's choreography
  // completed and the robot, standing still, "succeeded".
  Recording r = with_robot();
  r.has_choreography = true;
  r.choreography_completed = true;
  for (int i = 0; i <= 50; ++i) r.samples.push_back(sample(i, disc(0, 0.001 * i, 0), {disc(1, 5, 1)}));
  const auto values = compute_episode_metrics(r);
  EXPECT_FALSE(metric(values, "success").value);
  EXPECT_NE(metric(values, "success").null_reason.find("no navigation goal"), std::string::npos);
  for (const char* goal_metric : {"time_to_goal", "path_efficiency", "minimum_distance_to_target", "final_distance_to_target", "failure_to_progress", "spl"}) {
    EXPECT_EQ(metric(values, goal_metric).null_reason, "the robot has no navigation goal") << goal_metric;
  }
  EXPECT_EQ(value(values, "choreography_completed"), 1.0) << "the choreography's own metric still says it completed";
}

TEST(EpisodeMetrics, ABenchmarkTasksGoalConditionIsItsSuccess) {
  // approach_human ends at its goal condition (termination "goal"); follow_human runs its length.
  Recording r = with_robot();
  for (int i = 0; i < 5; ++i) r.samples.push_back(sample(i, disc(0, 0.1 * i, 0, 1, 0), {disc(1, 5, 0)}));
  r.task_goal_condition = true;
  r.termination = "goal";
  EXPECT_EQ(value(compute_episode_metrics(r), "success"), 1.0);
  r.termination = "timeout";
  EXPECT_EQ(value(compute_episode_metrics(r), "success"), 0.0);
  r.task_goal_condition = false;
  EXPECT_EQ(metric(compute_episode_metrics(r), "success").null_reason, "the benchmark task has no goal condition: its reward measures the episode");
}

TEST(EpisodeMetrics, ASingleStep) {
  Recording r = with_robot();
  r.samples.push_back(sample(0, disc(0, 0, 0, 0.5, 0), {disc(1, 2, 0)}));
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(value(values, "episode_length"), 0.0);
  EXPECT_EQ(value(values, "path_length"), 0.0);
  EXPECT_EQ(value(values, "max_robot_linear_speed"), 0.5);
  EXPECT_EQ(metric(values, "avg_acceleration").null_reason, "an acceleration needs two steps");
  EXPECT_EQ(metric(values, "max_jerk").null_reason, "a jerk needs three steps");
  EXPECT_FALSE(metric(values, "avg_robot_angular_speed").value);
  EXPECT_NEAR(value(values, "minimum_distance_to_people"), 1.4, 1e-12);
}

TEST(EpisodeMetrics, ReachingAGoal) {
  // Straight to a goal 5 m away at 1 m/s with radius 0.5: inside from t = 4.5 s.
  Recording r = with_robot();
  r.goal = core::Vec2(5, 0);
  r.goal_radius = 0.5;
  for (int i = 0; i <= 50; ++i) r.samples.push_back(sample(i, disc(0, 0.1 * i, 0, 1, 0), {}));
  const auto values = compute_episode_metrics(r);
  EXPECT_NEAR(value(values, "time_to_goal"), 4.5, 1e-12);
  EXPECT_NEAR(value(values, "path_efficiency"), 1.0, 1e-12);
  EXPECT_NEAR(value(values, "final_distance_to_target"), 0.0, 1e-12);
  EXPECT_EQ(value(values, "success"), 1.0);
  EXPECT_EQ(value(values, "failure_to_progress"), 0.0);
}

TEST(EpisodeMetrics, PathEfficiencyToTheGoalsCircleAndUpToReachingIt) {
  // Start (0, 0), goal (4, 0) with radius 1: the shortest way is 3 m, to the circle. The robot drives
  // (0,0) → (0,2) → (3,2) → (3,0.1), still 1.005 m from the goal → (3.2,0), inside; then it wanders
  // on, which path_efficiency ignores. Path up to the goal: 2 + 3 + 1.9 + √0.05.
  Recording r = with_robot();
  r.goal = core::Vec2(4, 0);
  r.goal_radius = 1.0;
  const double points[][2] = {{0, 0}, {0, 2}, {3, 2}, {3, 0.1}, {3.2, 0}, {3.2, 5}, {-3, 5}};
  for (int i = 0; i < 7; ++i) r.samples.push_back(sample(i, disc(0, points[i][0], points[i][1]), {}));
  const auto values = compute_episode_metrics(r);
  EXPECT_NEAR(value(values, "path_efficiency"), 3.0 / (6.9 + std::sqrt(0.05)), 1e-12);
  EXPECT_NEAR(value(values, "time_to_goal"), 4 * kDt, 1e-12);
}

TEST(EpisodeMetrics, NotReachingAGoalWhileStuck) {
  // 20 s stuck 3 m short of the goal: unsuccessful and no progress over the last 10 s.
  Recording r = with_robot();
  r.goal = core::Vec2(5, 0);
  r.goal_radius = 0.5;
  for (int i = 0; i <= 200; ++i) r.samples.push_back(sample(i, disc(0, 2, 0), {}));
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(value(values, "success"), 0.0);
  EXPECT_EQ(value(values, "failure_to_progress"), 1.0);
  EXPECT_FALSE(metric(values, "time_to_goal").value);
  EXPECT_FALSE(metric(values, "path_efficiency").value);
  EXPECT_NEAR(value(values, "minimum_distance_to_target"), 3.0, 1e-12);
}

TEST(EpisodeMetrics, HeadingChangesWrapAroundPi) {
  // 0 → 0.5 → −0.5 → 3.0 → −3.0: changes 0.5, 1.0, 3.5 wrapped to 2π − 3.5, 6 wrapped to 2π − 6.
  Recording r = with_robot();
  const double headings[] = {0.0, 0.5, -0.5, 3.0, -3.0};
  for (int i = 0; i < 5; ++i) r.samples.push_back(sample(i, disc(0, 0, 0, 0, 0, headings[i]), {}));
  const auto values = compute_episode_metrics(r);
  const double expected = 0.5 + 1.0 + (2 * M_PI - 3.5) + (2 * M_PI - 6.0);
  EXPECT_NEAR(value(values, "cumulative_heading_changes"), expected, 1e-12);
  EXPECT_NEAR(value(values, "avg_robot_angular_speed"), expected / 4 / kDt, 1e-9);
}

TEST(EpisodeMetrics, AccelerationAndJerkFromForwardSpeed) {
  // Forward speeds 0, 0.1, 0.3, 0.3 at dt 0.1: accelerations 1, 2, 0; jerks 10, −20.
  Recording r = with_robot();
  const double speeds[] = {0.0, 0.1, 0.3, 0.3};
  for (int i = 0; i < 4; ++i) r.samples.push_back(sample(i, disc(0, 0, 0, speeds[i], 0), {}));
  const auto values = compute_episode_metrics(r);
  EXPECT_NEAR(value(values, "avg_acceleration"), 1.0, 1e-9);
  EXPECT_NEAR(value(values, "max_acceleration"), 2.0, 1e-9);
  EXPECT_NEAR(value(values, "avg_jerk"), 15.0, 1e-9);
  EXPECT_NEAR(value(values, "max_jerk"), 20.0, 1e-9);
}

TEST(EpisodeMetrics, RequestsAndTheirLatency) {
  Recording r = with_robot();
  r.has_choreography = true;
  r.robot_in_choreography = true;
  r.choreography_completed = true;
  for (int i = 0; i <= 50; ++i) r.samples.push_back(sample(i, disc(0, 0, 0), {}));
  using Kind = RecordedEvent::Kind;
  r.events = {{10, Kind::request, 1}, {12, Kind::request, 2}, {30, Kind::request_dropped, 2},
              {40, Kind::request_accepted, 1}};
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(value(values, "requests_sent"), 2.0);
  EXPECT_EQ(value(values, "requests_accepted"), 1.0);
  EXPECT_EQ(value(values, "requests_dropped"), 1.0);
  EXPECT_NEAR(value(values, "request_latency"), 3.0, 1e-12);
  EXPECT_EQ(value(values, "choreography_completed"), 1.0);
  EXPECT_EQ(value(values, "success"), 1.0) << "choreography completed without a collision";
}

TEST(EpisodeMetrics, WithoutARobotOnlyEpisodeMetricsHaveValues) {
  Recording r;
  r.dt = kDt;
  for (int i = 0; i < 3; ++i) r.samples.push_back(sample(i, {}, {disc(1, i, 0)}));
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(value(values, "episode_length"), 2.0);
  EXPECT_EQ(metric(values, "collisions").null_reason, "the scenario has no robot");
  EXPECT_EQ(metric(values, "choreography_completed").null_reason, "the scenario has no choreography");
}

TEST(EpisodeMetrics, SplAndObstacleClearance) {
  // Straight to a goal 5 m away (path 5 m). With a 6 m shortest path on the map (the grid's corners):
  // SPL 6 / max(5, 6) = 1; with a 4 m one: 4 / 5 = 0.8.
  for (const auto& [shortest, expected] : {std::pair{6.0, 1.0}, std::pair{4.0, 0.8}}) {
    Recording r = with_robot();
    r.goal = core::Vec2(5, 0);
    r.goal_radius = 0.1;
    r.shortest_path_length = shortest;
    for (int i = 0; i <= 50; ++i) r.samples.push_back(sample(i, disc(0, 0.1 * i, 0, 1, 0), {}, 1.0 + 0.01 * i));
    const auto values = compute_episode_metrics(r);
    EXPECT_NEAR(value(values, "spl"), expected, 1e-12) << shortest;
    EXPECT_NEAR(value(values, "min_obstacle_clearance"), 1.0, 1e-12);
    EXPECT_NEAR(value(values, "avg_obstacle_clearance"), 1.25, 1e-12);
    // 10·exp(−d/0.2) summed over the steps times dt.
    double push = 0.0;
    for (int i = 0; i <= 50; ++i) push += 10.0 * std::exp(-(1.0 + 0.01 * i) / 0.2) * kDt;
    EXPECT_NEAR(value(values, "obstacle_force_on_robot"), push, 1e-12);
  }
  Recording failed = with_robot();
  failed.goal = core::Vec2(5, 0);
  failed.shortest_path_length = 5.0;
  failed.samples.push_back(sample(0, disc(0, 0, 0), {}));
  EXPECT_EQ(value(compute_episode_metrics(failed), "spl"), 0.0) << "no success, no credit";
  failed.shortest_path_length.reset();
  EXPECT_EQ(metric(compute_episode_metrics(failed), "spl").null_reason, "no collision-free path from the start to the goal on the map");
}

TEST(EpisodeMetrics, ObstacleContactsCountOncePerContact) {
  Recording r = with_robot();
  const std::vector<std::vector<std::string>> touched{{}, {"map"}, {"map"}, {"map", "cup"}, {}, {"cup"}};
  for (std::size_t i = 0; i < touched.size(); ++i) {
    Sample s = sample(static_cast<int>(i), disc(0, 0, 0), {});
    s.touched_obstacles = touched[i];
    r.samples.push_back(s);
  }
  EXPECT_EQ(value(compute_episode_metrics(r), "obstacle_collisions"), 3.0) << "the wall once, the cup twice";
}

TEST(EpisodeMetrics, GroupSpaceFromTheGroupsCentre) {
  // Two people at (3, 0) and (3, 1) facing the robot (heading π): centre (3, 0.5) + 1.5 m ahead =
  // (1.5, 0.5), 1.5811 m from the robot's centre, 1.2811 m from its surface: the social band.
  Recording r = with_robot();
  Sample s = sample(0, disc(0, 0, 0), {disc(1, 3, 0, 0, 0, M_PI), disc(2, 3, 1, 0, 0, M_PI)});
  s.groups = {{0, 1}};
  r.samples.push_back(s);
  r.samples.push_back(sample(1, disc(0, 0, 0), {disc(1, 3, 0, 0, 0, M_PI), disc(2, 3, 1, 0, 0, M_PI)}));  // the group broke up
  const auto values = compute_episode_metrics(r);
  EXPECT_EQ(value(values, "group_social_space_intrusions"), 50.0);
  EXPECT_EQ(value(values, "group_personal_space_intrusions"), 0.0);
  EXPECT_EQ(value(values, "group_intimate_space_intrusions"), 0.0);
}

TEST(EpisodeMetrics, DangerCostsOfFearAndPanic) {
  // The robot drives at 1 m/s straight at a still person 2 m ahead: fear |V|/|P| = 0.5, no panic
  // (on a collision course). A person at (2, 1): P·V = 2 > 0, sin θ = 1/√5, d⊥ = 1 > R = 0.6:
  // fear 1/√5, panic 1 / ((1 − 0.6)·(1/√5)) = √5 / 0.4.
  Recording r = with_robot();
  r.samples.push_back(sample(0, disc(0, 0, 0, 1, 0), {disc(1, 2, 0)}));
  r.samples.push_back(sample(1, disc(0, 0, 0, 1, 0), {disc(1, 2, 1)}));
  r.samples.push_back(sample(2, disc(0, 0, 0, 1, 0), {disc(1, -2, 0)}));  // behind: moving away, no cost
  const auto values = compute_episode_metrics(r);
  EXPECT_NEAR(value(values, "danger_fear_cost"), (0.5 + 1 / std::sqrt(5.0)) * kDt, 1e-12);
  EXPECT_NEAR(value(values, "danger_panic_cost"), std::sqrt(5.0) / 0.4 * kDt, 1e-9);

  // A course missing a person by 5 mm costs as if it missed by 1 cm (the floor), not by 5 mm.
  Recording near = with_robot();
  near.samples.push_back(sample(0, disc(0, 0, 0, 1, 0), {disc(1, 2, 0.605)}));
  const double sine = 0.605 / std::hypot(2.0, 0.605);
  EXPECT_NEAR(value(compute_episode_metrics(near), "danger_panic_cost"), 1.0 / (0.01 * sine) * kDt, 1e-6);
  // Within 1 mm of grazing (here 0.5 mm, and 1e-12 m) it is a collision course: no panic at all.
  for (const double miss : {0.0005, 1e-12}) {
    Recording grazing = with_robot();
    grazing.samples.push_back(sample(0, disc(0, 0, 0, 1, 0), {disc(1, 2, 0.6 + miss)}));
    EXPECT_EQ(value(compute_episode_metrics(grazing), "danger_panic_cost"), 0.0) << "missing by " << miss << " m";
  }
}

TEST(SocialForce, BetweenStillAgentsItPushesApartWithHuNavSimsStrength) {
  // Still agents 1 m apart: D = e, B = γ, θ = 0, so F = −A·exp(−d/γ)·e and no sideways part.
  const Vec2 force = social_force(disc(0, 0, 0), disc(1, 1, 0));
  EXPECT_NEAR(force.x(), -2.1 * std::exp(-1.0 / 0.35), 1e-12);
  EXPECT_NEAR(force.y(), 0.0, 1e-15);
  EXPECT_EQ(social_force(disc(0, 0, 0), disc(1, 0, 0)), Vec2::Zero()) << "coincident: no direction";
  // Walking past on the left: the push has a sideways part away from the other's side.
  const Vec2 passing = social_force(disc(0, 0, 0, 1, 0), disc(1, 1, 0.5));
  EXPECT_LT(passing.y(), 0.0);

  Recording r = with_robot();
  for (int i = 0; i < 10; ++i) r.samples.push_back(sample(i, disc(0, 0, 0), {disc(1, 1, 0)}));
  const auto values = compute_episode_metrics(r);
  const double per_step = 2.1 * std::exp(-1.0 / 0.35);
  EXPECT_NEAR(value(values, "social_force_on_robot"), 10 * per_step * kDt, 1e-12);
  EXPECT_NEAR(value(values, "social_force_on_agents"), 10 * per_step * kDt, 1e-12);
  const double obstacle = 10.0 * std::exp(-10.0 / 0.2);
  EXPECT_NEAR(value(values, "social_work"), 10 * (2 * per_step + obstacle) * kDt, 1e-12);
}

TEST(SocialForce, AnAngleWithinRoundingOfZeroHasNoSidewaysTerm) {
  // Both at rest at these places, 1.15 m apart: D̂ = e up to rounding, and θ comes out as −5.6e-17
  // rather than 0. Its sign must not add a sideways term as large as the main one: the force lies along e.
  const Vec2 at(-4.26, 2.50), other(-4.64, 3.59);
  const Vec2 force = social_force(disc(0, at.x(), at.y()), disc(1, other.x(), other.y()));
  const Vec2 e = (other - at).normalized();
  const double expected = 2.1 * std::exp(-(other - at).norm() / 0.35);
  EXPECT_NEAR(core::cross(force, e), 0.0, 1e-15 * expected) << "no component across the line between them";
  EXPECT_NEAR(force.norm(), expected, 1e-12 * expected);
}

TEST(Series, OneValuePerStepAndNoneWhereAStepHasNone) {
  // The head-on approach of above, then the person is gone.
  Recording r = with_robot();
  r.samples.push_back(sample(0, disc(0, 0, 0, 1.0, 0), {disc(1, 2.0, 0, -1.0, 0, M_PI)}));
  r.samples.push_back(sample(1, disc(0, 0.1, 0, 1.0, 0), {disc(1, 1.5, 0, -1.0, 0, M_PI)}));
  r.samples.push_back(sample(2, disc(0, 0.2, 0), {}));
  const auto series = compute_series(r);
  ASSERT_EQ(series.size(), series_definitions().size());
  const auto& distance = series[0];
  EXPECT_EQ(distance.name, "distance_to_closest_person");
  ASSERT_EQ(distance.values.size(), 3u);
  EXPECT_NEAR(*distance.values[0], 1.4, 1e-12);
  EXPECT_NEAR(*distance.values[1], 0.8, 1e-12);
  EXPECT_FALSE(distance.values[2]);
  EXPECT_EQ(series[1].values[0], 2.0) << "1.4 m: social zone";
  EXPECT_EQ(series[1].values[1], 1.0) << "0.8 m: personal zone";
  EXPECT_NEAR(*series[2].values[0], 0.7, 1e-12) << "1.4 m closing at 2 m/s";
  EXPECT_FALSE(series[2].values[2]);
  EXPECT_EQ(series[3].values[0], 1.0);
  EXPECT_EQ(series[3].values[2], 0.0);
  EXPECT_GT(*series[4].values[1], *series[4].values[0]) << "closer people push harder";
  EXPECT_EQ(series[4].values[2], 0.0);
}

TEST(TimeToCollision, OverlappingParallelAndPassing) {
  EXPECT_EQ(time_to_collision(disc(0, 0, 0), disc(1, 0.5, 0)), 0.0);
  EXPECT_FALSE(time_to_collision(disc(0, 0, 0, 1, 0), disc(1, 2, 0, 1, 0))) << "same velocity: the gap never closes";
  EXPECT_FALSE(time_to_collision(disc(0, 0, 0, 1, 0), disc(1, 2, 1, 0, 0))) << "passes 1 m to the side with 0.6 m of radii";
  EXPECT_FALSE(time_to_collision(disc(0, 0, 0, -1, 0), disc(1, 2, 0))) << "moving apart";
  // Closing at 1 m/s from a surface distance of 1.4 m.
  EXPECT_NEAR(*time_to_collision(disc(0, 0, 0, 1, 0), disc(1, 2, 0)), 1.4, 1e-12);
}

}  // namespace
}  // namespace hrisim::metrics

namespace hrisim::metrics {
namespace {

TEST(HumanPathDeviation, ExtraPathPerPersonAgainstTheRunWithoutTheRobot) {
  // With the robot, person 1 walks 5 m (a detour) and person 2 stands; without it, 4 m and 0 m.
  // Person 3 exists only in the robot run and is left out: (1 + 0) / 2 = 0.5 m.
  Recording with = with_robot(), without = with_robot();
  for (int i = 0; i <= 10; ++i) {
    with.samples.push_back(sample(i, disc(0, 0, 0), {disc(1, 0.5 * i, 5), disc(2, 3, 3), disc(3, 0.1 * i, -5)}));
    without.samples.push_back(sample(i, disc(0, 0, 0), {disc(1, 0.4 * i, 5), disc(2, 3, 3)}));
  }
  EXPECT_NEAR(*human_path_deviation(with, without), 0.5, 1e-12);
  Recording empty = with_robot();
  empty.samples.push_back(sample(0, disc(0, 0, 0), {}));
  EXPECT_FALSE(human_path_deviation(with, empty)) << "nobody in both runs";
  EXPECT_EQ(metric(compute_episode_metrics(with), "human_path_deviation").null_reason, "measured only in runs with baseline_without_robot");
}

}  // namespace
}  // namespace hrisim::metrics
