#pragma once
// The benchmark task's part of the state: what its episode has drawn, counted and measured so far. The
// task itself (tasks::Task) is configuration only — the model's TaskSettings, its spaces — so a copy
// of the state (a checkpoint) carries everything the task goes on from, and the state hash covers it.
// Plain data: the tasks (server/tasks/) give it its meaning.
#include <string>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>

#include "core/random.hpp"

namespace hrisim::sim {

/// Which side someone points to, seen from above (mirror_gesture).
enum class PointingSide { none, left, right };

/// approach_human, follow_human and approach_human_apartment.
struct NavigationTaskState {
  core::Random random;  ///< the task's own stream ("task"): the human's place, walking style and legs
  /// The gap between the robot's and the human's footprints after the last step (at the start before
  /// the first), m: the next step's distance reward is measured from it.
  double gap = 0.0;
  std::string walking_style;  ///< follow_human: the style drawn for the human; "" for the others

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(random, gap, walking_style); }
};

struct PickAndPlaceState {
  double initial_height = 0.0;  ///< the object's height at the start, m: lifting is measured from it
  /// Ticks of the last step (a gripper step is shorter than an arm step): a step without a new action
  /// lasts as long.
  int step_ticks = 0;
  // Measured at the last step's end, for Gymnasium's info.
  double gripper_object_distance = 0.0;  ///< m, from the grasp point
  double object_target_distance = 0.0;   ///< m
  bool held = false;                     ///< the gripper held the object

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(initial_height, step_ticks, gripper_object_distance, object_target_distance, held); }
};

struct MirrorGestureState {
  core::Random random;  ///< the task's own stream ("task"): the side the human points to
  PointingSide human_side = PointingSide::none;  ///< the side she points to, for the whole episode
  PointingSide robot_side = PointingSide::none;  ///< the side the robot pointed to at the last step's end

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(random, human_side, robot_side); }
};

struct TaskState {
  /// Penalised obstacles and objects the robot has touched during the step under way, sorted.
  std::vector<std::string> touched_this_step;
  /// Those it touched during the last step, sorted: that step's collision penalty, shown in info.
  std::vector<std::string> touched_last_step;
  /// The last step's reward terms, in the task's order; empty until a step of a benchmark task ended.
  std::vector<std::pair<std::string, double>> last_reward_terms;
  /// The task's ending held after the last step (or at the start): the episode is over (reason goal).
  bool terminated = false;
  /// What only one kind of task keeps; none for the default navigation task and without a task.
  std::variant<std::monostate, NavigationTaskState, PickAndPlaceState, MirrorGestureState> kind_state;

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(touched_this_step, touched_last_step, last_reward_terms, terminated, kind_state); }
};

}  // namespace hrisim::sim
