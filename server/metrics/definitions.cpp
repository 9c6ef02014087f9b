#include "metrics/definitions.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace hrisim::metrics {
namespace {

constexpr std::string_view kTask = "task_and_path", kProximity = "proximity", kContact = "contact", kForces = "social_forces",
                           kInteraction = "interaction", kRewards = "task_rewards";

// The order is the order of METRICS.md and of every listing.
constexpr std::array kDefinitions{
    Definition{"success", "bool", kTask, Better::higher,
               "1 when the episode reached its goal condition: the robot's navigation goal reached with no robot-human collision; "
               "for a searching robot, the person found with no collision; for a benchmark task that ends at a goal condition "
               "(approach_human, approach_human_apartment), the task ended there with no collision (null for the other tasks: their "
               "reward measures them); for a robot with none of these but a part in the choreography "
               "(a step's action or a request it makes), the choreography completed with no collision; null for a robot with none "
               "of these (nothing it was asked to do can succeed)",
               "recent social-navigation benchmarks"},
    Definition{"spl", "ratio", kTask, Better::higher,
               "success weighted by path length: success x shortest / max(path length, shortest), the shortest path on the map's "
               "grid inflated by the robot's radius, people ignored; null without a goal",
               "Anderson et al. 2018"},
    Definition{"failure_to_progress", "bool", kTask, Better::lower,
               "1 for an unsuccessful episode whose last 10 s brought the robot less than 0.1 m closer to its goal; null without a goal",
               "HuNavSim"},
    Definition{"time_to_goal", "s", kTask, Better::lower,
               "simulation time at which the robot was first within its goal radius; null if never", "HuNavSim"},
    Definition{"time_to_find", "s", kTask, Better::lower,
               "simulation time at which a searching robot's people detector first saw the person's face; null without a search "
               "or if never",
               "seed 000 (apartment search)"},
    Definition{"path_length", "m", kTask, Better::none, "length of the robot's path: sum of the distances between consecutive steps",
               "HuNavSim"},
    Definition{"path_efficiency", "ratio", kTask, Better::higher,
               "distance from the start to the goal's circle (straight line to the goal minus its radius) divided by the path length up "
               "to the first step at the goal, for an episode that reached its goal; 1 for a start inside the goal", "SEAN 2.0"},
    Definition{"cumulative_heading_changes", "rad", kTask, Better::lower,
               "sum of the absolute heading changes between consecutive steps, each wrapped into (-pi, pi]", "HuNavSim"},
    Definition{"minimum_distance_to_target", "m", kTask, Better::lower, "smallest distance from the robot to its goal", "HuNavSim"},
    Definition{"final_distance_to_target", "m", kTask, Better::lower, "distance from the robot to its goal at the last step", "HuNavSim"},
    Definition{"time_not_moving", "s", kTask, Better::lower,
               "time with |v| < 0.01 m/s and |omega| < 0.02 rad/s (HuNavSim takes abs of a boolean here: fixed)", "HuNavSim"},
    Definition{"avg_robot_linear_speed", "m/s", kTask, Better::none, "mean of the robot's absolute forward speed", "HuNavSim"},
    Definition{"avg_robot_angular_speed", "rad/s", kTask, Better::lower,
               "mean over the N - 1 intervals between consecutive steps of |heading change, wrapped into (-pi, pi]| / dt", "HuNavSim"},
    Definition{"max_robot_linear_speed", "m/s", kTask, Better::none, "largest absolute forward speed of the robot", "HuNavSim"},
    Definition{"min_obstacle_clearance", "m", kTask, Better::higher,
               "smallest surface distance from the robot to the nearest static obstacle (grid resolution)", "HuNavSim"},
    Definition{"avg_obstacle_clearance", "m", kTask, Better::higher, "mean surface distance from the robot to the nearest static obstacle",
               "HuNavSim"},
    Definition{"avg_acceleration", "m/s^2", kTask, Better::lower,
               "mean of |dv/dt| over consecutive steps (HuNavSim divides by dt squared: fixed)", "HuNavSim"},
    Definition{"max_acceleration", "m/s^2", kTask, Better::lower, "largest |dv/dt| over consecutive steps", "HuNavSim"},
    Definition{"avg_jerk", "m/s^3", kTask, Better::lower, "mean of |da/dt| over consecutive accelerations", "HuNavSim"},
    Definition{"max_jerk", "m/s^3", kTask, Better::lower, "largest |da/dt| over consecutive accelerations", "HuNavSim"},

    Definition{"avg_distance_to_closest_person", "m", kProximity, Better::higher,
               "mean over steps with at least one human of the surface distance to the closest person", "HuNavSim"},
    Definition{"minimum_distance_to_people", "m", kProximity, Better::higher,
               "smallest surface distance (centre distance minus both radii, at least 0) to any person", "HuNavSim"},
    Definition{"intimate_space_intrusions", "%", kProximity, Better::lower,
               "percentage of steps with the closest person nearer than 0.45 m", "HuNavSim"},
    Definition{"personal_space_intrusions", "%", kProximity, Better::lower,
               "percentage of steps with the closest person between 0.45 m and 1.2 m", "HuNavSim"},
    Definition{"social_space_intrusions", "%", kProximity, Better::lower,
               "percentage of steps with the closest person between 1.2 m and 3.6 m", "HuNavSim"},
    Definition{"group_intimate_space_intrusions", "%", kProximity, Better::lower,
               "percentage of steps with the closest group's centre (members' mean position plus 1.5 m ahead of each) nearer than "
               "0.45 m to the robot's surface",
               "HuNavSim"},
    Definition{"group_personal_space_intrusions", "%", kProximity, Better::lower,
               "percentage of steps with the closest group's centre between 0.45 m and 1.2 m", "HuNavSim"},
    Definition{"group_social_space_intrusions", "%", kProximity, Better::lower,
               "percentage of steps with the closest group's centre between 1.2 m and 3.6 m", "HuNavSim"},
    Definition{"discomfort_frequency", "%", kProximity, Better::lower,
               "percentage of steps with the closest person nearer than 0.2 m (CrowdNav's danger)", "CrowdNav"},
    Definition{"min_time_to_collision", "s", kProximity, Better::higher,
               "smallest time at which the robot and a person, as discs at constant current velocities, would touch; null if never",
               "SocNavBench"},

    Definition{"danger_fear_cost", "1/s", kProximity, Better::lower,
               "sum over steps and people, times dt, of |V|/|P| while the robot closes in (P = person - robot, V = robot - person "
               "velocity, P.V > 0)",
               "Singamaneni et al. 2023 (HuNavSim)"},
    Definition{"danger_panic_cost", "1/s", kProximity, Better::lower,
               "sum over steps and people, times dt, of |V| / ((d_perp - R) |sin theta|) while closing in on a course that misses "
               "(d_perp = |P| sin theta, R = both radii, d_perp - R > 1 mm: a course within 1 mm of grazing is a collision course); "
               "d_perp - R at least 1 cm, so that a near-grazing course does not divide by almost zero",
               "Singamaneni et al. 2023 (HuNavSim)"},

    Definition{"collisions", "count", kContact, Better::lower,
               "distinct robot-human contacts (physics contact or surface distance < 0.02 m); a contact lasting several steps counts once",
               "HuNavSim"},
    Definition{"robot_on_person_collisions", "count", kContact, Better::lower,
               "collisions where the robot moved towards the person (faster than 0.01 m/s) at the first step of contact", "HuNavSim"},
    Definition{"person_on_robot_collisions", "count", kContact, Better::lower,
               "collisions where the person moved towards the robot, or the robot did not", "HuNavSim"},
    Definition{"obstacle_collisions", "count", kContact, Better::lower,
               "distinct contacts of the robot with static things (walls, obstacles, objects; physics contact, or a disc robot "
               "within 0.02 m of a wall)",
               "HuNavSim"},
    Definition{"contact_time", "s", kContact, Better::lower, "total time in contact with any human", "hrisim"},

    Definition{"social_force_on_robot", "N s/kg", kForces, Better::lower,
               "sum over steps and people of |F(person -> robot)| dt, lightsfm's social force (HuNavSim swaps x and y in one "
               "atan2: fixed here)",
               "HuNavSim"},
    Definition{"social_force_on_agents", "N s/kg", kForces, Better::lower, "sum over steps and people of |F(robot -> person)| dt",
               "HuNavSim"},
    Definition{"obstacle_force_on_robot", "N s/kg", kForces, Better::lower,
               "sum over steps of 10 exp(-d/0.2) dt, d the robot's surface distance to the nearest obstacle", "HuNavSim"},
    Definition{"social_work", "N s/kg", kForces, Better::lower,
               "sum over steps of (|sum of the forces of people on the robot| + |obstacle force| + sum of |forces of the robot on "
               "people|) dt",
               "HuNavSim"},

    Definition{"requests_sent", "count", kInteraction, Better::none, "robot requests to humans", "IMHuS"},
    Definition{"requests_accepted", "count", kInteraction, Better::higher, "robot requests a human accepted", "IMHuS"},
    Definition{"requests_dropped", "count", kInteraction, Better::lower,
               "robot requests no idle human within 3 m could answer", "IMHuS"},
    Definition{"request_latency", "s", kInteraction, Better::lower, "mean time from a request to its acceptance", "IMHuS"},
    Definition{"human_path_deviation", "m", kInteraction, Better::lower,
               "mean over the people of the extra path each walked compared with the same seed run without the robot (runs "
               "with baseline_without_robot only)",
               "hrisim"},
    Definition{"choreography_completed", "bool", kInteraction, Better::higher,
               "1 when every regular choreography step finished before the time limit; null without a choreography", "IMHuS"},

    Definition{"episode_reward", "reward", kRewards, Better::higher,
               "sum of the benchmark task's per-step rewards; null for a scenario without a benchmark task", "Gymnasium"},
    Definition{"episode_length", "steps", kRewards, Better::none, "number of simulation steps of the episode", "Gymnasium"},
    Definition{"reward_distance", "reward", kRewards, Better::higher,
               "navigation tasks: sum over the env steps of the previous minus the current robot–person distance", "seed 003 §4.4.1"},
    Definition{"reward_collision_human", "reward", kRewards, Better::higher,
               "navigation tasks: sum of the penalties for ending an env step closer to the person than the collision distance",
               "seed 003 §4.4.1"},
    Definition{"reward_collision_obstacle", "reward", kRewards, Better::higher,
               "approach_human_apartment, pick_and_place: sum of the penalties for the listed obstacles and objects touched",
               "seed 003 §4.4.3"},
    Definition{"reward_gripper_object", "reward", kRewards, Better::higher,
               "pick_and_place: sum of the gripper's proximity to the object", "seed 003 §4.4.4"},
    Definition{"reward_object_target", "reward", kRewards, Better::higher,
               "pick_and_place: sum of the object's proximity to the target, weighted", "seed 003 §4.4.4"},
    Definition{"reward_lifting", "reward", kRewards, Better::higher, "pick_and_place: sum of the object's height above its start",
               "seed 003 §4.4.4"},
    Definition{"reward_mirror", "reward", kRewards, Better::higher,
               "mirror_gesture: env steps at whose end the robot pointed to the side the person points to", "seed 003 §4.4.5"},
};

constexpr std::array kSeries{
    SeriesDefinition{"distance_to_closest_person", "m", "surface distance from the robot to the closest person; none without people"},
    SeriesDefinition{"proxemic_zone", "zone",
                     "Hall's zone of the closest person: 0 intimate (< 0.45 m), 1 personal (< 1.2 m), 2 social (< 3.6 m), 3 public"},
    SeriesDefinition{"time_to_collision", "s",
                     "soonest time at which the robot and a person, at their current velocities, would touch; none if never"},
    SeriesDefinition{"robot_speed", "m/s", "the robot's speed"},
    SeriesDefinition{"social_force_on_robot", "N/kg", "magnitude of the people's summed social force on the robot"},
    SeriesDefinition{"episode_reward", "reward",
                     "the benchmark task's rewards of the env steps ended so far, summed; none without a benchmark task"},
};

}  // namespace

