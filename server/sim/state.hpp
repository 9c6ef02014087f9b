#pragma once
// Everything about a running scenario that changes: agents, choreography progress, topics, robot
// requests, events, robots' runtimes, movable objects, the planner's history, the benchmark task's
// bookkeeping. The Model it runs is shared and immutable; the session's engines (the Bullet world,
// the crowd solver) are set from it.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Geometry>

#include "core/index.hpp"
#include "core/math.hpp"
#include "core/random.hpp"
#include "humans/motion.hpp"
#include "sensors/sound.hpp"
#include "sim/event_types.hpp"
#include "sim/robot_runtime.hpp"
#include "sim/task_state.hpp"
#include "world/path_planner.hpp"

namespace hrisim::sim {

using core::Pose2;
using core::Vec2;

/// An action waiting or running for one agent; routines are expanded when they start.
/// PendingAction::routine of an action given by a command (index into State::commanded).
inline constexpr int kCommandedAction = -2;
/// PendingAction::routine of the activity a person's activity model chose (index: the person, whose
/// AgentState::activity_action it is).
inline constexpr int kActivityAction = -3;

struct PendingAction {
  int routine = -1; ///< routine the action belongs to, -1 for a step action, kCommandedAction
  int index = -1;   ///< index of the action in the step or routine
  int step = -1;    ///< step it belongs to; -1 when it answers a robot request
  int role = 0;     ///< place in the group for a group action (0 leads)
  int group_size = 1;
  int group = -1;   ///< the group acting (a group action, or a compound task given to a group), or -1

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(routine, index, step, role, group_size, group); }
};

/// Where a person is in sitting on a seat (scenario::Seat) or leaving it: walking to the free spot in
/// front of it, stepping back onto the seat's spot, sitting down, seated, standing up, stepping off.
enum class SeatPhase { none, approaching, stepping_in, sitting, seated, standing_up, stepping_out };

/// Where a person is in a pick_up or put_down: walking to a spot within reach, reaching, done.
enum class ReachPhase { none, walking, reaching, done };

/// Indices into the model's lists (Model::agents, seats, objects, …) that the state refers to.
using AgentIndex = core::Index<struct AgentList>;
using LocationIndex = core::Index<struct LocationList>;
using SpaceIndex = core::Index<struct SocialSpaceList>;
using SlotIndex = core::Index<struct SlotList>;  ///< a slot of a social space
using QueueIndex = core::Index<struct QueueList>;
using ActivityIndex = core::Index<struct ActivityList>;  ///< an activity of the person's activity model
using RoomIndex = core::Index<struct RoomList>;          ///< a room of the person's daily schedule
using SeatIndex = core::Index<struct SeatList>;
using ObjectIndex = core::Index<struct ObjectList>;  ///< a movable object

/// Where an agent's usual planning clearance failed (plan_path): the narrower clearance a person's
/// path needs through a passage only as wide as their body, and whether their last plan started from
/// the nearest free cell because their own spot was unplannable. Hashed only when either is set, so a
/// session that never needed them hashes as it did before they existed (the golden hashes).
struct PlanningFallback {
  double body_clearance = 0.0;  ///< the clearance the path was planned with when the radius found none; 0: the radius
  bool from_free_cell = false;  ///< replanned from the nearest free cell (said once, until a plan starts where the agent stands)

  bool operator==(const PlanningFallback&) const = default;
};

/// Walking to a goal: the goal, the path planned to it and the leg under way, and the progress made.
struct Navigation {
  bool under_way = false;  ///< walking to `goal`: false once there (or never sent)
  Vec2 goal = Vec2::Zero();
  double goal_radius = 0.0;
  std::optional<double> goal_heading;
  std::vector<Vec2> path;
  std::size_t path_index = 0;
  Vec2 leg_start = Vec2::Zero();     ///< where the leg towards path[path_index] began
  std::int64_t replan_at_tick = -1;  ///< when no path was found, try again at this tick
  std::int64_t planned_tick = 0;     ///< when the current path was planned
  // Progress towards the goal: the nearest it has come, when it last came kStuckProgress closer, and
  // whether "stuck" was said since.
  double nearest_to_goal = 0.0;
  std::int64_t progress_tick = 0;
  bool stuck_reported = false;
  std::optional<Vec2> hold;  ///< where the agent arrived last; it steps back there when pushed away
  PlanningFallback fallback;

