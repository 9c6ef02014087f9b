#include "humans/locomotion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/random.hpp"

namespace hrisim::humans {
namespace {

constexpr double kDt = 1.0 / 60.0;
constexpr double kSpeed = 1.34;

std::optional<Vec2> no_obstacles(const Vec2&, double) { return std::nullopt; }

/// Steps agents towards their goals with the crowd; returns the smallest centre distance between
/// agents 0 and 1 seen on the way.
double simulate(Crowd& crowd, std::vector<CrowdAgent>& agents, const std::vector<Vec2>& goals, double seconds,
                const ObstacleQuery& obstacles = no_obstacles) {
  double closest = 1e9;
  std::vector<Vec2> velocities;
  for (int tick = 0; tick < static_cast<int>(seconds / kDt); ++tick) {
    for (std::size_t i = 0; i < agents.size(); ++i) {
      if (agents[i].controlled) continue;
      const Vec2 to_goal = goals[i] - agents[i].position;
      const double distance = to_goal.norm();
      agents[i].preferred_velocity = distance < 0.05 ? Vec2::Zero() : Vec2(to_goal / distance * std::min(kSpeed, distance / 0.5));
    }
    crowd.compute_velocities(agents, obstacles, kDt, velocities);
    for (std::size_t i = 0; i < agents.size(); ++i) {
      agents[i].velocity = velocities[i];
      agents[i].position += velocities[i] * kDt;
    }
    closest = std::min(closest, (agents[0].position - agents[1].position).norm());
  }
  return closest;
}

CrowdAgent walker(Vec2 position, LocalAvoidance avoidance) {
  CrowdAgent agent;
  agent.position = position;
  agent.avoidance = avoidance;
  agent.radius = 0.3;
  agent.max_speed = kSpeed * kMaxSpeedFactor;
  return agent;
}

TEST(SpatialGrid, NearestWithinMatchesBruteForce) {
  core::Random random(5);
  std::vector<Vec2> points;
  for (int i = 0; i < 500; ++i) points.emplace_back(random.uniform(-20, 20), random.uniform(-5, 5));
  // Ties: equal distances must be ordered by index, whatever cell the points are in.
  points.push_back(points[3]);
  points.push_back(points[3] + Vec2(0.5, 0.0));
  points.push_back(points[3] - Vec2(0.5, 0.0));
  SpatialGrid grid(2.0);
  grid.rebuild(points);
  std::vector<Vec2> centres{points[3]};
  for (int q = 0; q < 50; ++q) centres.emplace_back(random.uniform(-22, 22), random.uniform(-6, 6));
  for (const Vec2& centre : centres) {
    std::vector<std::pair<double, std::uint32_t>> all;
    for (std::uint32_t i = 0; i < points.size(); ++i) {
      const double distance = (points[i] - centre).squaredNorm();
      if (distance <= 9.0 && i != 7) all.emplace_back(distance, i);
    }
    std::sort(all.begin(), all.end());
    for (const std::size_t count : {std::size_t{1}, std::size_t{5}, points.size()}) {
      std::vector<std::pair<double, std::uint32_t>> found;
      grid.nearest_within(centre, 3.0, count, 7, found);
      const std::vector expected(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(std::min(count, all.size())));
      EXPECT_EQ(found, expected) << "count " << count;
    }
  }
}

TEST(SpatialGrid, EveryPairWithinRangeExactlyOnce) {
  core::Random random(9);
  std::vector<Vec2> points;
  for (int i = 0; i < 400; ++i) points.emplace_back(random.uniform(-15, 15), random.uniform(-4, 4));
  points.push_back(points[7]);  // two at the same spot
  for (const double range : {1.5, 4.0, 7.0}) {  // below, above and far above the cell size
    SpatialGrid grid(2.0);
    grid.rebuild(points);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> found, expected;
    const auto items = grid.items();
    const auto positions = grid.sorted_positions();
    grid.for_each_candidate_run(range, [&](std::uint32_t a, std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t b = begin; b < end; ++b) {
        if ((positions[b] - positions[a]).norm() <= range) {
          found.emplace_back(std::min(items[a], items[b]), std::max(items[a], items[b]));
        }
      }
    });
    for (std::uint32_t a = 0; a < points.size(); ++a) {
      for (std::uint32_t b = a + 1; b < points.size(); ++b) {
        if ((points[a] - points[b]).norm() <= range) expected.emplace_back(a, b);
      }
    }
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected) << "range " << range;
  }
}

