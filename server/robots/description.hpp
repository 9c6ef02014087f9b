#pragma once
// Robot descriptions: links with collision shapes, joints with type, axis, limits and motor model,
// sensors with their mounting pose, the base drive and the controllers' joint groups. Read from JSON
// (api/robot.schema.json) by one loader; HSR, ARTOS and ROMAN ship in assets/robots/ and inside the
// binary.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "core/json_schema.hpp"
#include "core/math.hpp"
#include "robots/differential_drive.hpp"
#include "robots/motor.hpp"

namespace hrisim::robots {

using core::Pose3;

struct Shape {
  enum class Kind { box, cylinder, sphere, capsule };
  Kind kind = Kind::box;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< box: x, y, z lengths
  double radius = 0.0;                             ///< cylinder, sphere, capsule
  double length = 0.0;                             ///< cylinder, capsule: along the link's z
};

struct Link {
  std::string name;
  std::optional<Shape> collision;
  Pose3 collision_origin;  ///< the shape's centre in the link frame
  double mass = 0.0;       ///< kg
};

enum class JointType { fixed, revolute, continuous, prismatic };

struct Joint {
  std::string name;
  JointType type = JointType::fixed;
  std::string parent, child;  ///< link names
  Pose3 origin;               ///< child frame in the parent frame at joint position 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  JointLimits limits;         ///< revolute and prismatic
  MotorParams motor;          ///< the actuator behind the joint (none for fixed and mimic joints)
  /// Follows another joint: position = multiplier × its position + offset.
  struct Mimic {
    std::string joint;
    double multiplier = 1.0;
    double offset = 0.0;
  };
  std::optional<Mimic> mimic;
  double initial = 0.0;       ///< position at the start, rad or m
};

/// What a camera's "camera" settings say about its image (api/robot.schema.json); these defaults where
/// it says nothing.
struct CameraSettings {
  int width = 640, height = 480;  ///< px
  double horizontal_fov = 1.047;  ///< rad
  double near = 0.05, far = 20.0;  ///< m
  double rate = 30.0;             ///< Hz
};

/// What a laser's or infrared sensor's "laser" settings say (api/robot.schema.json); what is absent
/// keeps the defaults of the sensor's type (sensors::LaserParams, sensors::infrared_defaults()).
struct RangeSettings {
  std::optional<double> field_of_view;  ///< rad
  std::optional<int> beams;
  std::optional<double> min_range, max_range, range_noise;  ///< m
  std::optional<double> rate;  ///< Hz
};

struct Sensor {
  std::string name;
  std::string type;  ///< laser, rgbd_camera, camera, infrared, microphone, bumper, imu, force_torque
  std::string link;
  Pose3 origin;      ///< sensor frame in the link frame (x forward, z up; cameras look along x)
  RangeSettings range;    ///< a laser's or infrared sensor's beams
  CameraSettings camera;  ///< a camera's image
};

struct Drive {
  DifferentialDriveParams params;
  std::string left_wheel, right_wheel;  ///< joint names
};

/// Named defaults of a gripper (docs/robots/description-format.md): the HSR's, seed 003.
inline constexpr double kDefaultGripperPayload = 1.3;   ///< kg: Table 3.1's maximum payload
inline constexpr double kDefaultGripperFriction = 0.5;  ///< static and dynamic, §4.1 ("set frictions")

struct Gripper {
  std::string joint;
  double open = 0.0;    ///< joint position when open
  double closed = 0.0;  ///< joint position when fully closed (nothing held)
  /// The heaviest object it holds still against gravity, kg: its fingers squeeze with the force whose
  /// friction carries this weight.
  double payload = kDefaultGripperPayload;
  double friction = kDefaultGripperFriction;  ///< Coulomb coefficient of its fingers' material
};

struct RobotDescription {
  std::string name;
  std::string description;
  double footprint_radius = 0.3;  ///< m: the disc other agents avoid
  double height = 1.0;            ///< m
  double mass = 0.0;              ///< kg
  std::optional<Drive> drive;     ///< absent for a robot that does not drive (ROMAN)
  std::vector<Link> links;        ///< links[0] is the root, fixed to the base pose
  std::vector<Joint> joints;      ///< parents before children
  std::vector<Sensor> sensors;
  std::map<std::string, std::vector<std::string>> groups;  ///< named joint groups: arm, head, torso, …
  std::optional<Gripper> gripper;

  int find_joint(std::string_view name) const;  ///< -1 when absent
  int find_link(std::string_view name) const;   ///< -1 when absent
  /// The gripper's finger joints (its own and those mimicking it), by index; empty without a gripper.
  std::vector<int> finger_joints() const;
  /// A link and every link beyond it (its joints' children, theirs, …), as indices, by name.
  std::vector<int> links_from(const std::string& link) const;
  const Sensor* find_sensor(std::string_view name) const;
};

struct LoadedRobot {
  std::shared_ptr<const RobotDescription> description;  ///< null when there are errors
  std::vector<core::ValidationError> errors;            ///< all of them, each with its JSON pointer
};

/// Reads a description: schema errors, then the references between its parts (joint links, wheel and
/// group joints, sensor links, one root, no cycles).
LoadedRobot load_robot_description(const nlohmann::json& document);

/// Names of the descriptions built into the binary (from assets/robots/), sorted.
std::vector<std::string> builtin_robot_names();
/// A built-in description's JSON document (api/robot.schema.json); null when there is none by that name.
nlohmann::json builtin_robot_document(std::string_view name);
/// A built-in description by name, loaded once; null when there is none by that name.
std::shared_ptr<const RobotDescription> builtin_robot(std::string_view name);

}  // namespace hrisim::robots
