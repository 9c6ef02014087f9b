#pragma once
// A session runs one scenario model: fixed time step, seeded randomness owned by the session, no wall
// clock. step() advances one tick in a fixed order: inputs → choreography decides → locomotion computes
// all new velocities → commit → observers. Same model, seed and inputs give bit-identical states.
#include <memory>
#include <string>

#include "core/id.hpp"
#include "humans/body.hpp"
#include "humans/locomotion.hpp"
#include "physics/physics_world.hpp"
#include "scenario/model.hpp"
#include "sim/robot_runtime.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// A human answers a robot request only within this distance of where the robot asked (IMHuS).
inline constexpr double kRequestRadius = 3.0;
/// An unanswered request is tried again this often, in seconds...
inline constexpr double kRequestRetryPeriod = 5.0;
/// ...until it is this old, then dropped (counted as a failure), in seconds.
inline constexpr double kRequestTimeout = 30.0;
/// Turning speed of humans, rad/s.
inline constexpr double kTurnRate = 3.0;
/// A turn or look-at is complete within this angle, rad.
inline constexpr double kHeadingTolerance = 0.05;
/// Humans slow down over this distance before their goal, m.
inline constexpr double kArrivalSlowdown = 0.5;
/// A waypoint (other than the last) counts as passed within this distance, m.
inline constexpr double kWaypointReached = 0.3;
/// A standing agent pushed further than this from where it arrived steps back, m...
inline constexpr double kHoldTolerance = 0.3;
/// ...at this speed, m/s.
inline constexpr double kHoldSpeed = 0.5;
/// Replanning because avoidance pushed an agent off its path happens at most this often, s.
inline constexpr double kReplanInterval = 0.5;
/// An agent pushed off its path walks on straight to its waypoint when a disc of this fraction of its
/// radius would pass; otherwise it plans again (waypoints hug the inflated walls, so the full radius
/// would fail needlessly).
inline constexpr double kRejoinClearance = 0.5;
/// Without a path, planning is tried again after this long, s.
inline constexpr double kReplanRetry = 1.0;

/// A person's body takes part in the physics world within this distance of a robot, m (farther, it
/// cannot touch one: a robot's reach plus a person's).
inline constexpr double kHumanContactRange = 3.0;
/// A person holding a motion primitive's last pose walks off it (it blends out) above this speed, m/s.
inline constexpr double kMotionReleaseSpeed = 0.2;

struct AgentTag {};
/// An agent of a session; stale once the agent is removed (using it then fails with not_found).
using AgentId = core::Id<AgentTag>;

class Session {
 public:
  Session(std::shared_ptr<const scenario::Model> model, std::uint64_t seed);

  /// Advances one tick; does nothing once finished.
  void step();
  /// The benchmark task's ending held (e.g. the robot reached the person): the episode is over, for
  /// reason "goal".
  void end_by_task();
  /// Ends the episode at this much simulation time instead of the model's limit.
  void set_time_limit(double seconds) { time_limit_ = seconds; }

  /// The id of the agent named `name` in the scenario; throws core::Error(not_found) when there is none.
  AgentId agent_id(const std::string& name) const;
  /// Ids of the agents still in the session, in creation order.
  std::vector<AgentId> agent_ids() const { return ids_.ids(); }
  /// Index of a live agent in state().agents and model().agents; throws on a stale or unknown id.
  int index_of(AgentId id) const { return ids_.at(id); }
  /// Takes an agent out of the session (it leaves the scene); its id becomes stale.
  void remove_agent(AgentId id);

  /// A robot asks for a task now (IMHuS request): the closest idle human within 3 m answers.
  void request(AgentId robot, int task);
  /// A robot will ask for a task at simulation time `time`.
  void schedule_request(double time, AgentId robot, int task);
  /// A textual command to a human, as SimVis3D's command interface: "walk X Y", "wait S",
  /// "turn_to RAD", "look_at NAME" (an agent or a location), "motion NAME [S]" (a motion primitive).
  /// It goes before whatever the human was doing, which starts again afterwards. Throws
  /// core::Error(bad_request) saying what is wrong.
  void command_human(AgentId human, std::string_view text);
  /// The action a command would give, checked but not given.
  scenario::Action parse_human_command(AgentId human, std::string_view text) const;
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
  const scenario::Model& model() const { return *model_; }
  const std::shared_ptr<const scenario::Model>& shared_model() const { return model_; }
  double time() const { return static_cast<double>(state_.tick) * model_->dt; }
  /// Hash of everything that changes, bit for bit.
  std::uint64_t state_hash() const;
  /// The same as 16 lower-case hex digits, as the API and stored episodes give it.
  std::string state_hash_hex() const;