std::span<const Definition> definitions() { return kDefinitions; }

std::span<const SeriesDefinition> series_definitions() { return kSeries; }

const Definition* find_definition(std::string_view key) {
  const auto found = std::find_if(kDefinitions.begin(), kDefinitions.end(), [&](const Definition& d) { return d.key == key; });
  return found == kDefinitions.end() ? nullptr : &*found;
}

std::string reference_markdown() {
  std::string page =
      "# Episode metrics\n\n"
      "Generated by `hrisim metrics` from the definitions that `GET /api/v1/metrics` serves "
      "(`server/metrics/definitions.cpp`); a test keeps this page equal to them. The specification is "
      "`../shared/METRICS.md`. Every metric is computed for the robot under test (the scenario's first "
      "robot) from what the episode recorded at every simulation step. A metric without a value is `null` "
      "with its reason, never NaN or infinity. Distances to people are surface to surface (centre distance "
      "minus both radii, at least 0).\n";
  const auto number = [](double value) {
    std::string text = std::to_string(value);
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') text.pop_back();
    return text;
  };
  std::string_view category;
  for (const Definition& d : definitions()) {
    if (d.category != category) {
      category = d.category;
      std::string title(category);
      std::replace(title.begin(), title.end(), '_', ' ');
      title[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(title[0])));
      page += "\n## " + title + "\n\n| key | unit | better | definition | convention |\n|---|---|---|---|---|\n";
    }
    std::string description;
    for (const char c : d.description) description += c == '|' ? std::string("\\|") : std::string(1, c);  // a table cell
    page += "| `" + std::string(d.key) + "` | " + std::string(d.unit) + " | " + std::string(to_string(d.better)) + " | " + description +
            " | " + std::string(d.convention) + " |\n";
  }
  page += "\nThe duration of each choreography step (METRICS.md's `step_durations`) is in every episode's detail, "
          "`GET /api/v1/episodes/{id}`, as `step_durations`.\n";
  page += "\n## Per-step series\n\nKept for plots at the trajectory's rate (10 Hz), served by `GET /api/v1/episodes/{id}/series`.\n\n"
          "| name | unit | meaning |\n|---|---|---|\n";
  for (const SeriesDefinition& series : kSeries) {
    page += "| `" + std::string(series.name) + "` | " + std::string(series.unit) + " | " + std::string(series.description) + " |\n";
  }
  page += "\n## Named defaults\n\n| name | value | meaning |\n|---|---|---|\n";
  const std::pair<const char*, std::pair<double, const char*>> defaults[] = {
      {"kIntimateDistance", {kIntimateDistance, "m: Hall's intimate zone ends (HuNavSim)"}},
      {"kPersonalDistance", {kPersonalDistance, "m: personal zone ends"}},
      {"kSocialDistance", {kSocialDistance, "m: social zone ends"}},
      {"kDiscomfortDistance", {kDiscomfortDistance, "m: CrowdNav's danger distance"}},
      {"kContactDistance", {kContactDistance, "m: surface distance that counts as contact without a physics contact"}},
      {"kNotMovingSpeed", {kNotMovingSpeed, "m/s: below it (and kNotMovingTurnRate) the robot is not moving"}},
      {"kNotMovingTurnRate", {kNotMovingTurnRate, "rad/s"}},
      {"kBlameSpeed", {kBlameSpeed, "m/s: a collision is blamed on whoever moved towards the other faster"}},
      {"kProgressWindow", {kProgressWindow, "s: failure to progress looks back this far"}},
      {"kProgressDistance", {kProgressDistance, "m: ... and asks for at least this much progress"}},
      {"kPanicMissFloor", {kPanicMissFloor, "m: the panic cost's miss distance is at least this"}},
      {"kPanicGrazeMargin", {kPanicGrazeMargin, "m: a course missing by no more than this is a collision course (no panic cost)"}},
      {"kGroupCentreAhead", {kGroupCentreAhead, "m: a group's centre lies this far ahead of its members"}},
      {"kSocialForceStrength", {kSocialForceStrength, "A of the social force"}},
      {"kSocialForceLambda", {kSocialForceLambda, "lambda: weight of the velocity difference"}},
      {"kSocialForceGamma", {kSocialForceGamma, "gamma"}},
      {"kSocialForceN", {kSocialForceN, "n"}},
      {"kSocialForceNPrime", {kSocialForceNPrime, "n'"}},
      {"kSocialForceZeroAngle", {kSocialForceZeroAngle, "rad: a smaller |theta| counts as 0 (no sideways term)"}},
      {"kObstacleForceStrength", {kObstacleForceStrength, "strength of the obstacle force at contact"}},
      {"kObstacleForceRange", {kObstacleForceRange, "m: its decay length"}},
  };
  for (const auto& [name, entry] : defaults) page += "| `" + std::string(name) + "` | " + number(entry.first) + " | " + entry.second + " |\n";
  return page;
}

std::string_view to_string(Better better) {
  switch (better) {
    case Better::higher: return "higher";
    case Better::lower: return "lower";
    case Better::none: return "none";
  }
  return "none";
}

}  // namespace hrisim::metrics
