#pragma once
// A scenario compiled once into an immutable model that every session of it shares: the map with its
// grid, distance field and planner, named locations and social spaces, the agents' definitions, the
// routines, the steps and the asynchronous responses (IMHuS semantics, DESIGN.md §1).
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/math.hpp"
#include "scenario/activity_models.hpp"
#include "scenario/daily_schedules.hpp"
#include "humans/behaviour.hpp"
#include "humans/locomotion.hpp"
#include "robots/description.hpp"
#include "sensors/odometry.hpp"
#include "sensors/microphones.hpp"
#include "sensors/people_detector.hpp"
#include "sensors/sound_direction.hpp"
#include "world/occupancy_grid.hpp"
#include "world/outline.hpp"
#include "world/path_planner.hpp"

namespace hrisim::scenario {

using core::Pose2;
using core::Vec2;

/// Default simulation step, in seconds (seed 003 §5: physics at 60 Hz).
inline constexpr double kDefaultDt = 1.0 / 60.0;
/// Default episode time limit, in seconds.
inline constexpr double kDefaultTimeLimit = 300.0;
/// Goal tolerance of a location or pose without its own radius, in metres.
inline constexpr double kDefaultGoalRadius = 0.2;
/// Radius of a human or robot disc without its own, in metres (ORCA's default agent radius).
inline constexpr double kDefaultAgentRadius = 0.3;
/// Preferred walking speed drawn per human: mean and standard deviation, m/s (pedsim, after Helbing).
inline constexpr double kPreferredSpeedMean = 1.34;
inline constexpr double kPreferredSpeedStddev = 0.26;
/// Bounds of the drawn preferred speed, m/s, so no human stands still or sprints.
inline constexpr double kPreferredSpeedMin = 0.5;
inline constexpr double kPreferredSpeedMax = 2.0;
/// Replan when pushed this far from the planned path, in metres.
inline constexpr double kDefaultReplanDistance = 1.0;

/// Thickness of walls and doors that do not give one, in metres.
inline constexpr double kDefaultWallThickness = 0.1;

struct Location {
  std::string name;
  Pose2 pose;
  double radius = kDefaultGoalRadius;
};

/// A waiting line (Pedsim's <queue>): people join at its end, move up as the head is served, and are
/// served one at a time at the head.
/// People stand this far apart along the line, m (centre to centre: two 0.3 m bodies and 0.2 m between
/// them; pedsim_ros's random 0.2–0.8 m would overlap hrisim's bodies).
inline constexpr double kQueueSpacing = 0.8;
/// Mean time the person at the head is served, s: pedsim_ros draws Gamma(shape 2, scale 0.5).
inline constexpr double kQueueServiceTime = 1.0;
/// A person walking to the end of the line joins it within this distance of their place, m (pedsim_ros).
inline constexpr double kQueueJoinDistance = 2.0;
/// Service begins once the person at the head is this near the head, m (pedsim_ros).
inline constexpr double kQueueHeadTolerance = 0.3;

struct Queue {
  std::string name;
  Pose2 head;  ///< where the first person is served, facing the way everyone in the line faces
  double spacing = kQueueSpacing;
  double service_time = kQueueServiceTime;  ///< mean; each service is drawn from Gamma(shape 2, mean / 2)
  /// The place of the person `behind` people behind the head.
  Pose2 place(int behind) const { return core::compose(head, {-behind * spacing, 0.0, 0.0}); }
};

/// An area that draws passers-by in for a while (Pedsim's <attraction>, pedsim_ros's shopping): a
/// walking person within kAttractionReach of its centre turns aside with probability
/// kAttractionRate × strength × (1 − d / kAttractionReach) per second, walks to a random point of the
/// area, stays there an exponentially drawn time of mean 1 / kAttractionLeaveRate, then goes on.
inline constexpr double kAttractionReach = 7.0;
inline constexpr double kAttractionRate = 0.02;
inline constexpr double kAttractionLeaveRate = 0.03;

struct Attraction {
  std::string name;
  Vec2 centre = Vec2::Zero();
  double width = 1.0, height = 1.0;  ///< the area, along x and y, m
  double strength = 1.0;
};

struct SocialSpace {
  std::string name;
  Pose2 centre;
  std::vector<Pose2> slots;  ///< absolute poses, in the order they are taken
};

/// Height of walls, doors and obstacles without their own, m.
inline constexpr double kDefaultObstacleHeight = 2.0;

struct Obstacle {
  std::string name;
  std::vector<Vec2> polygon;
  double height = kDefaultObstacleHeight;
  std::map<std::string, Pose2> anchors;  ///< absolute poses
  /// How cameras draw it: a furniture mesh's name (empty: a box) filling the box `frame` (its centre
  /// and orientation) × length × width × height.
  std::string mesh;
  Pose2 frame;
  double length = 0.0, width = 0.0;
};

/// A place to sit: an obstacle's anchor (a chair's seat), its pose the seat's centre on the floor plan
/// and the way a person seated there faces. Every anchor of every obstacle is one, named
/// "obstacle/anchor" (just "obstacle" for an anchor named "seat").
struct Seat {
  std::string name;
  int obstacle = -1;
  Pose2 pose;
};
/// The anchor a sit_on action takes when it names only the obstacle.
inline constexpr const char* kDefaultSeatAnchor = "seat";

/// A door: a segment with thickness that blocks agents and paths while not fully open.
struct Door {
  std::string name;
  Vec2 from = Vec2::Zero();
  Vec2 to = Vec2::Zero();
  double thickness = kDefaultWallThickness;
  bool initially_open = false;
  double width() const { return (to - from).norm(); }
};

/// IMHuS's elevator plugin: door speed, how long a door stays open, trip time and its settling.
inline constexpr double kElevatorDoorSpeed = 0.5;
inline constexpr double kElevatorOpenTime = 10.0;
inline constexpr double kElevatorTravelTime = 3.0;
inline constexpr double kElevatorSettleTime = 1.0;
/// The doorway's light curtain sees a body this close to the door's leaves (or nearer), in metres: an
/// open door does not start closing, and a closing door opens again.
inline constexpr double kElevatorCurtainReach = 0.02;
/// A door reopened for someone standing in the doorway stays open at least this long, in seconds.
inline constexpr double kElevatorReopenHold = 2.0;
/// An open door waits up to this long past its open time for someone still on their way to a place in
/// the cabin or out through it, as riders hold the door for each other, in seconds.
inline constexpr double kElevatorPassengerHold = 30.0;

/// A cabin joining floors; door i serves floor i (IMHuS: door1 on floor 1, door2 on floor 2).
struct Elevator {
  std::string name;
  std::string topic = "/elevator";
  std::vector<int> doors;
  std::vector<int> social_spaces;  ///< reservations cleared whenever a door has closed
  int start_floor = 0;             ///< index into doors
  double door_speed = kElevatorDoorSpeed;
  double open_time = kElevatorOpenTime;
  double travel_time = kElevatorTravelTime;
  double settle_time = kElevatorSettleTime;
  std::string request_topic() const { return topic + "/request"; }
};

enum class AgentKind { human, robot };

/// Side-by-side distance between members walking together, m (about shoulder to shoulder with room).
inline constexpr double kFormationSpacing = 0.7;
/// Distance between rows of a group of more than three, m.
inline constexpr double kFormationRowGap = 0.8;
/// A harassing human stands this far in front of the robot, m (InHuS gives no value).
inline constexpr double kHarassDistance = 1.0;
/// A human with the stop-and-look attitude stops when the robot is this close, m (InHuS gives none).
inline constexpr double kStopAndLookDistance = 2.0;

struct Group {
  std::string name;
  std::vector<int> members;  ///< first member leads
};

/// A robot's built-in controller (when no external controller is connected). Every kind but idle and
/// teleop drives to its goal, if it has one, and along the choreography's gotos: goal by blind pure
/// pursuit, social, dwa, orca and social_force each with their local planner (docs/robots/controllers.md).
struct RobotController {
  enum class Kind { idle, goal, social, teleop, dwa, orca, social_force, search };
  /// How the search controller orders the rooms: by the person's presence probability at the
  /// current hour, or the nearest unvisited room next (a sweep that knows nothing of the person).
  enum class SearchStrategy { presence, sweep };
  Kind kind = Kind::idle;
  std::optional<Pose2> goal;  ///< where to drive, if anywhere
  double goal_radius = kDefaultGoalRadius;
  int search_person = -1;  ///< search: the human to find
  SearchStrategy search_strategy = SearchStrategy::presence;
};

struct AgentDef {
  std::string id;
  AgentKind kind = AgentKind::human;
  Pose2 start;
  double radius = kDefaultAgentRadius;
  std::optional<double> preferred_speed;  ///< drawn per session when absent
  humans::LocalAvoidance avoidance = humans::LocalAvoidance::orca;
  std::string type = "adult";
  int activity_model = -1;  ///< a human living by an activity model once the choreography is over, or -1
  int daily_schedule = -1;  ///< a human living by a daily schedule once the choreography is over, or -1
  humans::Behaviour behaviour;  ///< how a human reacts to a robot in view (HuNavSim)
  double enters_at = 0.0;  ///< s: a human out of the scene until then, who then appears at `start` (a Pedsim source's later people)
  // Robots with a model (a robot without one is a disc moved by choreography or velocity commands).
  std::shared_ptr<const robots::RobotDescription> robot_model;
  RobotController controller;
  std::optional<sensors::PeopleDetectorParams> people_detector;
  /// Its description's microphone array listens (the scenario's `microphones`), with its direction of arrival.
  std::optional<sensors::MicrophonesParams> microphones;
  sensors::DoaParams sound_direction;
  sensors::OdometryParams odometry;
  std::map<std::string, double> initial_joints;  ///< overrides of the model's initial joint positions
};

/// A movable object: a dynamic body in the session's physics world.
struct MovableObject {
  std::string name;
  robots::Shape shape;
  double mass = 0.0;
  core::Pose3 pose;  ///< its centre at the start
};

struct Action {
  enum class Kind {
    go_to_location,      ///< target: location, pose: offset in the location's frame
    go_to_social_space,  ///< target: social space; the first free slot
    go_to_pose,          ///< pose, radius
    wait_duration,       ///< value: seconds
    wait_message,        ///< topic, message
    look_at_angle,       ///< value: heading
    look_at_agent,       ///< target: agent
    look_at_location,    ///< target: location
    look_at_object,      ///< target: a movable object, or -1 and pose: a piece of furniture's centre
    turn_by,             ///< value: angle
    turn_to,             ///< value: heading
    publish,             ///< topic, message
    run_routine,         ///< target: routine
    form_group,          ///< target: group; members
    dismantle_group,     ///< target: group
    harass,              ///< target: robot; value: duration; radius: distance in front of it
    stop_and_look,       ///< target: robot; value: duration; radius: distance that stops the human
    request,             ///< target: routine a robot asks a human to run
    play_motion,         ///< motion: a shipped motion primitive; value: seconds it plays
    set_behaviour,       ///< target: a humans::BehaviourType, taken with its defaults (a command)
    say,                 ///< value: seconds; target: a clip (the scenario's `clips`), or -1 for synthetic speech
    sit_on,              ///< target: a seat (Model::seats)
    pick_up,             ///< target: a movable object
    put_down,            ///< pose: where the carried object goes (x, y); value: the height of the surface it rests on
    join_queue,          ///< target: a queue; done once served at its head
    leave,               ///< the human leaves the scene (a Pedsim sink)
  };
  Kind kind = Kind::wait_duration;
  int agent = -1;   ///< acting agent in steps; -1 in routines (the invoker acts) and group actions
  int group = -1;   ///< acting group in steps (goto only), or -1
  std::vector<int> members;  ///< form_group: the new members
  int target = -1;  ///< index of the location, social space, agent or routine
  Pose2 pose;
  double radius = kDefaultGoalRadius;
  double value = 0.0;
  std::string topic;
  std::string message;
  std::string motion;   ///< play_motion: the primitive's name
  bool repeat = false;  ///< run_routine: over and over until the episode ends (a Pedsim route, HuNavSim's cyclic goals)
  std::string pointer;  ///< where it stands in the scenario (JSON pointer, with the current keys), for events and errors
};

/// A routine, IMHuS's compound task (the scenario file's "routines"): actions an agent performs in order.
struct Routine {
  std::string name;
  std::vector<Action> actions;
};

struct Step {
  std::string name;
  std::vector<Action> actions;
};

struct Request {
  double time = 0.0;
  int routine = -1;  ///< the routine a human is asked to run
  int robot = -1;
};

/// The benchmark tasks of seed 003 §4.4 (the HSR human–robot interaction benchmark).
enum class TaskKind { approach_human, follow_human, approach_human_apartment, pick_and_place, mirror_gesture };

/// Whether a benchmark task ends at a goal condition (the robot reaching its human), which is then its
/// episode's success; the others run their episode's length and are measured by their reward.
constexpr bool has_goal_condition(TaskKind kind) { return kind == TaskKind::approach_human || kind == TaskKind::approach_human_apartment; }

// Episode settings of seed 003 §5.3 (Tables 5.2 and 5.3).
/// Physics ticks per environment step of the navigation tasks and gesture mirroring.
inline constexpr int kTaskFrameSkip = 10;
/// Physics ticks per pick-and-place step (Table 5.3): a gripper step uses kPickGripperFrames of them,
/// an arm step the rest.
inline constexpr int kPickFrameSkip = 128;
inline constexpr int kPickGripperFrames = 8;
/// Ticks in an episode of the navigation tasks (256 × 6, Table 5.2).
inline constexpr int kNavigationEpisodeLength = 1536;
/// Ticks in an episode of pick and place (128 × 2, Table 5.3) and gesture mirroring (§5.3.5).
inline constexpr int kShortEpisodeLength = 256;
// Rewards and endings (seed 003 §4.4).
/// approach_human: the human stands at a uniform random point of [−5, 5]², m.
inline constexpr double kSpawnHalfWidth = 5.0;
/// The episode is done when the robot is closer than this to the human, m (§4.4.1.4).
inline constexpr double kReachDistance = 0.3;
/// Closer than this, robot and human collide (−20, §4.4.1.6), m.
inline constexpr double kHumanCollisionDistance = 0.1;
inline constexpr double kHumanCollisionPenalty = 20.0;
/// Each named obstacle or object the robot touches during a step costs this (§4.4.3.5, §4.4.4.4).
inline constexpr double kObstacleCollisionPenalty = 0.5;
/// Pick and place: the distance terms reward gripper–object and object–target distances below this, m.
inline constexpr double kPickRewardRange = 0.5;
/// Pick and place: weight of the object–target term.
inline constexpr double kPlaceRewardWeight = 2.0;
/// follow_human: the human starts this far ahead of the robot, m (the seed puts both at the origin).
inline constexpr double kFollowLeadDistance = 1.0;
/// Gesture mirroring: the human stands this far in front of the robot, facing it, m.
inline constexpr double kMirrorHumanDistance = 2.0;
/// Gesture mirroring: the robot points to a side when its hand is this far from its base's centre
/// towards that side, m (the arm hanging down reaches 0.08 m; stretched sideways about 0.6 m).
inline constexpr double kPointingReach = 0.3;
/// Gesture mirroring: size of the camera image observed, pixels (§4.4.5.1).
inline constexpr int kMirrorImageSize = 256;

/// A walking style of follow_human's human: a name and a walking speed.
struct WalkingStyle {
  std::string name;
  double speed = 0.0;  ///< m/s
};

/// A scenario's benchmark task: which one, its agents and its settings (defaults from seed 003).
struct TaskSettings {
  TaskKind kind = TaskKind::approach_human;
  std::string name;
  int robot = -1;  ///< agent index of the robot under test (an HSR-like robot with a drive)
  int human = -1;  ///< agent index of the human (-1 for pick_and_place)
  int frame_skip = kTaskFrameSkip;
  int gripper_frames = kPickGripperFrames;
  int max_episode_length = kNavigationEpisodeLength;
  Vec2 spawn_min{-kSpawnHalfWidth, -kSpawnHalfWidth}, spawn_max{kSpawnHalfWidth, kSpawnHalfWidth};
  double reach_distance = kReachDistance;
  double collision_distance = kHumanCollisionDistance;
  double collision_penalty = kHumanCollisionPenalty;
  double obstacle_penalty = kObstacleCollisionPenalty;
  /// Obstacles and movable objects whose contact with the robot costs obstacle_penalty, by name.
  std::vector<std::string> penalised;
  std::vector<WalkingStyle> walking_styles;
  double lead_distance = kFollowLeadDistance;
  int object = -1;         ///< pick_and_place: the movable object to carry
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  ///< pick_and_place: where to put it (map frame)
  double reward_range = kPickRewardRange;
  double place_weight = kPlaceRewardWeight;
  double human_distance = kMirrorHumanDistance;
  double pointing_reach = kPointingReach;
  std::string camera = "head_rgbd";  ///< mirror_gesture: the robot's camera observed
  int image_width = kMirrorImageSize, image_height = kMirrorImageSize;
};

/// follow_human's walking styles (the seed draws one of its animation set's walking modes).
std::vector<WalkingStyle> default_walking_styles();
/// The task a scenario's task section names (nullopt for an unknown name).
std::optional<TaskKind> task_kind(std::string_view name);

struct Model {
  Model(world::OccupancyGrid grid_in) : grid(std::move(grid_in)), field(grid), planner(grid, field) {}
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;

