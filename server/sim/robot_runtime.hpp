#pragma once
// Robots with a model in a session: their motors and base (robots::Robot), the built-in controller
// that commands them when no external controller is connected, and their sensors — lasers, people
// detector, odometry, bumper — which read the world after each step, each at its own rate and from
// its own random stream.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "core/state_hash.hpp"
#include "humans/body.hpp"
#include "robots/robot.hpp"
#include "scenario/model.hpp"
#include "sensors/laser.hpp"
#include "sensors/microphones.hpp"
#include "sensors/sound_direction.hpp"
#include "sensors/odometry.hpp"
#include "sensors/people_detector.hpp"

namespace hrisim::sim {

using core::Pose2;
using core::Vec2;

/// The people detector looks at this height, m (mid-torso of an adult)...
inline constexpr double kPeopleDetectorHeight = 1.15;
/// ...and reports a person as a disc of this radius, m.
inline constexpr double kPersonRadius = 0.2;

/// A range sensor reading in ROS LaserScan's terms (REP 117 for out-of-range values).
struct LaserReading {
  std::string sensor;
  std::int64_t tick = -1;  ///< when it was taken; -1 before the first
  Pose2 pose;              ///< the sensor's pose in the map frame when it was taken
  double height = 0.0;     ///< m above the floor
  double angle_min = 0.0, angle_increment = 0.0, range_min = 0.0, range_max = 0.0;
  std::vector<double> ranges;
};

struct PeopleReading {
  std::int64_t tick = -1;
  std::vector<sensors::Detection> people;
};

struct OdometryReading {
  std::int64_t tick = -1;
  Pose2 pose;
  robots::Twist twist;
};

/// Named defaults of the inertial and force sensors (docs/robots/sensors.md): hrisim's own, of a
/// MEMS IMU and a 6-axis wrist sensor's order of magnitude (the HSR's models are not published).
inline constexpr double kImuAccelerationNoise = 0.02;  ///< m/s², standard deviation per reading
inline constexpr double kImuGyroNoise = 0.002;         ///< rad/s
inline constexpr double kForceNoise = 0.05;            ///< N
inline constexpr double kTorqueNoise = 0.002;          ///< N·m

/// An IMU's reading in its own frame (REP 145): the specific force (gravity included, +9.81 m/s²
/// along its up axis at rest) and the angular velocity, over the last tick; its orientation in the map.
struct ImuReading {
  std::string sensor;
  std::int64_t tick = -1;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero(), linear_acceleration = Eigen::Vector3d::Zero();
};

/// A force/torque sensor's reading in its own frame: the wrench the links beyond it receive from
/// outside — a held object's load and the contacts the physics world resolves — about its origin.
struct ForceTorqueReading {
  std::string sensor;
  std::int64_t tick = -1;
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
};

/// Something the robot's body touches.
struct Contact {
  int agent = -1;    ///< the human or robot touched, or -1
  int object = -1;   ///< the movable object touched, or -1 (neither: the map)
  std::string part;  ///< a human's body part (l_shin, torso, …); another robot's link; the object's or obstacle's name
  bool operator==(const Contact&) const = default;
};

/// A sensor and when it reads next.
struct Schedule {
  double period = 0.0;        ///< s
  std::int64_t next_tick = 0;
};

/// A robot with a model and everything the session keeps for it.
struct RobotRuntime {
  RobotRuntime(int agent_index, const scenario::AgentDef& def, double dt, const core::Random& session_random);

  struct LaserSensor {
    const robots::Sensor* mount;  ///< in the robot's description
    sensors::Laser laser;
    Schedule schedule;
    LaserReading reading;
  };

  struct ImuSensor {
    const robots::Sensor* mount;
    Eigen::Isometry3d last_pose;     ///< where it was a tick ago
    Eigen::Vector3d last_velocity;   ///< m/s, map frame, over the tick before
    ImuReading reading;
  };
  struct ForceTorqueSensor {
    const robots::Sensor* mount;
    std::vector<int> links;  ///< its link and every link beyond it
    ForceTorqueReading reading;
  };

  int agent;
  robots::Robot robot;
  scenario::RobotController controller;
  robots::Twist command;  ///< teleoperation (or an external controller): held until changed
  core::Random motor_random, sensor_random;
  std::vector<LaserSensor> lasers;  ///< laser and infrared sensors, in description order
  std::vector<ImuSensor> imus;
  std::vector<ForceTorqueSensor> force_torque_sensors;
  std::optional<sensors::PeopleDetector> people_detector;
  Schedule people_schedule;
  PeopleReading people;
  sensors::Odometry odometry;
  Schedule odometry_schedule;
  OdometryReading odometry_reading;
  std::vector<Contact> contacts;  ///< what the body touches now
  int held_object = -1;           ///< the object its gripper holds
  /// The grasp it holds the object by: where the gripper joint came to rest on it, and the line
  /// between the two fingers' contacts (in the palm body's frame).
  std::int64_t grasped_at = 0;  ///< tick
  double grip_position = 0.0;
  Eigen::Vector3d grip_from = Eigen::Vector3d::Zero(), grip_to = Eigen::Vector3d::Zero();
  /// Its grip slipped: it grasps again only after opening.
  bool slipped = false;
  /// Its microphone array, when the scenario has it listen: the last tick's block, the recent samples
  /// the direction of arrival reads, and its latest reading (in the array link's frame).
  struct Hearing {
    sensors::Microphones microphones;
    sensors::DirectionOfArrival direction;
    sensors::AudioHistory history;
    sensors::AudioBlock block;
    Schedule direction_schedule;
    std::optional<sensors::DoaReading> reading;
    std::int64_t reading_tick = -1;
    core::Random random;
  };
  std::optional<Hearing> hearing;
  /// Where the microphone array's link is now (map frame); the robot must listen.
  Eigen::Isometry3d microphones_pose() const;
  /// The search controller's progress: the rooms looked into, the room it goes to or looks around in,
  /// how far it has turned there, and whether it found the person.
  struct Search {
    std::vector<std::uint8_t> looked_into;
    int room = -1;
    bool scanning = false;
    double turned = 0.0, last_heading = 0.0;
    double closest = 0.0;              ///< to the lookout so far, m
    std::int64_t closer_tick = 0;      ///< when it last came kSearchProgress closer
    bool found = false;
  } search;

  void hash(core::StateHasher& hasher) const;
};

/// True when a sensor with this schedule reads at `tick` (and moves its schedule on).
bool due(Schedule& schedule, std::int64_t tick, double dt);

/// Height of the cylinder that stands for a robot without a model in the physics world, m.
inline constexpr double kDiscRobotHeight = 1.0;

/// A human's body where it crosses the plane at `height`, as range sensors see it: each capsule's
/// cross-section as circles (one for a limb crossing the plane steeply, a row along one lying in it).
void add_human_body(sensors::RayScene& scene, const humans::BodyCapsules& body, double height);

}  // namespace hrisim::sim
