#include "robots/robot.hpp"

#include <algorithm>
#include <string>

#include "core/error.hpp"

namespace hrisim::robots {

Eigen::Isometry3d to_isometry(const Pose3& pose) {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.translate(Eigen::Vector3d(pose.x, pose.y, pose.z));
  transform.rotate(Eigen::AngleAxisd(pose.yaw, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(pose.pitch, Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(pose.roll, Eigen::Vector3d::UnitX()));
  return transform;
}

Robot::Robot(std::shared_ptr<const RobotDescription> description, const Pose2& start, double dt,
             const std::map<std::string, double>& initial_joints)
    : description_(std::move(description)), dt_(dt), pose_(start) {
  auto chain = std::make_shared<Chain>();
  for (const Joint& joint : description_->joints) {
    chain->joints.push_back({description_->find_link(joint.parent), description_->find_link(joint.child), to_isometry(joint.origin)});
  }
  for (const Link& link : description_->links) chain->collision_origins.push_back(to_isometry(link.collision_origin));
  for (const Sensor& sensor : description_->sensors) {
    chain->sensors.push_back({static_cast<std::size_t>(description_->find_link(sensor.link)), to_isometry(sensor.origin)});
  }
  chain_ = std::move(chain);
  for (const Joint& joint : description_->joints) {
    if (joint.type == JointType::fixed || joint.mimic) {
      motors_.emplace_back();
    } else {
      const auto initial = initial_joints.find(joint.name);
      motors_.emplace_back(Motor(joint.motor, joint.limits, dt, initial != initial_joints.end() ? initial->second : joint.initial));
    }
  }
}

int Robot::joint_index(std::string_view name) const {
  const int index = description_->find_joint(name);
  if (index < 0) {
    throw core::Error(core::ErrorCode::not_found, "robot '" + description_->name + "' has no joint '" + std::string(name) + "'");
  }
  return index;
}

namespace {
Motor& moving(std::vector<std::optional<Motor>>& motors, const RobotDescription& robot, int joint) {
  if (joint < 0 || joint >= static_cast<int>(motors.size())) {
    throw core::Error(core::ErrorCode::not_found, "robot '" + robot.name + "' has no joint " + std::to_string(joint));
  }
  if (!motors[joint]) {
    throw core::Error(core::ErrorCode::bad_request, "joint '" + robot.joints[joint].name + "' has no motor of its own (fixed or mimic)");
  }
  return *motors[joint];
}
}  // namespace

void Robot::command_position(int joint, double position) { moving(motors_, *description_, joint).command_position(position); }

void Robot::command_velocity(int joint, double velocity) { moving(motors_, *description_, joint).command_velocity(velocity); }

void Robot::command_base(const Twist& twist) {
  if (!description_->drive) {
    throw core::Error(core::ErrorCode::conflict, "robot '" + description_->name + "' has no drive");
  }
  const Drive& drive = *description_->drive;
  const WheelSpeeds wheels = robots::wheel_speeds(drive.params, limit(drive.params, twist));
  motors_[description_->find_joint(drive.left_wheel)]->command_velocity(wheels.left);
  motors_[description_->find_joint(drive.right_wheel)]->command_velocity(wheels.right);
}

void Robot::command_group(std::string_view group, std::span<const double> targets, bool velocities) {
  const auto found = description_->groups.find(std::string(group));
  if (found == description_->groups.end()) {
    throw core::Error(core::ErrorCode::not_found, "robot '" + description_->name + "' has no joint group '" + std::string(group) + "'");
  }
  const std::vector<std::string>& joints = found->second;
  if (targets.size() != joints.size()) {
    throw core::Error(core::ErrorCode::bad_request, "group '" + std::string(group) + "' takes " + std::to_string(joints.size()) +
                                                        " targets, got " + std::to_string(targets.size()));
  }
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const int joint = description_->find_joint(joints[i]);
    velocities ? command_velocity(joint, targets[i]) : command_position(joint, targets[i]);
  }
}

void Robot::set_gripper(bool closed) {
  if (!description_->gripper) {
    throw core::Error(core::ErrorCode::conflict, "robot '" + description_->name + "' has no gripper");
  }
  gripper_closed_ = closed;
  const Gripper& gripper = *description_->gripper;
  command_position(description_->find_joint(gripper.joint), closed ? gripper.closed : gripper.open);
}

void Robot::stop_gripper_at(double position) {
  const Gripper& gripper = description_->gripper.value();
  Motor& motor = *motors_[description_->find_joint(gripper.joint)];
  if ((motor.position() - position) * (gripper.closed - gripper.open) > 0.0) motor.stop_at(position, 0.0);
}

void Robot::step(core::Random& random) {
  for (auto& motor : motors_) {
    if (motor) motor->step(random);
  }
  if (!description_->drive) return;
  twist_ = body_twist(description_->drive->params, wheel_speeds());
  pose_ = integrate(pose_, twist_, dt_);
}

WheelSpeeds Robot::wheel_speeds() const {
  if (!description_->drive) return {};
  const Drive& drive = *description_->drive;
  return {motors_[description_->find_joint(drive.left_wheel)]->velocity(),
          motors_[description_->find_joint(drive.right_wheel)]->velocity()};
}

double Robot::joint_position(int joint) const {
  if (motors_.at(joint)) return motors_[joint]->position();
  const Joint& def = description_->joints[joint];
  if (def.mimic) {
    double position = def.mimic->multiplier * joint_position(description_->find_joint(def.mimic->joint)) + def.mimic->offset;
    if (def.limits.lower) position = std::max(position, *def.limits.lower);
    if (def.limits.upper) position = std::min(position, *def.limits.upper);
    return position;
  }
  return 0.0;
}

double Robot::joint_velocity(int joint) const {
  if (motors_.at(joint)) return motors_[joint]->velocity();
  const Joint& def = description_->joints[joint];
  if (def.mimic) {
    const double followed = def.mimic->multiplier * joint_position(description_->find_joint(def.mimic->joint)) + def.mimic->offset;
    if (followed != joint_position(joint)) return 0.0;  // held at its own limit
    return def.mimic->multiplier * joint_velocity(description_->find_joint(def.mimic->joint));
  }
  return 0.0;
}

Configuration between(const Configuration& from, const Configuration& to, double t) {
  Configuration at{{from.base.x + t * (to.base.x - from.base.x), from.base.y + t * (to.base.y - from.base.y),
                    core::wrap_angle(from.base.theta + t * core::wrap_angle(to.base.theta - from.base.theta))},
                   from.joints};
  for (std::size_t j = 0; j < at.joints.size(); ++j) at.joints[j] += t * (to.joints[j] - from.joints[j]);
  return at;
}

Configuration Robot::configuration() const {
  Configuration configuration{pose_, std::vector<double>(description_->joints.size(), 0.0)};
  for (std::size_t j = 0; j < configuration.joints.size(); ++j) configuration.joints[j] = joint_position(static_cast<int>(j));
  return configuration;
}

Configuration Robot::configuration_with_gripper_at(double position) const {
  Robot moved = *this;
  moved.motors_[description_->find_joint(description_->gripper.value().joint)]->stop_at(position, 0.0);
  return moved.configuration();
}

void Robot::stop_at(const Configuration& from, double t) {
  const Configuration reached = between(from, configuration(), t);
  pose_ = reached.base;
  twist_ = {t * twist_.linear, t * twist_.angular};
  for (std::size_t j = 0; j < motors_.size(); ++j) {
    if (motors_[j]) motors_[j]->stop_at(reached.joints[j], t * motors_[j]->velocity());
  }
}

std::vector<Eigen::Isometry3d> Robot::link_poses() const { return link_poses(configuration()); }

std::vector<Eigen::Isometry3d> Robot::link_poses(const Configuration& configuration) const {
  std::vector<Eigen::Isometry3d> poses(description_->links.size(), Eigen::Isometry3d::Identity());
  const Pose2& base = configuration.base;
  poses[0] = to_isometry({base.x, base.y, 0.0, 0.0, 0.0, base.theta});
  for (std::size_t j = 0; j < description_->joints.size(); ++j) {
    const Joint& joint = description_->joints[j];
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    const double q = configuration.joints[j];
    if (joint.type == JointType::prismatic) {
      motion.translate(q * joint.axis);
    } else if (joint.type != JointType::fixed) {
      motion.rotate(Eigen::AngleAxisd(q, joint.axis));
    }
    // The loader guarantees parents come first, so the parent's pose is final here.
    const Chain::Link& link = chain_->joints[j];
    poses[static_cast<std::size_t>(link.child)] = poses[static_cast<std::size_t>(link.parent)] * link.origin * motion;
  }
  return poses;
}

Eigen::Isometry3d Robot::sensor_pose(const Sensor& sensor) const {
  const Chain::Mount& mount = chain_->sensors.at(static_cast<std::size_t>(&sensor - description_->sensors.data()));
  return link_poses()[mount.link] * mount.origin;
}

void Robot::hash(core::StateHasher& hasher) const {
  hasher.add(pose_.x).add(pose_.y).add(pose_.theta).add(twist_.linear).add(twist_.angular).add(gripper_closed_);
  for (const auto& motor : motors_) {
    if (motor) motor->hash(hasher);
  }
}

}  // namespace hrisim::robots
