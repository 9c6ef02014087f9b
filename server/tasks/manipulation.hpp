#pragma once
// The benchmark's arm tasks (seed 003 §4.4.4–4.4.5).
//
// pick_and_place — a cup on one table, to be put at the centre of another:
//   observation (float64, 18 values): the arm group's 6 joint positions (arm_lift m, arm_flex,
//     arm_roll, wrist_flex, wrist_roll, base_roll rad); the gripper joint's position (rad); gripper
//     closed (0/1); object held (0/1); the grasp point (between the fingers), the object's centre and
//     the target, each x, y, z in the map frame (m)
//   action (float64, 8 values): [mode, gripper, 6 arm joint targets]. mode ≥ 0 makes a gripper step
//     (close when gripper ≥ 0, else open) lasting gripper_frames ticks (8); mode < 0 an arm step to
//     the targets (clipped to the joint limits) lasting frame_skip − gripper_frames ticks (120).
//   reward: 1 − min(d(grasp point, object) / 0.5, 1) + 2 × (1 − min(d(object, target) / 0.5, 1))
//     + (object height − its height at the start) − 0.5 per penalised object touched during the step
//
// mirror_gesture — a human in front of the robot points to her left or right for the whole episode:
//   observation (float32, height × width × 5): the robot camera's R, G, B, A (0–255) and depth (m,
//     0 where nothing is seen) — sent as a binary camera frame, not in JSON
//   action (float64, 6 values): arm joint targets, clipped to the limits; frame_skip ticks (10)
//   reward: 1 when the robot's hand is at least pointing_reach (0.3 m) from its base's centre towards
//     the side the human points to, else 0. Sides are the human's: facing her, pointing to her left
//     is pointing to the robot's right, as a mirror image does.
#include <string>
#include <vector>

#include "tasks/rewards.hpp"
#include "tasks/task.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::tasks {

/// Its state is sim::PickAndPlaceState.
class PickAndPlace : public Task {
 public:
  explicit PickAndPlace(const sim::Session& session);
  void begin(sim::Session& session) const override;
  std::vector<double> observe(const sim::Session& session) const override;
  int act(sim::Session& session, const std::vector<double>& action) const override;
  int idle_ticks(const sim::Session& session) const override;
  void after_tick(sim::Session& session) const override;
  Reward reward(sim::Session& session) const override;
  nlohmann::json info(const sim::Session& session) const override;

  /// Midway between the gripper's fingers, in the map frame.
  static Eigen::Vector3d grasp_point(const sim::Session& session, int robot);

 private:
  const scenario::TaskSettings& task_;
  TouchCounter touches_;
};

/// Its state is sim::MirrorGestureState.
class MirrorGesture : public Task {
 public:
  explicit MirrorGesture(const sim::Session& session);
  void begin(sim::Session& session) const override;
  std::vector<double> observe(const sim::Session&) const override { return {}; }
  int act(sim::Session& session, const std::vector<double>& action) const override;
  int idle_ticks(const sim::Session&) const override { return task_.frame_skip; }
  Reward reward(sim::Session& session) const override;
  nlohmann::json info(const sim::Session& session) const override;

  /// The side of the human that the robot's hand points to (none when nearer than `reach`).
  static Side pointing_side(const sim::Session& session, int robot, int human, double reach);

 private:
  const scenario::TaskSettings& task_;
};

}  // namespace hrisim::tasks