  auto fields() const {
    return std::tie(under_way, goal, goal_radius, goal_heading, path, path_index, leg_start, replan_at_tick, planned_tick, nearest_to_goal,
                    progress_tick, stuck_reported, hold, fallback);
  }
};

/// How the agent stands towards others: whom it follows, blocks, watches or faces.
struct Attitude {
  AgentIndex follow_leader;               ///< walking in formation behind or beside this agent
  Vec2 formation_offset = Vec2::Zero();   ///< own spot in the leader's frame (x ahead, y left)
  AgentIndex harass_robot;                ///< standing in this robot's way
  double harass_distance = 0.0;
  AgentIndex watched_robot;               ///< stop-and-look: stops and faces this robot when it is near
  double watch_distance = 0.0;
  std::int64_t watch_until_tick = 0;
  std::optional<double> target_heading;   ///< turning in place towards this
  AgentIndex look_at_agent;               ///< keeps facing this agent while the action runs

  auto fields() const {
    return std::tie(follow_leader, formation_offset, harass_robot, harass_distance, watched_robot, watch_distance, watch_until_tick,
                    target_heading, look_at_agent);
  }
};

/// The spot a person holds: a location, or a slot of a social space (a cabin, a group's circle).
struct Reservation {
  LocationIndex location;
  SpaceIndex space;
  SlotIndex slot;  ///< of `space`

  auto fields() const { return std::tie(location, space, slot); }
};

/// Standing in a waiting line (Model::queues) for a join_queue.
struct Queueing {
  QueueIndex queue;      ///< the line the join_queue is for
  int place = -1;        ///< place in that line (0: at its head); -1 until they have joined it
  bool served = false;   ///< served at the head of the line: the join_queue action is done

  auto fields() const { return std::tie(queue, place, served); }
};

/// Reacting to robots and to the crowd: being touched, giving up personal space, and HuNavSim's
/// behaviours (the behaviour, how long a robot has been in view during the reaction under way,
/// whether a once-only reaction is spent, and the robot reacted to).
struct Reaction {
  std::int64_t startled_tick = -1;  ///< when a robot last touched this person, -1 before
  /// Share (0…1) of their personal-space margins a person keeps: it falls while others hold them up
  /// and comes back once they walk freely (squeezing past in a narrow place).
  double personal_space = 1.0;
  humans::Behaviour behaviour;
  double behaviour_seen = 0.0;
  bool behaviour_spent = false;
  AgentIndex reacting_to;

  auto fields() const { return std::tie(startled_tick, personal_space, behaviour, behaviour_seen, behaviour_spent, reacting_to); }
};

/// Living by an activity model (the activity under way and what it asks for, drawn from the person's
/// own stream, so that nobody else's choices change theirs) or by a daily schedule (the room of the
/// stay under way, whether the person has set off to it, and the tick the stay ends).
struct Living {
  ActivityIndex activity;  ///< none before the first
  scenario::Action activity_action;
  core::Random activity_random;
  RoomIndex room;          ///< none before the first stay
  bool in_room = false;    ///< set off to the room (a spot reserved)
  std::int64_t stay_until_tick = -1;

  auto fields() const { return std::tie(activity, activity_action, activity_random, room, in_room, stay_until_tick); }
};