TEST(Orca, WithoutConstraintsThePreferredVelocityIsKept) {
  EXPECT_TRUE(solve_orca({}, 0, 2.0, Vec2(1.0, 0.5)).isApprox(Vec2(1.0, 0.5)));
  EXPECT_TRUE(solve_orca({}, 0, 1.0, Vec2(3.0, 4.0)).isApprox(Vec2(0.6, 0.8))) << "clipped to the max speed";
}

TEST(Orca, HalfPlaneProjectsThePreferredVelocity) {
  // Permitted: left of the line through (0.5, 0) pointing +y, i.e. vx <= 0.5.
  const Vec2 v = solve_orca({{Vec2(0.5, 0.0), Vec2(0.0, 1.0)}}, 0, 2.0, Vec2(1.0, 0.3));
  EXPECT_NEAR(v.x(), 0.5, 1e-12);
  EXPECT_NEAR(v.y(), 0.3, 1e-12);
}

TEST(Orca, HeadOnSwapWithoutCollision) {
  Crowd crowd;
  std::vector<CrowdAgent> agents{walker({-4, 0.0}, LocalAvoidance::orca), walker({4, 0.01}, LocalAvoidance::orca)};
  const std::vector<Vec2> goals{{4, 0}, {-4, 0}};
  const double closest = simulate(crowd, agents, goals, 12.0);
  EXPECT_GE(closest, 0.6 - 0.02) << "the discs (0.3 m each) never overlap";
  EXPECT_LT((agents[0].position - goals[0]).norm(), 0.2);
  EXPECT_LT((agents[1].position - goals[1]).norm(), 0.2);
}

TEST(Orca, HumansGiveWayToANonReciprocatingRobot) {
  Crowd crowd;
  CrowdAgent robot = walker({-4, 0.0}, LocalAvoidance::orca);
  robot.controlled = true;
  robot.velocity = Vec2(0.8, 0.0);
  std::vector<CrowdAgent> agents{robot, walker({4, 0.05}, LocalAvoidance::orca)};
  const std::vector<Vec2> goals{{0, 0}, {-4, 0}};
  const double closest = simulate(crowd, agents, goals, 10.0);
  EXPECT_NEAR(agents[0].position.y(), 0.0, 1e-12) << "the robot keeps its course";
  EXPECT_NEAR(agents[0].position.x(), -4.0 + 0.8 * static_cast<int>(10.0 / kDt) * kDt, 1e-9);
  EXPECT_GE(closest, 0.6 - 0.02) << "the human takes all of the avoidance";
  EXPECT_LT((agents[1].position - goals[1]).norm(), 0.2);
}

// Moussaïd's interaction term turns the two to opposite sides; with pedsim's parameters they pass with
// their centres about 0.4 m apart (pedsim's agents have a 0.2 m radius), where without the term they
// would walk straight through each other.
TEST(SocialForce, HeadOnPassSwervesToOppositeSides) {
  Crowd crowd;
  std::vector<CrowdAgent> agents{walker({-5, 0.0}, LocalAvoidance::social_force),
                                 walker({5, 0.05}, LocalAvoidance::social_force)};
  const std::vector<Vec2> goals{{5, 0}, {-5, 0}};
  const double closest = simulate(crowd, agents, goals, 6.0);  // until just after they meet
  EXPECT_GT(closest, 0.35);
  EXPECT_LT(agents[0].position.y(), -0.1);
  EXPECT_GT(agents[1].position.y(), 0.1);

  Crowd without_interaction(OrcaParams{}, SocialForceParams{.social_factor = 0.0}, PersonalSpace{0.0, 0.0});
  std::vector<CrowdAgent> blind{walker({-5, 0.0}, LocalAvoidance::social_force),
                                walker({5, 0.05}, LocalAvoidance::social_force)};
  EXPECT_LT(simulate(without_interaction, blind, goals, 6.0), 0.1);
}

