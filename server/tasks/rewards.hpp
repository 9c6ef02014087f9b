#pragma once
// The reward terms of seed 003 §4.4, as pure functions of what a step measured: each task adds the
// ones it uses, and the tests check each against values worked out by hand.
#include <algorithm>

#include "sim/task_state.hpp"

namespace hrisim::tasks {

/// §4.4.1.6: previous minus current robot–human distance (positive when the robot came closer).
inline double distance_reward(double previous_distance, double distance) { return previous_distance - distance; }

/// §4.4.1.6: −penalty when robot and human are closer than `collision_distance`, else 0.
inline double human_collision_reward(double distance, double collision_distance, double penalty) {
  return distance < collision_distance ? -penalty : 0.0;
}

/// §4.4.3.5, §4.4.4.4: −penalty for each named obstacle or object the robot touched during the step.
inline double obstacle_collision_reward(int touched, double penalty) { return touched > 0 ? -penalty * touched : 0.0; }

/// §4.4.4.4: 1 − min(d / range, 1): 1 at the point, falling to 0 at `range` and beyond.
inline double proximity_reward(double distance, double range) { return 1.0 - std::min(distance / range, 1.0); }

/// §4.4.4.4: how far the object is above where it started, m (negative below).
inline double lift_reward(double height, double initial_height) { return height - initial_height; }

/// Which side something points to, seen from above (kept in the task's state, hence sim's).
using Side = sim::PointingSide;

/// §4.4.5.5: 1 when the robot points to the side the human points to, else 0.
inline double mirror_reward(Side robot, Side human) { return robot != Side::none && robot == human ? 1.0 : 0.0; }

}  // namespace hrisim::tasks
