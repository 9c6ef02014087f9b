#include "robots/description.hpp"

#include <algorithm>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>

#include "core/embedded.hpp"
#include "core/error.hpp"

namespace hrisim::robots::embedded {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace hrisim::robots::embedded

namespace hrisim::robots {
namespace {

using nlohmann::json;

const std::span<const core::EmbeddedFile> kFiles{embedded::kEmbedded, static_cast<std::size_t>(embedded::kEmbeddedCount)};

std::string_view embedded_file(std::string_view name) { return core::find_embedded(kFiles, name); }

const core::JsonSchema& robot_schema() {
  static const core::JsonSchema schema(json::parse(embedded_file("robot.schema.json")));
  return schema;
}

Pose3 read_pose3(const json& value) {
  if (!value.is_object()) return {};
  return {value.value("x", 0.0),    value.value("y", 0.0),     value.value("z", 0.0),
          value.value("roll", 0.0), value.value("pitch", 0.0), value.value("yaw", 0.0)};
}

MotorParams read_motor(const json& value) {
  MotorParams motor;
  motor.kind = value.at("kind") == "servo" ? MotorKind::servo : MotorKind::dc;
  motor.transmission = value.value("transmission", kDefaultTransmission);
  motor.max_motor_velocity = value.value("max_motor_velocity", motor.max_motor_velocity);
  motor.max_acceleration = value.value("max_acceleration", kDefaultMaxAcceleration);
  motor.gain_error = value.value("gain_error", 0.0);
  motor.motor_velocity_noise = value.value("motor_velocity_noise", 0.0);
  motor.dead_time = value.value("dead_time", kDefaultDeadTime);
  motor.position_gain = value.value("position_gain", kDefaultPositionGain);
  motor.delay = value.value("delay", kDefaultServoDelay);
  if (value.contains("servo_speed")) motor.servo_speed = value["servo_speed"].get<double>();
  return motor;
}

Shape read_shape(const json& value) {
  Shape shape;
  const std::string kind = value.at("kind");
  shape.kind = kind == "box" ? Shape::Kind::box
               : kind == "cylinder" ? Shape::Kind::cylinder
               : kind == "sphere" ? Shape::Kind::sphere
                                  : Shape::Kind::capsule;
  if (value.contains("size")) shape.size = Eigen::Vector3d(value["size"][0], value["size"][1], value["size"][2]);
  shape.radius = value.value("radius", 0.0);
  shape.length = value.value("length", 0.0);
  return shape;
}

JointType read_joint_type(const std::string& type) {
  if (type == "revolute") return JointType::revolute;
  if (type == "continuous") return JointType::continuous;
  if (type == "prismatic") return JointType::prismatic;
  return JointType::fixed;
}

/// What the schema cannot say: every name a part refers to exists, names are unique, the joints form
/// one tree hanging from the first link, and each shape has the sizes its kind needs.
void check_references(const json& document, const RobotDescription& robot, std::vector<core::ValidationError>& errors) {
  auto error = [&](std::string pointer, std::string message) { errors.push_back({std::move(pointer), std::move(message)}); };
  std::set<std::string> seen;
  for (std::size_t i = 0; i < robot.links.size(); ++i) {
    const std::string pointer = "/links/" + std::to_string(i);
    if (!seen.insert(robot.links[i].name).second) error(pointer + "/name", "duplicate link '" + robot.links[i].name + "'");
    if (const auto& shape = robot.links[i].collision) {
      const bool sized = shape->kind == Shape::Kind::box ? (shape->size.array() > 0.0).all()
                                                         : shape->radius > 0.0 && (shape->kind == Shape::Kind::sphere || shape->length > 0.0);
      if (!sized) error(pointer + "/collision", "the shape lacks the sizes of its kind (box: size; sphere: radius; cylinder, capsule: radius and length)");
    }
  }
  seen.clear();
  std::set<std::string> children;
  for (std::size_t i = 0; i < robot.joints.size(); ++i) {
    const Joint& joint = robot.joints[i];
    const std::string pointer = "/joints/" + std::to_string(i);
    if (!seen.insert(joint.name).second) error(pointer + "/name", "duplicate joint '" + joint.name + "'");
    if (robot.find_link(joint.parent) < 0) error(pointer + "/parent", "no link named '" + joint.parent + "'");
    if (robot.find_link(joint.child) < 0) error(pointer + "/child", "no link named '" + joint.child + "'");
    if (joint.child == robot.links.front().name) error(pointer + "/child", "the first link is the root: no joint may move it");
    if (!children.insert(joint.child).second) error(pointer + "/child", "link '" + joint.child + "' already has a parent joint");
    // Parents before children: the parent must be the root or the child of an earlier joint.
    const bool parent_placed = joint.parent == robot.links.front().name ||
                               std::any_of(robot.joints.begin(), robot.joints.begin() + static_cast<std::ptrdiff_t>(i),
                                           [&](const Joint& earlier) { return earlier.child == joint.parent; });
    if (robot.find_link(joint.parent) >= 0 && !parent_placed) {
      error(pointer + "/parent", "link '" + joint.parent + "' is not placed by an earlier joint (list parents before children)");
    }
    const json& entry = document["joints"][i];
    const bool moves = joint.type != JointType::fixed;
    if (joint.mimic) {
      const int followed = robot.find_joint(joint.mimic->joint);
      if (followed < 0 || robot.joints[followed].type == JointType::fixed || robot.joints[followed].mimic) {
        error(pointer + "/mimic/joint", "'" + joint.mimic->joint + "' is not a joint with a motor of its own");
      }
      if (!moves) error(pointer + "/mimic", "a fixed joint cannot follow another");
      if (entry.contains("motor")) error(pointer + "/motor", "a mimic joint has no motor of its own");
    } else if (moves && !entry.contains("motor")) {
      error(pointer, "a moving joint needs a motor (or a mimic)");
    }
    if ((joint.type == JointType::revolute || joint.type == JointType::prismatic) && !(entry.contains("lower") && entry.contains("upper"))) {
      error(pointer, "revolute and prismatic joints need lower and upper limits");
    }
    if (joint.limits.lower && joint.limits.upper && *joint.limits.lower > *joint.limits.upper) error(pointer + "/lower", "lower is above upper");
    if (joint.axis.norm() == 0.0) error(pointer + "/axis", "the axis has no direction");
    if (entry.contains("initial") && ((joint.limits.lower && joint.initial < *joint.limits.lower) ||
                                       (joint.limits.upper && joint.initial > *joint.limits.upper))) {
      error(pointer + "/initial", "outside the joint's limits");
    }
    if (moves && entry.contains("motor") && joint.motor.kind == MotorKind::dc && !entry["motor"].contains("max_motor_velocity")) {
      error(pointer + "/motor", "a DC motor needs max_motor_velocity");
    }
  }
  for (std::size_t i = 1; i < robot.links.size(); ++i) {
    if (!children.contains(robot.links[i].name)) error("/links/" + std::to_string(i), "link '" + robot.links[i].name + "' is attached by no joint");
  }
  auto moving_joint = [&](const std::string& name, const std::string& pointer) {
    const int index = robot.find_joint(name);
    if (index < 0) {
      error(pointer, "no joint named '" + name + "'");
    } else if (robot.joints[index].type == JointType::fixed || robot.joints[index].mimic) {
      error(pointer, "joint '" + name + "' has no motor of its own (fixed or mimic)");
    }
    return index;
  };
  if (robot.drive) {
    for (const char* side : {"left_wheel", "right_wheel"}) {
      const int index = moving_joint(document["drive"][side], std::string("/drive/") + side);
      if (index >= 0 && robot.joints[index].type != JointType::continuous) error(std::string("/drive/") + side, "a wheel joint must be continuous");
    }
  }
  for (const auto& [group, joints] : robot.groups) {
    for (std::size_t i = 0; i < joints.size(); ++i) moving_joint(joints[i], "/groups/" + core::pointer_token(group) + "/" + std::to_string(i));
  }
  if (robot.gripper) moving_joint(robot.gripper->joint, "/gripper/joint");
  seen.clear();
  for (std::size_t i = 0; i < robot.sensors.size(); ++i) {
    const std::string pointer = "/sensors/" + std::to_string(i);
    if (!seen.insert(robot.sensors[i].name).second) error(pointer + "/name", "duplicate sensor '" + robot.sensors[i].name + "'");
    if (robot.find_link(robot.sensors[i].link) < 0) error(pointer + "/link", "no link named '" + robot.sensors[i].link + "'");
  }
}

}  // namespace

int RobotDescription::find_joint(std::string_view name) const {
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int RobotDescription::find_link(std::string_view name) const {
  for (std::size_t i = 0; i < links.size(); ++i) {
    if (links[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<int> RobotDescription::finger_joints() const {
  std::vector<int> fingers;
  if (!gripper) return fingers;
  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (joints[j].name == gripper->joint || (joints[j].mimic && joints[j].mimic->joint == gripper->joint)) fingers.push_back(static_cast<int>(j));
  }
  return fingers;
}

std::vector<int> RobotDescription::links_from(const std::string& link) const {
  std::vector<int> beyond{find_link(link)};
  // Joints come parents first, so one pass collects the whole subtree.
  for (const Joint& joint : joints) {
    if (std::find(beyond.begin(), beyond.end(), find_link(joint.parent)) != beyond.end()) beyond.push_back(find_link(joint.child));
  }
  return beyond;
}

const Sensor* RobotDescription::find_sensor(std::string_view name) const {
  for (const Sensor& sensor : sensors) {
    if (sensor.name == name) return &sensor;
  }
  return nullptr;
}

LoadedRobot load_robot_description(const json& document) {
  LoadedRobot loaded;
  loaded.errors = robot_schema().validate(document);
  if (!loaded.errors.empty()) return loaded;
  auto robot = std::make_shared<RobotDescription>();
  robot->name = document["name"];
  robot->description = document.value("description", "");
  robot->footprint_radius = document.value("footprint_radius", robot->footprint_radius);
  robot->height = document.value("height", robot->height);
  robot->mass = document.value("mass", 0.0);
  if (document.contains("drive")) {
    const json& drive = document["drive"];
    robot->drive = Drive{{drive["wheel_radius"], drive["wheel_separation"], drive["max_linear_speed"], drive["max_angular_speed"]},
                         drive["left_wheel"], drive["right_wheel"]};
  }
  for (const json& entry : document["links"]) {
    Link link{entry["name"], std::nullopt, {}, entry.value("mass", 0.0)};
    if (entry.contains("collision")) {
      link.collision = read_shape(entry["collision"]);
      link.collision_origin = read_pose3(entry["collision"].value("origin", json::object()));
    }
    robot->links.push_back(std::move(link));
  }
  for (const json& entry : document["joints"]) {
    Joint joint;
    joint.name = entry["name"];
    joint.type = read_joint_type(entry["type"]);
    joint.parent = entry["parent"];
    joint.child = entry["child"];
    joint.origin = read_pose3(entry.value("origin", json::object()));
    if (entry.contains("axis")) joint.axis = Eigen::Vector3d(entry["axis"][0], entry["axis"][1], entry["axis"][2]);
    if (joint.type == JointType::revolute || joint.type == JointType::prismatic) {
      if (entry.contains("lower")) joint.limits.lower = entry["lower"].get<double>();
      if (entry.contains("upper")) joint.limits.upper = entry["upper"].get<double>();
    }
    if (entry.contains("motor")) joint.motor = read_motor(entry["motor"]);
    if (entry.contains("mimic")) {
      const json& mimic = entry["mimic"];
      joint.mimic = Joint::Mimic{mimic["joint"], mimic.value("multiplier", 1.0), mimic.value("offset", 0.0)};
    }
    joint.initial = entry.value("initial", 0.0);
    robot->joints.push_back(std::move(joint));
  }
  const json sensors = document.value("sensors", json::array());
  for (const json& entry : sensors) {
    Sensor sensor{entry["name"], entry["type"], entry["link"], read_pose3(entry.value("origin", json::object())), {}, {}};
    if (entry.contains("laser")) {
      const json& laser = entry["laser"];
      const auto number = [&](const char* key) { return laser.contains(key) ? std::optional<double>(laser[key].get<double>()) : std::nullopt; };
      sensor.range = {number("field_of_view"), laser.contains("beams") ? std::optional<int>(laser["beams"].get<int>()) : std::nullopt,
                      number("min_range"), number("max_range"), number("range_noise"), number("rate")};
    }
    if (entry.contains("camera")) {
      const json& camera = entry["camera"];
      CameraSettings& image = sensor.camera;
      image.width = camera.value("width", image.width);
      image.height = camera.value("height", image.height);
      image.horizontal_fov = camera.value("horizontal_fov", image.horizontal_fov);
      image.near = camera.value("near", image.near);
      image.far = camera.value("far", image.far);
      image.rate = camera.value("rate", image.rate);
    }
    robot->sensors.push_back(std::move(sensor));
  }
  const json groups = document.value("groups", json::object());
  for (const auto& [group, joints] : groups.items()) robot->groups[group] = joints.get<std::vector<std::string>>();
  if (document.contains("gripper")) {
    const json& gripper = document["gripper"];
    robot->gripper = Gripper{gripper["joint"], gripper["open"], gripper["closed"], gripper.value("payload", kDefaultGripperPayload),
                             gripper.value("friction", kDefaultGripperFriction)};
  }
  check_references(document, *robot, loaded.errors);
  if (!loaded.errors.empty()) return loaded;
  for (Joint& joint : robot->joints) joint.axis.normalize();
  loaded.description = std::move(robot);
  return loaded;
}

std::vector<std::string> builtin_robot_names() { return core::json_file_stems(kFiles, "robot.schema.json"); }

json builtin_robot_document(std::string_view name) {
  const auto names = builtin_robot_names();
  if (std::find(names.begin(), names.end(), name) == names.end()) return nullptr;
  return json::parse(embedded_file(std::string(name) + ".json"));
}

std::shared_ptr<const RobotDescription> builtin_robot(std::string_view name) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const RobotDescription>, std::less<>> loaded;
  std::lock_guard lock(mutex);
  if (const auto found = loaded.find(name); found != loaded.end()) return found->second;
  const json document = builtin_robot_document(name);
  if (document.is_null()) return nullptr;
  LoadedRobot robot = load_robot_description(document);
  if (!robot.description) {
    // A bundled description is checked by the tests; reaching this is a build with a broken asset.
    throw core::Error(core::ErrorCode::internal, "bundled robot '" + std::string(name) + "' is invalid",
                      {{"pointer", robot.errors.front().pointer}, {"message", robot.errors.front().message}});
  }
  return loaded.emplace(std::string(name), robot.description).first->second;
}

}  // namespace hrisim::robots