TEST(SocialForce, HeadOnPassReachesTheGoals) {
  Crowd crowd;
  std::vector<CrowdAgent> agents{walker({-5, 0.0}, LocalAvoidance::social_force),
                                 walker({5, 0.05}, LocalAvoidance::social_force)};
  const std::vector<Vec2> goals{{5, 0}, {-5, 0}};
  simulate(crowd, agents, goals, 15.0);
  EXPECT_LT((agents[0].position - goals[0]).norm(), 0.3);
  EXPECT_LT((agents[1].position - goals[1]).norm(), 0.3);
}

// Walking straight at a wall, the agent settles where the driving force (v0 / τ = 2.68 m/s²) equals
// the obstacle force 10·exp(−(d − r)/0.8): d − r = 0.8·ln(10 / 2.68) = 1.054 m, so d = 1.354 m.
TEST(SocialForce, StopsBeforeAWallAtTheForceEquilibrium) {
  Crowd crowd;
  const ObstacleQuery wall = [](const Vec2& p, double range) -> std::optional<Vec2> {
    if (10.0 - p.x() > range) return std::nullopt;
    return Vec2(10.0, p.y());
  };
  std::vector<CrowdAgent> agents{walker({0, 0}, LocalAvoidance::social_force), walker({0, 50}, LocalAvoidance::social_force)};
  const std::vector<Vec2> goals{{20, 0}, {0, 50}};
  simulate(crowd, agents, goals, 30.0, wall);
  EXPECT_NEAR(10.0 - agents[0].position.x(), 0.3 + 0.8 * std::log(10.0 / kSpeed * 0.5), 0.02);
}

TEST(Crowd, ControlledAgentsKeepTheirVelocity) {
  Crowd crowd;
  CrowdAgent robot = walker({0, 0}, LocalAvoidance::orca);
  robot.controlled = true;
  robot.velocity = Vec2(0.3, -0.2);
  std::vector<CrowdAgent> agents{robot, walker({0.5, 0}, LocalAvoidance::social_force)};
  std::vector<Vec2> velocities;
  crowd.compute_velocities(agents, no_obstacles, kDt, velocities);
  EXPECT_EQ(velocities[0], robot.velocity);
}

// A recorded person played back walks on regardless; the simulated one avoids them alone (as from a
// robot) but keeps the margin it keeps from people (0.30 m), not a robot's (0.45 m).
TEST(Crowd, APersonGivesWayAloneToAReplayedPersonWithThePeoplesMargin) {
  const auto closest_to = [](bool robot) {
    Crowd crowd;
    CrowdAgent other = walker({-4, 0.0}, LocalAvoidance::orca);
    (robot ? other.controlled : other.replayed) = true;
    other.velocity = Vec2(0.8, 0.0);
    std::vector<CrowdAgent> agents{other, walker({4, 0.05}, LocalAvoidance::orca)};
    const double closest = simulate(crowd, agents, {{0, 0}, {-4, 0}}, 10.0);
    EXPECT_NEAR(agents[0].position.y(), 0.0, 1e-12) << "keeps its course";
    EXPECT_LT((agents[1].position - Vec2(-4, 0)).norm(), 0.2);
    return closest;
  };
  const double from_person = closest_to(false), from_robot = closest_to(true);
  EXPECT_GE(from_person, 0.6 + kPersonalSpaceFromPeople - 0.02) << "the whole avoidance, the people's margin";
  EXPECT_LT(from_person, 0.6 + kPersonalSpaceFromRobots - 0.05);
  EXPECT_GE(from_robot, 0.6 + kPersonalSpaceFromRobots - 0.02);
}

