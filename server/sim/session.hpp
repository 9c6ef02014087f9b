#pragma once
// A session runs one scenario model: fixed time step, seeded randomness owned by the session, no wall
// clock. tick() advances one tick as a list of phases, each a free function over the model, the state
// and its inputs in a file named for it:
//   people enter → scheduled requests → doors and elevators → requests → choreography → queues →
//   attractions → robots decide → walking → robots move → sounds → tick → physics → sensing →
//   listening → search → time limit → the physics world built again when due.
// Same model, seed and inputs give bit-identical states.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/id.hpp"
#include "humans/body.hpp"
#include "scenario/model.hpp"
#include "sim/choreography.hpp"
#include "sim/human_bodies.hpp"
#include "sim/physics_step.hpp"
#include "sim/robot_runtime.hpp"
#include "sim/events.hpp"
#include "sim/state.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {

struct AgentTag {};
/// An agent of a session; stale once the agent is removed (using it then fails with not_found).
using AgentId = core::Id<AgentTag>;

/// A command's action: human `human` (index) walks to `goal` (within the default goal radius).
scenario::Action walk_action(int human, const Vec2& goal);
/// A command's action: human `human` plays motion primitive `name` for `seconds`, then holds its last pose.
scenario::Action motion_action(int human, const std::string& name, double seconds);

class Session {
 public:
  /// Everything a session is between two ticks but its events: what a checkpoint keeps.
  struct Copy {
    State state;  ///< without its events, which only ever grow: the session's own are its prefix
    core::EntityTable<AgentTag, int> ids;
    std::vector<int> runtime_of_agent;
    std::size_t events = 0;  ///< how many the state had
  };

  Session(std::shared_ptr<const scenario::Model> model, std::uint64_t seed);
  /// The session a copy was taken of, bit for bit, `events` its first copy.events events (the
  /// session's it was copied from); its physics world built again from the state.
  Session(std::shared_ptr<const scenario::Model> model, Copy copy, std::span<const Event> events);

  /// A copy of this session now, or none when it has a physics world that was not just built again from
  /// the state (kPhysicsRebuildInterval): Bullet's world holds history a copy would not carry, and going
  /// on from the copy would not be going on from here, bit for bit.
  std::optional<Copy> copy();

  /// Advances one tick; does nothing once finished.
  void tick();
  /// The benchmark task's ending held (e.g. the robot reached the person): the episode is over, for
  /// reason "goal".
  void end_by_task();
  /// Ends the episode at this much simulation time instead of the model's limit.
  void set_time_limit(double seconds) { state_.time_limit = seconds; }
  /// Threads (this one included) that compute the crowd's velocities; 1 by default. Every count
  /// gives the same trajectory bit for bit: each person's velocity is computed from the tick's inputs
  /// alone, and the sums across people stay on one thread in a fixed order.
  void set_crowd_threads(unsigned threads) { walking_.crowd.set_threads(threads); }

  /// The id of the agent named `name` in the scenario; throws core::Error(not_found) when there is none.
  AgentId agent_id(const std::string& name) const;
  /// The id of the agent at `index` (of the model's agents); throws core::Error(not_found) once it was removed.
  AgentId agent_at(int index) const;
  /// Ids of the agents still in the session, in creation order.
  std::vector<AgentId> agent_ids() const { return ids_.ids(); }
  /// Index of a live agent in state().agents and model().agents; throws on a stale or unknown id.
  int index_of(AgentId id) const { return ids_.at(id); }
  /// Takes an agent out of the session (it leaves the scene); its id becomes stale.
  void remove_agent(AgentId id);

  /// A robot asks for a routine now (IMHuS request): the closest idle human within 3 m answers.
  void request(AgentId robot, int routine);
  /// A robot will ask for a routine at simulation time `time`.
  void schedule_request(double time, AgentId robot, int routine);
  /// Gives a human an action as a command: it goes before whatever they were doing, which starts again
  /// afterwards; `text` says what for the event. The action's agent is the human's index;
  /// scenario::parse_human_command() (the text command language), walk_action() and motion_action()
  /// make them. Throws core::Error(bad_request) for an action to anyone but a human.
  void command_human(const scenario::Action& action, std::string text);
  /// Sets the velocity of a robot without a model, in the map frame, until changed.
  void command_robot(AgentId robot, const Vec2& velocity);
  /// Sets the body velocity of a robot with a model (teleoperation or an external controller) until
  /// changed; it drives by it whenever it is not following a path of its own. Throws
  /// core::Error(conflict) for a robot without a model or without a drive.
  void command_robot_twist(AgentId robot, const robots::Twist& twist);
  /// A robot with a model: its motors, controller and latest sensor readings; null for other agents.
  const RobotRuntime* robot_runtime(AgentId agent) const;
  /// Position targets (or velocities) for a joint group of a robot with a model ("arm", "head", …).
  void command_robot_joints(AgentId robot, const std::string& group, const std::vector<double>& targets, bool velocities = false);
  /// Opens or closes a robot's gripper; closing around an object holds it once both fingers touch it.
  void command_robot_gripper(AgentId robot, bool closed);
  /// The pose of movable object `object` (index in the model's objects) in the map frame.
  Eigen::Isometry3d object_pose(int object) const;
  /// Places an agent (seed 000's uniform pose interface) on free floor, facing pose.theta; a path it
  /// was following is planned again from there, a standing agent stays there. Throws bad_request for
  /// a place off the floor.
  void place_agent(AgentId agent, const Pose2& pose);
  /// An agent that stands its ground (seed 003's idle human, an animation that never yields): it does
  /// not move, not even aside for a robot; others still avoid it.
  void set_rooted(AgentId agent, bool rooted);
  /// A human's walking speed from now on, m/s (throws conflict for a robot).
  void set_preferred_speed(AgentId human, double speed);
  /// Places a movable object, at rest. Throws conflict while a gripper holds it.
  void place_object(int object, const Eigen::Isometry3d& pose);

  /// A human's solids (capsules between its skeleton's joints) in the map frame, posed by what it is
  /// doing now: what contact, range sensors and cameras meet.
  humans::BodyCapsules human_body(int agent) const;

  const State& state() const { return state_; }
  /// The benchmark task's part of the state, for the task (tasks::Task) to keep its bookkeeping in:
  /// what it drew, counted and measured. Nothing in the session reads it.
  TaskState& task_state() { return state_.task; }
  const scenario::Model& model() const { return *model_; }
  const std::shared_ptr<const scenario::Model>& shared_model() const { return model_; }
  double time() const { return time_of(*model_, state_); }
  /// Hash of everything that changes, bit for bit.
  std::uint64_t state_hash() const;
  /// The same as 16 lower-case hex digits, as the API and stored episodes give it.
  std::string state_hash_hex() const;

 private:
  /// Ends the episode at its time limit.
  void end_at_time_limit();

  std::shared_ptr<const scenario::Model> model_;
  core::EntityTable<AgentTag, int> ids_;  ///< live agents → index
  State state_;
  std::vector<int> runtime_of_agent_;  ///< per agent: index into state_.robots, -1 without a model
  HumanBodies bodies_;
  WalkingBuffers walking_;
  PhysicsBodies physics_;
};

}  // namespace hrisim::sim
