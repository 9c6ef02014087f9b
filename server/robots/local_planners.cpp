#include "robots/local_planners.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/portable_math.hpp"
#include "robots/controllers.hpp"

namespace hrisim::robots {

namespace {

/// Gap between the robot's disc at `position` and the nearest static obstacle, up to `cap`.
double static_gap(const RobotMotion& robot, const Surroundings& around, const Vec2& position, double cap) {
  const double reach = robot.radius + kRobotWallMargin;
  const auto obstacle = around.nearest_obstacle(position, reach + around.obstacle_inset + cap);
  if (!obstacle) return cap;
  return (*obstacle - position).norm() - around.obstacle_inset - reach;
}

/// How one candidate velocity held over the prediction horizon fares.
struct Rollout {
  bool admissible = true;
  double clearance = kDwaClearanceCap;  ///< smallest gap on the way (less the personal space for people), capped
  double heading = 0.0;                 ///< how much nearer the target it comes, m
};

/// The gaps at the robot's pose now, the same for every candidate: to the walls, and to each person
/// beyond their personal space.
struct StartGaps {
  double wall = 0.0;
  std::vector<double> people;
};

Rollout roll_out(const RobotMotion& robot, const Twist& twist, const Vec2& target, const Surroundings& around,
                 const StartGaps& start_gaps) {
  const Vec2 start = robot.pose.position();
  Rollout rollout;
  Pose2 pose = robot.pose;
  const int steps = static_cast<int>(std::lround(kDwaPredictionTime / kDwaPredictionStep));
  double collision_time = std::numeric_limits<double>::infinity();
  double nearest_to_target = (target - start).norm();
  for (int k = 1; k <= steps && collision_time == std::numeric_limits<double>::infinity(); ++k) {
    const double time = k * kDwaPredictionStep;
    pose = integrate(pose, twist, kDwaPredictionStep);
    const Vec2 position = pose.position();
    nearest_to_target = std::min(nearest_to_target, (target - position).norm());
    // A gap that is already closed only counts as a collision when it closes further: a robot touching a
    // wall may still drive away from it.
    const double wall = static_gap(robot, around, position, kDwaClearanceCap);
    if (wall <= 0.0 && wall < start_gaps.wall) collision_time = time;
    rollout.clearance = std::min(rollout.clearance, wall);
    // People count as met at their personal space: the robot brakes for it and is steered round it.
    for (std::size_t p = 0; p < around.people.size(); ++p) {
      const Person& person = around.people[p];
      const double room = (person.position + person.velocity * time - position).norm() - (person.radius + robot.radius + around.personal_space);
      if (room <= 0.0 && room < start_gaps.people[p]) collision_time = time;
      rollout.clearance = std::min(rollout.clearance, room);
    }
  }
  rollout.clearance = std::max(rollout.clearance, 0.0);
  // Fox et al.'s admissibility: the robot can still stop before the collision on its way.
  if (collision_time != std::numeric_limits<double>::infinity()) {
    const double distance = std::abs(twist.linear) * std::max(collision_time - kDwaPredictionStep, 0.0);
    rollout.admissible = std::abs(twist.linear) <= std::sqrt(2.0 * distance * kDwaLinearAcceleration);
  }
  // Progress: how much nearer the target the rollout comes (a way round an obstacle is progress too;
  // Fox et al.'s heading alone leaves the robot facing a person who stands on its way). The nearest
  // point on the way, not the end, so that driving through the goal beats passing it.
  rollout.heading = std::max((target - start).norm() - nearest_to_target, 0.0);
  return rollout;
}

/// The nearest obstacle points within `range` in each of kOrcaRobotObstacleSectors directions round the
/// robot (each the nearest to a point on the robot's rim), without repeats: at a door jamb or in a
/// corner one nearest point would leave the other wall free to drive into.
std::vector<Vec2> obstacles_around(const RobotMotion& robot, const Surroundings& around, double range) {
  std::vector<Vec2> points;
  const Vec2 position = robot.pose.position();
  for (int k = 0; k < kOrcaRobotObstacleSectors; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / kOrcaRobotObstacleSectors;
    const Vec2 rim = position + robot.radius * Vec2(std::cos(angle), std::sin(angle));
    const auto obstacle = around.nearest_obstacle(rim, range + robot.radius);
    if (!obstacle || (*obstacle - position).norm() > range) continue;
    const bool seen = std::any_of(points.begin(), points.end(), [&](const Vec2& p) { return (p - *obstacle).norm() < 1e-9; });
    if (!seen) points.push_back(*obstacle);
  }
  return points;
}

/// `count` values evenly from `low` to `high` (one, `low`, when they are equal).
double sample(double low, double high, int index, int count) {
  return count <= 1 || high <= low ? low : low + (high - low) * index / (count - 1);
}

}  // namespace

humans::SocialForceParams social_force_robot_params() {
  humans::SocialForceParams params;
  params.desired_factor = kSocialForceRobotDesiredFactor;
  params.obstacle_sigma = kSocialForceRobotObstacleSigma;
  return params;
}

Twist dynamic_window(const RobotMotion& robot, const std::vector<Vec2>& path, double speed, const Surroundings& around) {
  if (path.empty()) return {};
  const Vec2 position = robot.pose.position();
  const Vec2 target = point_along(position, path, std::min(kDwaTargetDistance, remaining_length(position, path)));
  const double top = std::min(path_velocity(position, path, speed).norm(), robot.limits.max_linear_speed);
  const double linear_high = std::max(std::min(top, robot.twist.linear + kDwaLinearAcceleration * kDwaControlInterval), 0.0);
  const double linear_low = std::min(std::max(0.0, robot.twist.linear - kDwaLinearAcceleration * kDwaControlInterval), linear_high);
  const double turn = kDwaAngularAcceleration * kDwaControlInterval, max_turn = robot.limits.max_angular_speed;
  const double angular_low = std::clamp(robot.twist.angular - turn, -max_turn, max_turn);
  const double angular_high = std::clamp(robot.twist.angular + turn, -max_turn, max_turn);

  StartGaps start_gaps{static_gap(robot, around, position, kDwaClearanceCap), {}};
  for (const Person& person : around.people) {
    start_gaps.people.push_back((person.position - position).norm() - (person.radius + robot.radius + around.personal_space));
  }
  struct Candidate {
    Twist twist;
    Rollout rollout;
  };
  std::vector<Candidate> candidates;
  candidates.reserve(static_cast<std::size_t>(kDwaLinearSamples * kDwaAngularSamples));
  double best_heading = 0.0, best_clearance = 0.0, best_velocity = 0.0;
  for (int i = 0; i < kDwaLinearSamples; ++i) {
    for (int j = 0; j < kDwaAngularSamples; ++j) {
      const Twist twist{sample(linear_low, linear_high, i, kDwaLinearSamples), sample(angular_low, angular_high, j, kDwaAngularSamples)};
      const Rollout rollout = roll_out(robot, twist, target, around, start_gaps);
      if (!rollout.admissible) continue;
      candidates.push_back({twist, rollout});
      best_heading = std::max(best_heading, rollout.heading);
      best_clearance = std::max(best_clearance, rollout.clearance);
      best_velocity = std::max(best_velocity, twist.linear);
    }
  }
  if (candidates.empty()) {
    // Nothing admissible: a round base can always turn on the spot, towards where it is going.
    const Vec2 offset = target - position;
    const double bearing = core::wrap_angle(core::polynomial_atan2(offset.y(), offset.x()) - robot.pose.theta);
    return {0.0, std::clamp(kHeadingGain * bearing, -max_turn, max_turn)};
  }
  // Each term normalised over the window, as Fox et al. do, so the weights compare like with like.
  const auto normalised = [](double value, double best) { return best > 0.0 ? value / best : 0.0; };
  const Candidate* chosen = nullptr;
  double best_score = -1.0;
  for (const Candidate& candidate : candidates) {
    const double score = kDwaHeadingWeight * normalised(candidate.rollout.heading, best_heading) +
                         kDwaClearanceWeight * normalised(candidate.rollout.clearance, best_clearance) +
                         kDwaVelocityWeight * normalised(candidate.twist.linear, best_velocity);
    if (score > best_score) {
      best_score = score;
      chosen = &candidate;
    }
  }
  return chosen->twist;
}

Vec2 orca_velocity(const RobotMotion& robot, const std::vector<Vec2>& path, double speed, const Surroundings& around,
                   double dt) {
  const Vec2 position = robot.pose.position();
  const Vec2 velocity = core::heading_vector(robot.pose.theta) * robot.twist.linear;
  std::vector<humans::OrcaLine> lines;
  std::size_t obstacle_lines = 0;
  const double reach = robot.radius + kRobotWallMargin - around.obstacle_inset;
  for (const Vec2& obstacle : obstacles_around(robot, around, speed * kOrcaRobotObstacleHorizon + reach)) {
    lines.push_back(humans::orca_line(position, velocity, reach, obstacle, Vec2::Zero(), 0.0, kOrcaRobotObstacleHorizon, dt, 1.0));
    ++obstacle_lines;
  }
  // The nearest people, ties broken by their order so the choice is deterministic.
  std::vector<std::pair<double, std::size_t>> nearest;
  for (std::size_t k = 0; k < around.people.size(); ++k) {
    const double distance = (around.people[k].position - position).norm();
    if (distance <= kOrcaRobotNeighbourDistance) nearest.emplace_back(distance, k);
  }
  std::sort(nearest.begin(), nearest.end());
  if (nearest.size() > static_cast<std::size_t>(kOrcaRobotNeighbours)) nearest.resize(static_cast<std::size_t>(kOrcaRobotNeighbours));
  for (const auto& [distance, k] : nearest) {
    const Person& person = around.people[k];
    // The margin is kept where there is room for it; a person already closer is not fled from.
    const double margin = std::clamp(distance - person.radius - robot.radius, 0.0, around.personal_space);
    // Non-reciprocal: the robot takes the whole avoidance on itself.
    lines.push_back(humans::orca_line(position, velocity, robot.radius, person.position, person.velocity, person.radius + margin,
                                      kOrcaRobotTimeHorizon, dt, 1.0));
  }
  return humans::solve_orca(lines, obstacle_lines, speed, path_velocity(position, path, speed));
}

Vec2 social_force_velocity(const RobotMotion& robot, const std::vector<Vec2>& path, double speed,
                           const Surroundings& around, double dt) {
  const humans::SocialForceParams params = social_force_robot_params();
  const Vec2 position = robot.pose.position();
  const Vec2 velocity = core::heading_vector(robot.pose.theta) * robot.twist.linear;
  const Vec2 driving = (path_velocity(position, path, speed) - velocity) / params.relaxation_time;
  Vec2 social = Vec2::Zero();
  for (const Person& person : around.people) {
    const Vec2 offset = person.position - position;
    if (offset.norm() <= params.neighbour_distance) social += humans::interaction_force(params, offset, velocity - person.velocity);
  }
  const auto obstacle = around.nearest_obstacle(position, params.neighbour_distance);
  const Vec2 obstacle_force = obstacle ? humans::obstacle_force(params, position, robot.radius + around.obstacle_inset, *obstacle) : Vec2::Zero();
  const Vec2 acceleration = params.desired_factor * driving + params.social_factor * social + params.obstacle_factor * obstacle_force;
  Vec2 next = velocity + acceleration * dt;
  if (next.norm() > speed) next = next.normalized() * speed;
  return next;
}

}  // namespace hrisim::robots
