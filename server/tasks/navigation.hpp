#pragma once
// Navigation tasks. The default one, for scenarios that name no task:
//
//   observation (float64, kObservationSize values)
//     [0, 1]  x, y of the robot in the map frame, m
//     [2, 3]  cos θ, sin θ of its heading
//     [4, 5]  forward speed v (m/s) and yaw rate ω (rad/s)
//     [6, 7]  its goal in the robot's frame (x ahead, y left), m; 0, 0 without a goal
//     then kObservedPeople blocks of 5, nearest person first, people within kObservationRange only:
//             present (1 or 0), position x, y in the robot's frame (m), velocity x, y in the robot's frame (m/s)
//   action (float64, 2 values): forward speed and yaw rate commanded to a robot with a drive (held until
//     the next action), clipped to its limits; for a robot without a model, its velocity in the map frame.
//   reward: 0 (no task). One tick per step.
//
// The benchmark's navigation tasks (seed 003 §4.4.1–4.4.3):
//
//   observation (float64, 11 values): the robot's x, y, cos θ, sin θ, v, ω as above; the human's position
//     x, y and velocity x, y in the robot's frame; the gap between the robot's and the human's footprints (m)
//   action: forward speed and yaw rate, as above
//   reward: previous minus current gap; −20 when closer than 0.1 m; −0.5 for each
//     penalised obstacle touched during the step
//   terminated: closer than 0.3 m (not follow_human)
#include <limits>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "tasks/task.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::tasks {

/// People in the default observation, nearest first.
inline constexpr int kObservedPeople = 8;
/// People farther than this from the robot are left out of the observation, m.
inline constexpr double kObservationRange = 10.0;
/// Values per observed person: present, x, y, vx, vy.
inline constexpr int kPersonValues = 5;
inline constexpr int kObservationSize = 8 + kObservedPeople * kPersonValues;
/// Speed bound of a robot without a model in the action space, m/s.
inline constexpr double kDiscRobotMaxSpeed = 2.0;
/// follow_human: each leg of the human's walk ends at least this far from where it starts, m.
inline constexpr double kFollowMinLeg = 2.0;

class DefaultTask : public Task {
 public:
  explicit DefaultTask(const sim::Session& session);
  std::vector<double> observe(const sim::Session& session) const override;
  int act(sim::Session& session, const std::vector<double>& action) const override;
  int idle_ticks(const sim::Session&) const override { return 1; }
  Reward reward(sim::Session&) const override { return {}; }

 private:
  int robot_ = -1;  ///< agent index of the robot under test: the scenario's first robot
  bool drive_ = false;
};

/// approach_human, follow_human and approach_human_apartment; their state is sim::NavigationTaskState.
class NavigationTask : public Task {
 public:
  explicit NavigationTask(const sim::Session& session);
  void begin(sim::Session& session) const override;
  std::vector<double> observe(const sim::Session& session) const override;
  int act(sim::Session& session, const std::vector<double>& action) const override;
  void before_step(sim::Session& session) const override;
  int idle_ticks(const sim::Session&) const override { return task_.frame_skip; }
  void after_tick(sim::Session& session) const override;
  Reward reward(sim::Session& session) const override;
  bool terminated(const sim::Session& session) const override;
  nlohmann::json info(const sim::Session& session) const override;

 private:
  double distance(const sim::Session& session) const;
  /// A uniform random free place of the spawn area, at least `clearance` from `away_from`.
  core::Vec2 free_place(const sim::Session& session, core::Random& random, const core::Vec2& away_from, double clearance) const;
  /// follow_human: the human walks to the next random place.
  void walk_on(sim::Session& session, core::Random& random) const;

  const scenario::TaskSettings& task_;
  TouchCounter touches_;
};

}  // namespace hrisim::tasks
