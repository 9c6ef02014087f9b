#include "metrics/episode_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "core/error.hpp"
#include "metrics/definitions.hpp"

namespace hrisim::metrics {
namespace {

using Values = std::map<std::string, MetricValue, std::less<>>;

/// Why a benchmark task that runs its episode's length has no success.
constexpr const char* kTaskWithoutGoalCondition = "the benchmark task has no goal condition: its reward measures the episode";
/// Why a robot without a goal, a search or a part in the choreography has no success.
constexpr const char* kNoTaskForRobot =
    "the robot has no navigation goal, no search and no part in the choreography: nothing it was asked to do can succeed";

void set(Values& values, std::string key, double value) {
  values[key] = {key, value, ""};
}
void set_null(Values& values, std::string key, std::string reason) {
  values[key] = {key, std::nullopt, std::move(reason)};
}
void set_optional(Values& values, const std::string& key, std::optional<double> value, const std::string& reason) {
  if (value) {
    set(values, key, *value);
  } else {
    set_null(values, key, reason);
  }
}

/// Signed forward speed of the robot at a sample.
double forward_speed(const Body& robot) { return robot.velocity.dot(core::heading_vector(robot.heading)); }

/// Surface distance to the closest human at each sample; empty where no human is present.
std::vector<std::optional<double>> closest_distances(const Recording& recording) {
  std::vector<std::optional<double>> distances;
  distances.reserve(recording.samples.size());
  for (const Sample& sample : recording.samples) {
    std::optional<double> closest;
    for (const Body& human : sample.humans) {
      const double d = surface_distance(sample.robot, human);
      if (!closest || d < *closest) closest = d;
    }
    distances.push_back(closest);
  }
  return distances;
}

/// Path, speed, acceleration and goal metrics of the robot.
void path_metrics(const Recording& r, Values& values) {
  const auto& samples = r.samples;
  const double dt = r.dt;
  const std::size_t n = samples.size();
  double length = 0.0, heading_changes = 0.0, angular_sum = 0.0, not_moving = 0.0;
  double speed_sum = 0.0, max_speed = 0.0;
  std::vector<double> speeds;
  speeds.reserve(n);
  for (std::size_t t = 0; t < n; ++t) {
    const Body& robot = samples[t].robot;
    const double v = forward_speed(robot);
    speeds.push_back(v);
    speed_sum += std::abs(v);
    max_speed = std::max(max_speed, std::abs(v));
    // Yaw rate from the heading change since the previous step (0 at the first step).
    double omega = 0.0;
    if (t > 0) {
      const double turn = std::abs(core::wrap_angle(robot.heading - samples[t - 1].robot.heading));
      length += (robot.position - samples[t - 1].robot.position).norm();
      heading_changes += turn;
      omega = turn / dt;
      angular_sum += omega;
    }
    if (std::abs(v) < kNotMovingSpeed && omega < kNotMovingTurnRate) not_moving += dt;
  }
  set(values, "path_length", length);
  double clearance_sum = 0.0, clearance_min = std::numeric_limits<double>::infinity();
  for (const Sample& sample : samples) {
    clearance_sum += sample.obstacle_distance;
    clearance_min = std::min(clearance_min, sample.obstacle_distance);
  }
  set(values, "min_obstacle_clearance", clearance_min);
  set(values, "avg_obstacle_clearance", clearance_sum / static_cast<double>(n));
  set(values, "cumulative_heading_changes", heading_changes);
  set(values, "time_not_moving", not_moving);
  set(values, "avg_robot_linear_speed", speed_sum / static_cast<double>(n));
  set(values, "max_robot_linear_speed", max_speed);
  set_optional(values, "avg_robot_angular_speed", n > 1 ? std::optional(angular_sum / static_cast<double>(n - 1)) : std::nullopt,
               "a single step has no heading change");

  std::vector<double> accelerations;
  for (std::size_t t = 1; t < n; ++t) accelerations.push_back((speeds[t] - speeds[t - 1]) / dt);
  std::vector<double> jerks;
  for (std::size_t t = 1; t < accelerations.size(); ++t) jerks.push_back((accelerations[t] - accelerations[t - 1]) / dt);
  const auto mean_and_max_abs = [&](const std::vector<double>& series, const std::string& mean_key, const std::string& max_key,
                                    const std::string& reason) {
    if (series.empty()) {
      set_null(values, mean_key, reason);
      set_null(values, max_key, reason);
      return;
    }
    double sum = 0.0, largest = 0.0;
    for (const double x : series) {
      sum += std::abs(x);
      largest = std::max(largest, std::abs(x));
    }
    set(values, mean_key, sum / static_cast<double>(series.size()));
    set(values, max_key, largest);
  };
  mean_and_max_abs(accelerations, "avg_acceleration", "max_acceleration", "an acceleration needs two steps");
  mean_and_max_abs(jerks, "avg_jerk", "max_jerk", "a jerk needs three steps");
}

void goal_metrics(const Recording& r, bool collided, Values& values) {
  static const char* const kKeys[] = {"time_to_goal", "path_efficiency", "minimum_distance_to_target", "final_distance_to_target",
                                      "failure_to_progress", "spl"};
  if (!r.goal) {
    for (const char* key : kKeys) set_null(values, key, "the robot has no navigation goal");
    return;
  }
  const Vec2 goal = *r.goal;
  std::optional<double> reached_at;
  double closest = std::numeric_limits<double>::infinity();
  double length_to_goal = 0.0;  ///< path from the start up to the first step at the goal
  for (std::size_t t = 0; t < r.samples.size(); ++t) {
    const Sample& sample = r.samples[t];
    const double d = (sample.robot.position - goal).norm();
    closest = std::min(closest, d);
    if (reached_at) continue;
    if (t > 0) length_to_goal += (sample.robot.position - r.samples[t - 1].robot.position).norm();
    if (d <= r.goal_radius) reached_at = static_cast<double>(sample.tick - r.samples.front().tick) * r.dt;
  }
  const double final_distance = (r.samples.back().robot.position - goal).norm();
  set_optional(values, "time_to_goal", reached_at, "the robot never reached its goal");
  set(values, "minimum_distance_to_target", closest);
  set(values, "final_distance_to_target", final_distance);
  // The shortest way to the goal is the straight line to its circle, so the ratio is at most 1 as it is.
  const double straight = std::max((goal - r.samples.front().robot.position).norm() - r.goal_radius, 0.0);
  const double length = *values.at("path_length").value;
  if (!reached_at) {
    set_null(values, "path_efficiency", "the robot never reached its goal");
  } else if (length_to_goal <= 0.0) {
    set(values, "path_efficiency", 1.0);  // started at the goal
  } else {
    set(values, "path_efficiency", straight / length_to_goal);
  }
  const bool success = reached_at && !collided;
  set(values, "success", success ? 1.0 : 0.0);
  if (!r.shortest_path_length) {
    set_null(values, "spl", "no collision-free path from the start to the goal on the map");
  } else {
    const double shortest = *r.shortest_path_length;
    set(values, "spl", success ? (shortest <= 0.0 ? 1.0 : shortest / std::max(length, shortest)) : 0.0);
  }
  // Progress over the last window: distance to the goal then minus now.
  const auto window_ticks = static_cast<std::int64_t>(std::llround(kProgressWindow / r.dt));
  const std::int64_t from_tick = r.samples.back().tick - window_ticks;
  const auto then = std::find_if(r.samples.begin(), r.samples.end(), [&](const Sample& s) { return s.tick >= from_tick; });
  const double progress = (then->robot.position - goal).norm() - final_distance;
  set(values, "failure_to_progress", !success && progress < kProgressDistance ? 1.0 : 0.0);
}

/// A search: when the person was found (the event "person_found"), and success.
void search_metrics(const Recording& r, bool collided, Values& values) {
  if (!r.searching) {
    set_null(values, "time_to_find", "the robot does not search for anyone");
    return;
  }
  const auto found = std::find_if(r.events.begin(), r.events.end(), [](const RecordedEvent& event) { return event.kind == RecordedEvent::Kind::person_found; });
  std::optional<double> found_at;
  if (found != r.events.end()) found_at = static_cast<double>(found->tick - r.samples.front().tick) * r.dt;
  set_optional(values, "time_to_find", found_at, "the robot never saw the person's face");
  if (!r.goal) set(values, "success", found_at && !collided ? 1.0 : 0.0);
}

/// Hall's bands for the closest group's centre (the centre: members' mean position plus
/// kGroupCentreAhead ahead of each).
void group_metrics(const Recording& r, Values& values) {
  const auto n = static_cast<double>(r.samples.size());
  int intimate = 0, personal = 0, social = 0;
  for (const Sample& sample : r.samples) {
    std::optional<double> closest;
    for (const std::vector<int>& group : sample.groups) {
      Vec2 centre = Vec2::Zero();
      for (const int member : group) {
        const Body& body = sample.humans[member];
        centre += body.position + kGroupCentreAhead * core::heading_vector(body.heading);
      }
      centre /= static_cast<double>(group.size());
      const double d = std::max((centre - sample.robot.position).norm() - sample.robot.radius, 0.0);
      if (!closest || d < *closest) closest = d;
    }
    if (!closest) continue;
    intimate += *closest < kIntimateDistance;
    personal += *closest >= kIntimateDistance && *closest < kPersonalDistance;
    social += *closest >= kPersonalDistance && *closest < kSocialDistance;
  }
  set(values, "group_intimate_space_intrusions", 100.0 * intimate / n);
  set(values, "group_personal_space_intrusions", 100.0 * personal / n);
  set(values, "group_social_space_intrusions", 100.0 * social / n);
}

/// Singamaneni et al.'s danger costs: fear while the robot closes in on a person, panic while it
/// closes in on a course that passes them.
void danger_metrics(const Recording& r, Values& values) {
  double fear = 0.0, panic = 0.0;
  for (const Sample& sample : r.samples) {
    for (const Body& human : sample.humans) {
      const Vec2 p = human.position - sample.robot.position, v = sample.robot.velocity - human.velocity;
      const double distance = p.norm(), speed = v.norm();
      if (distance == 0.0 || speed == 0.0 || p.dot(v) <= 0.0) continue;
      fear += speed / distance * r.dt;
      const double sine = std::abs(core::cross(p, v)) / (distance * speed);
      const double miss = distance * sine, reach = sample.robot.radius + human.radius;
      if (miss - reach > kPanicGrazeMargin) panic += speed / (std::max(miss - reach, kPanicMissFloor) * sine) * r.dt;
    }
  }
  set(values, "danger_fear_cost", fear);
  set(values, "danger_panic_cost", panic);
}

/// Social forces between the robot and the people, and the obstacles' push on the robot.
void force_metrics(const Recording& r, Values& values) {
  double on_robot = 0.0, on_agents = 0.0, obstacle = 0.0, work = 0.0;
  for (const Sample& sample : r.samples) {
    Vec2 total = Vec2::Zero();
    double by_robot = 0.0;
    for (const Body& human : sample.humans) {
      const Vec2 on = social_force(sample.robot, human);
      total += on;
      on_robot += on.norm() * r.dt;
      by_robot += social_force(human, sample.robot).norm();
    }
    const double push = kObstacleForceStrength * std::exp(-sample.obstacle_distance / kObstacleForceRange);
    on_agents += by_robot * r.dt;
    obstacle += push * r.dt;
    work += (total.norm() + push + by_robot) * r.dt;
  }
  set(values, "social_force_on_robot", on_robot);
  set(values, "social_force_on_agents", on_agents);
  set(values, "obstacle_force_on_robot", obstacle);
  set(values, "social_work", work);
}

void proximity_metrics(const Recording& r, Values& values) {
  const std::vector<std::optional<double>> closest = closest_distances(r);
  const auto n = static_cast<double>(r.samples.size());
  double sum = 0.0, minimum = std::numeric_limits<double>::infinity();
  int with_humans = 0, intimate = 0, personal = 0, social = 0, discomfort = 0;
  for (const auto& d : closest) {
    if (!d) continue;
    ++with_humans;
    sum += *d;
    minimum = std::min(minimum, *d);
    intimate += *d < kIntimateDistance;
    personal += *d >= kIntimateDistance && *d < kPersonalDistance;
    social += *d >= kPersonalDistance && *d < kSocialDistance;
    discomfort += *d < kDiscomfortDistance;
  }
  if (with_humans == 0) {
    for (const char* key : {"avg_distance_to_closest_person", "minimum_distance_to_people", "min_time_to_collision"}) {
      set_null(values, key, "no human was present");
    }
  } else {
    set(values, "avg_distance_to_closest_person", sum / with_humans);
    set(values, "minimum_distance_to_people", minimum);
  }
  set(values, "intimate_space_intrusions", 100.0 * intimate / n);
  set(values, "personal_space_intrusions", 100.0 * personal / n);
  set(values, "social_space_intrusions", 100.0 * social / n);
  set(values, "discomfort_frequency", 100.0 * discomfort / n);
  group_metrics(r, values);
  danger_metrics(r, values);
  if (with_humans == 0) return;
  std::optional<double> soonest;
  for (const Sample& sample : r.samples) {
    for (const Body& human : sample.humans) {
      const auto t = time_to_collision(sample.robot, human);
      if (t && (!soonest || *t < *soonest)) soonest = t;
    }
  }
  set_optional(values, "min_time_to_collision", soonest, "at their velocities the robot and the people never meet");
}

/// Contact metrics; returns whether any collision happened.
bool contact_metrics(const Recording& r, Values& values) {
  int collisions = 0, robot_fault = 0, person_fault = 0;
  double contact_time = 0.0;
  std::set<int> touching_before;  // agents in contact at the previous step
  for (const Sample& sample : r.samples) {
    std::set<int> touching_now;
    for (const Body& human : sample.humans) {
      if (!human.touching_robot && surface_distance(sample.robot, human) >= kContactDistance) continue;
      touching_now.insert(human.agent);
      if (touching_before.contains(human.agent)) continue;
      ++collisions;
      const Vec2 towards_human = human.position - sample.robot.position;
      const bool robot_moved = sample.robot.velocity.norm() > kBlameSpeed && sample.robot.velocity.dot(towards_human) > 0.0;
      const bool human_moved = human.velocity.norm() > kBlameSpeed && human.velocity.dot(-towards_human) > 0.0;
      robot_fault += robot_moved;
      person_fault += human_moved || !robot_moved;
    }
    if (!touching_now.empty()) contact_time += r.dt;
    touching_before = std::move(touching_now);
  }
  int obstacle_collisions = 0;
  std::set<std::string> obstacles_before;
  for (const Sample& sample : r.samples) {
    const std::set<std::string> now(sample.touched_obstacles.begin(), sample.touched_obstacles.end());
    for (const std::string& name : now) obstacle_collisions += !obstacles_before.contains(name);
    obstacles_before = now;
  }
  set(values, "obstacle_collisions", obstacle_collisions);
  set(values, "collisions", collisions);
  set(values, "robot_on_person_collisions", robot_fault);
  set(values, "person_on_robot_collisions", person_fault);
  set(values, "contact_time", contact_time);
  return collisions > 0;
}

/// Each person's path length over the recording, by agent.
std::map<int, double> human_path_lengths(const Recording& r) {
  std::map<int, double> lengths;
  std::map<int, Vec2> last;
  for (const Sample& sample : r.samples) {
    for (const Body& human : sample.humans) {
      if (const auto before = last.find(human.agent); before != last.end()) lengths[human.agent] += (human.position - before->second).norm();
      lengths.try_emplace(human.agent, 0.0);
      last[human.agent] = human.position;
    }
  }
  return lengths;
}

void interaction_metrics(const Recording& r, Values& values) {
  int sent = 0, accepted = 0, dropped = 0;
  std::map<std::int64_t, std::int64_t> asked_at;  // request id → tick
  double latency_sum = 0.0;
  for (const RecordedEvent& event : r.events) {
    if (event.kind == RecordedEvent::Kind::request) {
      ++sent;
      if (event.request) asked_at[*event.request] = event.tick;
    } else if (event.kind == RecordedEvent::Kind::request_accepted) {
      ++accepted;
      if (event.request && asked_at.contains(*event.request)) latency_sum += static_cast<double>(event.tick - asked_at[*event.request]) * r.dt;
    } else if (event.kind == RecordedEvent::Kind::request_dropped) {
      ++dropped;
    }
  }
  set(values, "requests_sent", sent);
  set(values, "requests_accepted", accepted);
  set(values, "requests_dropped", dropped);
  set_optional(values, "request_latency", accepted > 0 ? std::optional(latency_sum / accepted) : std::nullopt,
               "no request was accepted");
  set_null(values, "human_path_deviation", "measured only in runs with baseline_without_robot");
  if (r.has_choreography) {
    set(values, "choreography_completed", r.choreography_completed ? 1.0 : 0.0);
  } else {
    set_null(values, "choreography_completed", "the scenario has no choreography");
  }
}

}  // namespace

double surface_distance(const Body& a, const Body& b) {
  return std::max((a.position - b.position).norm() - a.radius - b.radius, 0.0);
}

Vec2 social_force(const Body& on, const Body& from) {
  const Vec2 offset = from.position - on.position;
  const double d = offset.norm();
  if (d == 0.0) return Vec2::Zero();
  const Vec2 e = offset / d;
  const Vec2 interaction = kSocialForceLambda * (on.velocity - from.velocity) + e;
  const double strength = interaction.norm();
  if (strength == 0.0) return Vec2::Zero();
  const Vec2 direction = interaction / strength;
  const double b = kSocialForceGamma * strength;
  double theta = std::atan2(core::cross(direction, e), direction.dot(e));
  if (std::abs(theta) < kSocialForceZeroAngle) theta = 0.0;
  const double sign = theta > 0.0 ? 1.0 : theta < 0.0 ? -1.0 : 0.0;
  const double along = std::exp(-d / b - std::pow(kSocialForceNPrime * b * theta, 2));
  const double sideways = std::exp(-d / b - std::pow(kSocialForceN * b * theta, 2));
  return kSocialForceStrength * (-along * direction - sign * sideways * core::left_normal(direction));
}

std::optional<double> time_to_collision(const Body& a, const Body& b) {
  const Vec2 p = b.position - a.position;
  const Vec2 v = b.velocity - a.velocity;
  const double reach = a.radius + b.radius;
  const double c = p.squaredNorm() - reach * reach;
  if (c <= 0.0) return 0.0;
  const double qa = v.squaredNorm(), qb = 2.0 * p.dot(v);
  if (qa == 0.0 || qb >= 0.0) return std::nullopt;  // not closing in
  const double discriminant = qb * qb - 4.0 * qa * c;
  if (discriminant < 0.0) return std::nullopt;  // passing by
  return (-qb - std::sqrt(discriminant)) / (2.0 * qa);
}

std::optional<double> human_path_deviation(const Recording& with_robot, const Recording& without_robot) {
  const std::map<int, double> with = human_path_lengths(with_robot), without = human_path_lengths(without_robot);
  double sum = 0.0;
  int people = 0;
  for (const auto& [agent, length] : with) {
    const auto other = without.find(agent);
    if (other == without.end()) continue;
    sum += length - other->second;
    ++people;
  }
  return people == 0 ? std::nullopt : std::optional(sum / people);
}

std::vector<Series> compute_series(const Recording& recording) {
  std::vector<Series> list;
  for (const SeriesDefinition& definition : series_definitions()) list.push_back({std::string(definition.name), std::string(definition.unit), {}});
  const std::vector<std::optional<double>> closest = closest_distances(recording);
  for (std::size_t t = 0; t < recording.samples.size(); ++t) {
    const Sample& sample = recording.samples[t];
    // The reward is the task's, robot under test or not; the other series are the robot's.
    constexpr std::size_t kRewardSeries = 5;
    list[kRewardSeries].values.push_back(recording.episode_reward ? std::optional(sample.reward) : std::nullopt);
    if (!recording.has_robot) {
      for (std::size_t s = 0; s < kRewardSeries; ++s) list[s].values.emplace_back();
      continue;
    }
    std::optional<double> zone;
    if (closest[t]) zone = *closest[t] < kIntimateDistance ? 0 : *closest[t] < kPersonalDistance ? 1 : *closest[t] < kSocialDistance ? 2 : 3;
    std::optional<double> soonest;
    Vec2 force = Vec2::Zero();
    for (const Body& human : sample.humans) {
      const auto ttc = time_to_collision(sample.robot, human);
      if (ttc && (!soonest || *ttc < *soonest)) soonest = ttc;
      force += social_force(sample.robot, human);
    }
    list[0].values.push_back(closest[t]);
    list[1].values.push_back(zone);
    list[2].values.push_back(soonest);
    list[3].values.push_back(sample.robot.velocity.norm());
    list[4].values.push_back(force.norm());
  }
  return list;
}

std::vector<MetricValue> compute_episode_metrics(const Recording& recording) {
  if (recording.samples.empty() || !(recording.dt > 0.0)) {
    throw core::Error(core::ErrorCode::internal, "an episode recording needs at least one sample and dt > 0");
  }
  Values values;
  set(values, "episode_length", static_cast<double>(recording.samples.back().tick - recording.samples.front().tick));
  set_optional(values, "episode_reward", recording.episode_reward, "the scenario defines no benchmark task");
  for (const Definition& definition : definitions()) {
    const std::string key(definition.key);
    if (!key.starts_with("reward_")) continue;
    const auto term = std::find_if(recording.reward_terms.begin(), recording.reward_terms.end(),
                                   [&](const auto& t) { return "reward_" + t.first == key; });
    if (term != recording.reward_terms.end()) {
      set(values, key, term->second);
    } else {
      set_null(values, key, recording.episode_reward ? "the benchmark task's reward has no such term" : "the scenario defines no benchmark task");
    }
  }
  interaction_metrics(recording, values);
  if (recording.has_robot) {
    path_metrics(recording, values);
    const bool collided = contact_metrics(recording, values);
    proximity_metrics(recording, values);
    force_metrics(recording, values);
    goal_metrics(recording, collided, values);
    search_metrics(recording, collided, values);
    if (!recording.goal && !recording.searching) {
      if (recording.task_goal_condition == true) {
        set(values, "success", recording.termination == "goal" && !collided ? 1.0 : 0.0);
      } else if (recording.task_goal_condition == false) {
        set_null(values, "success", kTaskWithoutGoalCondition);
      } else if (recording.robot_in_choreography) {
        set(values, "success", recording.choreography_completed && !collided ? 1.0 : 0.0);
      } else {
        set_null(values, "success", kNoTaskForRobot);
      }
    }
  }
  std::vector<MetricValue> list;
  for (const Definition& definition : definitions()) {
    const auto found = values.find(definition.key);
    if (found != values.end()) {
      list.push_back(found->second);
    } else if (!recording.has_robot) {
      list.push_back({std::string(definition.key), std::nullopt, "the scenario has no robot"});
    } else {
      throw core::Error(core::ErrorCode::internal, "metric " + std::string(definition.key) + " was not computed");
    }
  }
  return list;
}

}  // namespace hrisim::metrics