 private:
  /// Whole ticks in a duration of simulation time.
  std::int64_t ticks(double seconds) const;
  void make_request(int robot, int task);
  void start_step(int step);
  void update_environment();
  void update_elevator(int elevator);
  void set_door(int door, DoorPhase phase);
  bool door_blocks(int door) const;
  bool someone_in_doorway(int door) const;
  std::vector<std::size_t> blocked_door_cells(double radius) const;
  void update_choreography();
  void update_requests();
  bool advance_agent(int agent);
  bool start_action(int agent, const scenario::Action& action, const PendingAction& pending);
  Vec2 formation_target(int agent) const;
  bool action_done(int agent, const scenario::Action& action);
  const scenario::Action& action_of(const PendingAction& pending) const;
  void finish_action(int agent);
  void go_to(int agent, const Pose2& goal, double radius, bool with_heading);
  bool plan_path(int agent);
  void release_reservations(int agent);
  bool slot_free(int space, int slot, int agent) const;
  bool idle(int agent) const;
  void locomotion();
  /// What a human's body is doing now: the inputs of its pose.
  humans::Activity activity(int agent) const;
  /// A human's gait, turn rate and motion primitive after it moved this step and turned by `turned`.
  void advance_body(AgentState& state, double turned) const;
  /// Robots with a model: their controllers pick a command (before the crowd moves).
  void decide_robots();
  /// Robots with a model: motors and bases advance; the agents follow their bases.
  void move_robots();
  /// The physics world: people's and robots' kinematic bodies follow them, objects move, grasps are
  /// made and released.
  void step_physics();
  void build_physics();
  /// Sensors of robots with a model read the world as it is after the step.
  void sense();
  /// The map, closed doors, people and other robots at `height`, as range sensors see them.
  sensors::RayScene range_scene(double height, int robot_agent) const;
  void emit(std::string kind, std::string subject, nlohmann::json data = nlohmann::json::object());

  std::shared_ptr<const scenario::Model> model_;
  double time_limit_;
  core::EntityTable<AgentTag, int> ids_;  ///< live agents → index
  State state_;
  humans::Crowd crowd_;
  std::vector<humans::CrowdAgent> crowd_agents_;
  std::vector<std::size_t> crowd_members_;  ///< agent index of each crowd entry (active agents)
  std::vector<Vec2> velocities_;
  std::vector<std::optional<double>> watching_headings_;  ///< per agent this tick: facing a watched robot
  std::vector<RobotRuntime> robots_;
  std::vector<std::optional<humans::Skeleton>> skeletons_;  ///< per agent: humans' bodies
  /// Per agent: the body last computed, for the tick and place it was computed at. A body depends
  /// on nothing else that changes within a tick. (Like the rest of a Session, not for several threads.)
  struct CachedBody {
    std::int64_t tick = -1;
    Vec2 position = Vec2::Zero();
    double heading = 0.0;
    humans::BodyCapsules body;
  };
  mutable std::vector<CachedBody> body_cache_;
  /// The Bullet world, when the scenario has a robot with a model or a movable object.
  std::unique_ptr<physics::PhysicsWorld> physics_;
  /// Per agent: the physics bodies of a human's capsules (robots: -1).
  std::vector<std::array<int, humans::kBodyPartCount>> human_bodies_;
  std::vector<int> door_bodies_;
  std::vector<int> disc_robot_bodies_;  ///< per agent: the body of a robot without a model, else -1
  std::vector<int> object_bodies_;
  std::vector<int> runtime_of_agent_;  ///< index into robots_ per agent, -1 for agents without a model
  world::PlanningHistory planning_history_;  ///< this session's own: its paths never depend on other sessions
};

}  // namespace hrisim::sim
