#include "tasks/manipulation.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.hpp"

namespace hrisim::tasks {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

const char* side_name(Side side) { return side == Side::left ? "left" : side == Side::right ? "right" : "none"; }

/// The map-frame pose of the link the robot's gripper is mounted on: its palm.
Eigen::Isometry3d palm_pose(const sim::Session& session, int robot) {
  const robots::RobotDescription& description = *session.model().agents[robot].robot_model;
  const int palm = description.find_link(description.joints[description.find_joint(description.gripper->joint)].parent);
  return runtime_of(session, robot).robot.link_poses()[palm];
}

}  // namespace

PickAndPlace::PickAndPlace(const sim::Session& session) : task_(*session.model().task), touches_(task_) {
  const scenario::AgentDef& robot = session.model().agents[task_.robot];
  const robots::RobotDescription& description = *robot.robot_model;
  const robots::Joint& gripper = description.joints[description.find_joint(description.gripper->joint)];
  std::vector<double> low, high;
  add_arm_limits(robot, low, high);
  low.insert(low.end(), {gripper.limits.lower.value_or(-std::numbers::pi), 0, 0});
  high.insert(high.end(), {gripper.limits.upper.value_or(std::numbers::pi), 1, 1});
  low.insert(low.end(), 9, -kInfinity);
  high.insert(high.end(), 9, kInfinity);
  observation_space_ = box(std::move(low), std::move(high));
  low = {-1, -1};  // mode, gripper
  high = {1, 1};
  add_arm_limits(robot, low, high);
  action_space_ = box(std::move(low), std::move(high));
}

Eigen::Vector3d PickAndPlace::grasp_point(const sim::Session& session, int robot) {
  const robots::RobotDescription& description = *session.model().agents[robot].robot_model;
  // Fixed in the palm: the fingertips' midpoint with the fingers straight (each finger's collision
  // box, centred on its link's axis, reaches twice its centre's offset).
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const std::vector<int> fingers = description.finger_joints();
  for (const int j : fingers) {
    const robots::Joint& finger = description.joints[j];
    const robots::Link& link = description.links[description.find_link(finger.child)];
    sum += robots::to_isometry(finger.origin) * (2.0 * robots::to_isometry(link.collision_origin).translation());
  }
  return palm_pose(session, robot) * (sum / static_cast<double>(fingers.size()));
}

void PickAndPlace::begin(sim::Session& session) const {
  sim::PickAndPlaceState& state = session.task_state().kind_state.emplace<sim::PickAndPlaceState>();
  state.initial_height = session.object_pose(task_.object).translation().z();
  state.step_ticks = task_.frame_skip - task_.gripper_frames;  // an arm step's, before any action
}

int PickAndPlace::idle_ticks(const sim::Session& session) const {
  return std::get<sim::PickAndPlaceState>(session.state().task.kind_state).step_ticks;
}

std::vector<double> PickAndPlace::observe(const sim::Session& session) const {
  std::vector<double> observation = arm_positions(session, task_.robot);
  const sim::RobotRuntime& runtime = runtime_of(session, task_.robot);
  const robots::Robot& body = runtime.robot;
  observation.push_back(body.joint_position(body.joint_index(body.description().gripper->joint)));
  observation.push_back(body.gripper_closed() ? 1.0 : 0.0);
  observation.push_back(runtime.held_object == task_.object ? 1.0 : 0.0);
  for (const Eigen::Vector3d& point : {grasp_point(session, task_.robot), Eigen::Vector3d(session.object_pose(task_.object).translation()), task_.target}) {
    observation.insert(observation.end(), {point.x(), point.y(), point.z()});
  }
  return observation;
}

int PickAndPlace::act(sim::Session& session, const std::vector<double>& action) const {
  int& ticks = std::get<sim::PickAndPlaceState>(session.task_state().kind_state).step_ticks;
  if (action[0] >= 0.0) {
    session.command_robot_gripper(session.agent_at(task_.robot), action[1] >= 0.0);
    ticks = task_.gripper_frames;
  } else {
    command_arm(session, task_.robot, action, 2, action_space_);
    ticks = task_.frame_skip - task_.gripper_frames;
  }
  return ticks;
}

void PickAndPlace::after_tick(sim::Session& session) const { touches_.after_tick(session); }