/// The body's animation (humans::Activity): the gait advanced by the distance walked, the turn rate,
/// the motion primitive played, and the steps walked for footfalls.
struct Animation {
  double gait_distance = 0.0;  ///< m, within one walk cycle
  double turn_rate = 0.0;      ///< rad/s in the last step
  const humans::MotionClip* motion = nullptr;  ///< a shipped primitive (its pose held once it ends)
  std::int64_t motion_tick = 0;                ///< when it started
  std::int64_t motion_released_tick = -1;      ///< when the person walked off (it blends out), -1 before
  double step_phase = 0.0;  ///< steps walked, for their footfalls (sensors::footfalls), when a robot listens

  auto fields() const { return std::tie(gait_distance, turn_rate, motion, motion_tick, motion_released_tick, step_phase); }
};

/// Sitting: the seat walked to, sat on or being left, how far along, and the free spot in front of it
/// the person came from and steps back to.
struct Seating {
  SeatIndex seat;
  SeatPhase phase = SeatPhase::none;
  Vec2 front = Vec2::Zero();

  auto fields() const { return std::tie(seat, phase, front); }
};

/// Carrying: the movable object in the right hand, and how far along a pick_up or put_down under way is.
struct Carrying {
  ObjectIndex object;
  ReachPhase phase = ReachPhase::none;

  auto fields() const { return std::tie(object, phase); }
};

struct AgentState {
  bool active = true;  ///< in the scene: false before a human's enters_at and once they have left
  bool left = false;   ///< left the scene (a leave action, or removed): never back, whatever enters_at says
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double heading = 0.0;
  double preferred_speed = 0.0;
  bool rooted = false;  ///< stands its ground: never moves, whoever comes (others still avoid it)
  Vec2 commanded_velocity = Vec2::Zero();  ///< robots without a model: from the controller

  std::deque<PendingAction> program;  ///< front is running (when started) or next
  bool action_started = false;
  std::int64_t wait_until_tick = 0;
  std::int64_t awaited_request = 0;  ///< a robot's request action waits until this request is resolved
  bool answering_request = false;

  Navigation navigation;
  Attitude attitude;
  Reservation reservation;
  Queueing queueing;
  Reaction reaction;
  Living living;
  Animation animation;
  Seating seating;
  Carrying carrying;

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const {
    return std::tie(active, left, position, velocity, heading, preferred_speed, rooted, commanded_velocity, program, action_started,
                    wait_until_tick, awaited_request, answering_request, navigation, attitude, reservation, queueing, reaction, living,
                    animation, seating, carrying);
  }
};

/// A robot request waiting for an idle human (IMHuS's asynchronous step).
struct OpenRequest {
  std::int64_t id = 0;
  int robot = -1;
  int routine = -1;
  Vec2 position = Vec2::Zero();  ///< the robot's position when it asked
  std::int64_t asked_tick = 0;
  std::int64_t next_try_tick = 0;

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(id, robot, routine, position, asked_tick, next_try_tick); }
};

/// A robot request to be made at a given simulation time (scripted in the scenario or the command line).
struct ScheduledRequest {
  double time = 0.0;
  int robot = -1;
  int routine = -1;

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(time, robot, routine); }
};

struct StepRecord {
  std::int64_t started_tick = -1;
  std::int64_t finished_tick = -1;

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(started_tick, finished_tick); }
};

/// A movable object as the physics world left it after the last step.
struct ObjectState {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// m/s and rad/s in the map frame: a physics world built again from the state goes on from them.
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  auto fields() const { return std::tie(pose, linear_velocity, angular_velocity); }
};

struct DoorState {
  DoorPhase phase = DoorPhase::closed;
  double opening = 0.0;  ///< 0 closed … 1 fully open

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(phase, opening); }
};

struct ElevatorState {
  enum class Phase { idle, opening, open, closing, travelling };
  Phase phase = Phase::idle;
  int floor = 0;                    ///< the floor the cabin is at (index of its door)
  std::deque<int> queue;            ///< requested floors, served in order
  std::int64_t until_tick = 0;      ///< end of the open period or of the trip
  std::int64_t reopened_until_tick = 0;  ///< a door reopened for someone in the doorway stays open until then
  int destination = 0;              ///< floor of the trip under way

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(phase, floor, queue, until_tick, reopened_until_tick, destination); }
};