// On a collision course, ORCA moves a person's velocity twice as far for a replayed person (full
// responsibility: it does not react) as for a person who takes their half.
TEST(Orca, APersonTakesTheWholeAvoidanceOfAReplayedPerson) {
  const auto change = [](bool replayed) {
    Crowd crowd;
    CrowdAgent self = walker({0, 0}, LocalAvoidance::orca);
    self.velocity = self.preferred_velocity = Vec2(1.0, 0.0);
    CrowdAgent other = walker({1.8, 0.1}, LocalAvoidance::orca);  // within ORCA's 2 m neighbourhood
    other.velocity = other.preferred_velocity = Vec2(-1.0, 0.0);
    other.replayed = replayed;
    std::vector<CrowdAgent> agents{self, other};
    std::vector<Vec2> velocities;
    crowd.compute_velocities(agents, no_obstacles, kDt, velocities);
    if (replayed) {
      EXPECT_EQ(velocities[1], other.velocity) << "a replayed person keeps their velocity";
    }
    return (velocities[0] - self.velocity).norm();
  };
  const double from_person = change(false);
  EXPECT_GT(from_person, 0.01);
  EXPECT_NEAR(change(true), 2.0 * from_person, 1e-9);
}

// Two crowds, one on three threads: 300 people counterflowing, then 200 of them (below kCrowdToShare,
// so the loops run on the caller), then all 300 again. Their velocities agree bit for bit throughout.
TEST(Crowd, ThreadsGiveTheSameVelocitiesAsTheCrowdGrowsAndShrinksPastTheShare) {
  std::vector<CrowdAgent> everyone;
  for (int i = 0; i < 300; ++i) {
    CrowdAgent agent = walker({(i % 20) * 0.9, (i / 20) * 0.9}, i % 3 ? LocalAvoidance::social_force : LocalAvoidance::orca);
    agent.preferred_velocity = {i % 2 ? kSpeed : -kSpeed, 0.0};
    everyone.push_back(agent);
  }
  Crowd one, three;
  three.set_threads(3);
  static_assert(kCrowdToShare > 200 && kCrowdToShare <= 300);
  for (const std::size_t people : {300u, 200u, 200u, 300u}) {
    std::vector<CrowdAgent> agents(everyone.begin(), everyone.begin() + static_cast<std::ptrdiff_t>(people));
    std::vector<Vec2> by_one, by_three;
    for (int tick = 0; tick < 5; ++tick) {
      one.compute_velocities(agents, no_obstacles, kDt, by_one);
      three.compute_velocities(agents, no_obstacles, kDt, by_three);
      ASSERT_EQ(by_one, by_three) << people << " people, tick " << tick;
      for (std::size_t i = 0; i < agents.size(); ++i) {
        agents[i].velocity = by_one[i];
        agents[i].position += by_one[i] * kDt;
      }
    }
    std::copy(agents.begin(), agents.end(), everyone.begin());
  }
}

}  // namespace
}  // namespace hrisim::humans