Reward PickAndPlace::reward(sim::Session& session) const {
  sim::PickAndPlaceState& state = std::get<sim::PickAndPlaceState>(session.task_state().kind_state);
  const Eigen::Vector3d object = session.object_pose(task_.object).translation();
  state.gripper_object_distance = (grasp_point(session, task_.robot) - object).norm();
  state.object_target_distance = (object - task_.target).norm();
  state.held = runtime_of(session, task_.robot).held_object == task_.object;
  const std::vector<std::string>& touched = touches_.end_step(session);
  const double grasp = proximity_reward(state.gripper_object_distance, task_.reward_range);
  const double place = task_.place_weight * proximity_reward(state.object_target_distance, task_.reward_range);
  const double lift = lift_reward(object.z(), state.initial_height);
  const double collisions = obstacle_collision_reward(static_cast<int>(touched.size()), task_.obstacle_penalty);
  return sum_of({{"gripper_object", grasp}, {"object_target", place}, {"lifting", lift}, {"collision_obstacle", collisions}});
}

nlohmann::json PickAndPlace::info(const sim::Session& session) const {
  const sim::TaskState& task = session.state().task;
  if (task.last_reward_terms.empty()) return nlohmann::json::object();  // no step ended yet
  const sim::PickAndPlaceState& state = std::get<sim::PickAndPlaceState>(task.kind_state);
  return {{"gripper_object_distance", state.gripper_object_distance},
          {"object_target_distance", state.object_target_distance},
          {"gripper_object", term(task.last_reward_terms, "gripper_object")},
          {"object_target", term(task.last_reward_terms, "object_target")},
          {"lifting", term(task.last_reward_terms, "lifting")},
          {"collision_obstacle", term(task.last_reward_terms, "collision_obstacle")},
          {"touched", task.touched_last_step},
          {"held", state.held}};
}

MirrorGesture::MirrorGesture(const sim::Session& session) : task_(*session.model().task) {
  const scenario::AgentDef& robot = session.model().agents[task_.robot];
  std::vector<double> low, high;
  add_arm_limits(robot, low, high);
  action_space_ = box(std::move(low), std::move(high));
  observation_space_.name = "Box";
  observation_space_.shape = {task_.image_height, task_.image_width, 5};
  observation_space_.low = {0.0};
  observation_space_.high = {255.0};  // colour 0–255; depth in metres, below any camera's far plane
  observation_space_.dtype = "float32";
  image_ = ImageObservation{robot.id + "." + task_.camera, task_.image_width, task_.image_height};
}

void MirrorGesture::begin(sim::Session& session) const {
  const scenario::Model& model = session.model();
  const sim::AgentState& robot = session.state().agents[task_.robot];
  const core::Vec2 at = robot.position + core::heading_vector(robot.heading) * task_.human_distance;
  const sim::AgentId human = session.agent_at(task_.human);
  session.place_agent(human, {at.x(), at.y(), core::wrap_angle(robot.heading + std::numbers::pi)});
  session.set_rooted(human, true);
  sim::MirrorGestureState& state = session.task_state().kind_state.emplace<sim::MirrorGestureState>();
  state.random = session.state().random.stream("task");
  state.human_side = state.random.uniform() < 0.5 ? Side::left : Side::right;
  // She holds the gesture's last pose for the rest of the episode.
  const std::string gesture = std::string("point_") + side_name(state.human_side);
  session.command_human(sim::motion_action(task_.human, gesture, task_.max_episode_length * model.dt), "motion " + gesture);
}

int MirrorGesture::act(sim::Session& session, const std::vector<double>& action) const {
  command_arm(session, task_.robot, action, 0, action_space_);
  return task_.frame_skip;
}

Side MirrorGesture::pointing_side(const sim::Session& session, int robot, int human, double reach) {
  const Eigen::Vector3d hand = palm_pose(session, robot).translation();
  const core::Vec2 offset = core::Vec2(hand.x(), hand.y()) - session.state().agents[robot].position;
  const double towards_her_left = offset.dot(core::heading_vector(session.state().agents[human].heading + 0.5 * std::numbers::pi));
  return towards_her_left >= reach ? Side::left : towards_her_left <= -reach ? Side::right : Side::none;
}

Reward MirrorGesture::reward(sim::Session& session) const {
  sim::MirrorGestureState& state = std::get<sim::MirrorGestureState>(session.task_state().kind_state);
  state.robot_side = pointing_side(session, task_.robot, task_.human, task_.pointing_reach);
  return sum_of({{"mirror", mirror_reward(state.robot_side, state.human_side)}});
}

nlohmann::json MirrorGesture::info(const sim::Session& session) const {
  const sim::TaskState& task = session.state().task;
  if (task.last_reward_terms.empty()) return nlohmann::json::object();  // no step ended yet
  const sim::MirrorGestureState& state = std::get<sim::MirrorGestureState>(task.kind_state);
  return {{"human_points", side_name(state.human_side)}, {"robot_points", side_name(state.robot_side)}};
}

}  // namespace hrisim::tasks