  std::string name;
  std::string description;
  double dt = kDefaultDt;
  double time_limit = kDefaultTimeLimit;

  world::OccupancyGrid grid;
  world::DistanceField field;
  world::PathPlanner planner;  ///< refers to grid and field above
  std::vector<Obstacle> obstacles;
  std::vector<Seat> seats;  ///< every obstacle's anchors, in the obstacles' order
  /// The static map as segments for range sensors: the obstacles' exact edges, or for a map from an
  /// image the outline of its occupied cells.
  std::vector<world::Segment> outline;
  bool map_from_image = false;  ///< the map came as a ROS map (outline of cells), not as geometry
  std::vector<Door> doors;
  std::vector<Elevator> elevators;

  std::vector<Location> locations;
  std::vector<SocialSpace> social_spaces;
  std::vector<Queue> queues;
  std::vector<Attraction> attractions;
  std::vector<AgentDef> agents;  ///< humans then robots, each in file order
  std::vector<MovableObject> objects;
  std::vector<Group> groups;     ///< declared groups (members at the start) and groups formed later (empty)
  std::vector<Routine> routines;  ///< IMHuS compound tasks (the file's "routines")
  std::vector<Step> steps;
  std::vector<int> async_routines;  ///< routines humans run when a robot requests them
  std::vector<Request> requests;  ///< scripted robot requests, by time
  std::vector<ActivityModel> activity_models;
  std::optional<Clock> clock;  ///< the time of day, when the scenario keeps one
  std::vector<Room> rooms;
  std::vector<DailySchedule> daily_schedules;
  /// Sound clips people can say (WAV files, resampled to sensors::kSampleRate), by name.
  std::vector<std::pair<std::string, std::shared_ptr<const sensors::AudioClip>>> clips;
  /// Some robot listens: only then does the session keep the sounds people, doors and elevators make.
  bool heard = false;

  std::optional<TaskSettings> task;  ///< a benchmark task; the episode then ends by it or its length

  humans::OrcaParams orca;
  humans::SocialForceParams social_force;
  humans::PersonalSpace personal_space;
  humans::Headway headway;
  double replan_distance = kDefaultReplanDistance;

  int find_agent(const std::string& id) const;
  int find_routine(const std::string& name) const;
  /// IMHuS's LookAt an object: at a movable object (followed where it has been moved) or at a piece of
  /// furniture's (an obstacle's) centre; none by that name.
  std::optional<Action> look_at_object(const std::string& name) const;
  /// The seat an obstacle's anchor gives (kDefaultSeatAnchor when `anchor` is empty), or -1.
  int find_seat(const std::string& obstacle, const std::string& anchor) const;
  /// Saying one of the scenario's clips, for its length; none by that name.
  std::optional<Action> say_clip(const std::string& name) const;
};

}  // namespace hrisim::scenario