namespace hrisim::humans {
namespace {

/// One ORCA step of `agents` under the calibrated preset, with ORCA seeing no one and no wall (its
/// neighbourhood cut to 0.5 m, its obstacle horizon to a millisecond) so that the velocity is what
/// Headway asks; agent 0's new velocity.
Vec2 headway_velocity(const std::vector<CrowdAgent>& agents, const ObstacleQuery& obstacles = no_obstacles) {
  CrowdParams params = crowd_preset(CrowdPreset::calibrated);
  params.orca.neighbour_distance = 0.5;
  params.orca.obstacle_horizon = 1e-3;
  Crowd crowd(params.orca, params.social_force, params.personal_space, params.headway);
  std::vector<Vec2> velocities;
  crowd.compute_velocities(agents, obstacles, kDt, velocities);
  return velocities[0];
}

CrowdAgent calibrated_walker(Vec2 position, Vec2 velocity = Vec2::Zero()) {
  CrowdAgent agent = walker(position, LocalAvoidance::orca);
  agent.velocity = agent.preferred_velocity = velocity;
  return agent;
}

TEST(Headway, BlockedEveryWayAWalkerGoesOnStraightAtTheGapOverTheTimeGap) {
  // People on a half circle of 1 m ahead, every 5°: each way within the field of view (every 15°) meets
  // one 0.4 m away, surface to surface. None is freer, so the walker keeps its way at 0.4 m / 0.65 s.
  std::vector<CrowdAgent> agents{calibrated_walker({0, 0}, {kSpeed, 0})};
  for (int degrees = -90; degrees <= 90; degrees += 5) {
    agents.push_back(calibrated_walker(core::heading_vector(degrees * std::numbers::pi / 180.0)));
  }
  const Vec2 velocity = headway_velocity(agents);
  EXPECT_NEAR(velocity.y(), 0.0, 1e-9);
  EXPECT_NEAR(velocity.x(), 0.4 / kCalibratedTimeGap, 1e-9);
}

TEST(Headway, AWalkerBehindASlowerOneTurnsToTheFreeWayAtItsOwnSpeed) {
  // Straight on, 0.4 m to the slower walker; 45° aside, nobody within the horizon: Moussaïd et al.'s
  // rule prefers 45° (the nearest way to the destination), at the walker's own speed.
  const std::vector<CrowdAgent> agents{calibrated_walker({0, 0}, {kSpeed, 0}), calibrated_walker({1.0, 0}, {0.5, 0})};
  const Vec2 velocity = headway_velocity(agents);
  EXPECT_NEAR(velocity.norm(), kSpeed, 1e-9);
  EXPECT_NEAR(std::abs(std::atan2(velocity.y(), velocity.x())), std::numbers::pi / 4, 1e-9);
}

TEST(Headway, AWallAheadSlowsAWalkerAsAPersonWouldAndOneAlongsideDoesNot) {
  // A wall 1 m ahead (its nearest point): 0.7 m to go before the body touches it.
  const auto wall_ahead = [](const Vec2& p, double range) -> std::optional<Vec2> {
    const Vec2 point(1.0, p.y());
    return (point - p).norm() <= range ? std::optional<Vec2>(point) : std::nullopt;
  };
  const Vec2 towards = headway_velocity({calibrated_walker({0, 0}, {kSpeed, 0})}, wall_ahead);
  EXPECT_NEAR(towards.x(), 0.7 / kCalibratedTimeGap, 1e-9);
  EXPECT_NEAR(towards.y(), 0.0, 1e-9);
  // Along the same wall, 0.5 m from it: nothing ahead.
  const Vec2 along = headway_velocity({calibrated_walker({0.5, 0}, {0, kSpeed})}, wall_ahead);
  EXPECT_NEAR(along.y(), kSpeed, 1e-9);
  EXPECT_NEAR(along.x(), 0.0, 1e-9);
}

TEST(Headway, OffByDefaultAndAWalkerAloneKeepsItsVelocity) {
  EXPECT_EQ(crowd_preset(CrowdPreset::hrisim).headway.time_gap, 0.0);
  EXPECT_EQ(Crowd().headway().time_gap, 0.0);
  const Vec2 alone = headway_velocity({calibrated_walker({0, 0}, {1.0, 0.5})});
  EXPECT_NEAR(alone.x(), 1.0, 1e-9);
  EXPECT_NEAR(alone.y(), 0.5, 1e-9);
}

TEST(CrowdPresets, CrowdNavsSettingsAreItsOrcaWithoutMargins) {
  const CrowdParams crowdnav = crowd_preset(CrowdPreset::crowdnav);
  EXPECT_EQ(crowdnav.orca.neighbour_distance, 10.0);
  EXPECT_EQ(crowdnav.orca.max_neighbours, 10);
  EXPECT_EQ(crowdnav.orca.time_horizon, 5.0);
  EXPECT_EQ(crowdnav.orca.obstacle_horizon, 5.0);
  EXPECT_EQ(crowdnav.personal_space.from_people, 0.0);
  EXPECT_EQ(crowdnav.personal_space.from_robots, 0.0);
  const CrowdParams calibrated = crowd_preset(CrowdPreset::calibrated);
  EXPECT_EQ(calibrated.headway.time_gap, kCalibratedTimeGap);
  EXPECT_EQ(calibrated.personal_space.from_people, 0.0);
  EXPECT_EQ(calibrated.personal_space.from_robots, kPersonalSpaceFromRobots) << "robots keep their margin";
  EXPECT_EQ(calibrated.social_force.obstacle_sigma, kCalibratedObstacleSigma);
}

}  // namespace
}  // namespace hrisim::humans