/// A waiting line (scenario::Queue) as it stands.
struct QueueState {
  std::vector<int> line;                 ///< the people in it, the head first
  std::int64_t served_until_tick = -1;   ///< the head's service ends then; -1 until they stand at the head
  core::Random random;                   ///< the line's own stream of service times

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(line, served_until_tick, random); }
};

/// A message published during the current tick, for subscribers that need every message.
struct Message {
  std::string topic;
  std::string text;

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(topic, text); }
};

/// Why an episode's simulation finished: its choreography's last step ended, its time limit came, or
/// its goal was reached (a search found the person, the benchmark task ended it).
enum class Termination { none, scenario_end, timeout, goal };
/// The termination's name in the API and the store; "" while running.
constexpr std::string_view to_string(Termination termination) {
  switch (termination) {
    case Termination::none: return "";
    case Termination::scenario_end: return "scenario_end";
    case Termination::timeout: return "timeout";
    case Termination::goal: return "goal";
  }
  return "";
}

struct State {
  std::int64_t tick = 0;
  std::vector<AgentState> agents;
  int current_step = 0;  ///< index of the choreography step under way; == steps.size() when all have finished
  std::vector<StepRecord> steps;
  std::map<std::string, std::string> topics;  ///< latest message per topic
  std::vector<Message> inbox;                 ///< messages published since the environment last read them
  std::vector<std::vector<int>> groups;  ///< current members of each group of the model
  std::vector<DoorState> doors;
  std::vector<ElevatorState> elevators;
  std::vector<QueueState> queues;
  std::vector<OpenRequest> requests;
  std::int64_t next_request_id = 1;
  std::vector<ScheduledRequest> scheduled;  ///< robot requests still to come, by time
  std::vector<Event> events;
  std::uint64_t events_digest = 0;  ///< hash of every event so far, kept by emit() (the hash reads this, not each event)
  std::vector<scenario::Action> commanded;  ///< actions given by textual commands, in order
  core::Random random;
  core::Random attraction_random;  ///< who is drawn to an attraction, where to and for how long
  /// Robots with a model: motors, controllers, sensor readings and their random streams.
  std::vector<RobotRuntime> robots;
  /// Movable objects after the last physics step (the physics world moves them).
  std::vector<ObjectState> objects;
  /// What the planner searched already: later plans to the same goal follow its field.
  world::PlanningHistory planning_history;
  double time_limit = 0.0;  ///< s of simulation time; the episode ends there
  double clock_start = 0.0;  ///< the scenario clock's time of day at t = 0 (drawn when the scenario says), s
  /// Sounds still audible somewhere, when a robot listens (Model::heard), and who says each (a
  /// person's speech moves with them; -1 for other sounds).
  std::vector<sensors::SoundSource> sounds;
  std::vector<int> speakers;
  bool finished = false;
  Termination termination = Termination::none;  ///< why it finished
  /// The benchmark task's bookkeeping (its random stream, what it counted and measured): a copy of the
  /// state carries it, so the task itself is configuration only.
  TaskState task;

  /// Every member, in order: the state hash (and anything else that must see all of it) walks these.
  auto fields() const { return std::tie(tick, agents, current_step, steps, topics, inbox, groups, doors, elevators, queues, requests, next_request_id, scheduled, events, events_digest, commanded, random, attraction_random, robots, objects, planning_history, time_limit, clock_start, sounds, speakers, finished, termination, task); }
};

/// Hash of everything in the state, bit for bit.
std::uint64_t state_hash(const State& state);
/// The bytes of data the state holds, as its hash reads them: its events count as their number alone
/// (their content is digested as they happen), containers' overhead not at all.
std::size_t state_data_bytes(const State& state);
/// A state hash as 16 lower-case hex digits, as the API and stored episodes give it.
std::string hash_hex(std::uint64_t hash);

}  // namespace hrisim::sim
