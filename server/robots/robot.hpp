#pragma once
// A robot in a session: its joints' motors, the base pose the wheels carry, and the controllers a
// user or a built-in controller commands — wheel (body velocity → wheel speeds), joint groups (arm,
// head: position or velocity targets) and gripper (open/close). The same commands work whatever
// motor sits behind a joint.
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "core/random.hpp"
#include "core/state_hash.hpp"
#include "robots/description.hpp"

namespace hrisim::robots {

using core::Pose2;

/// Pose3 as a rigid transform (rpy about fixed x, y, z).
Eigen::Isometry3d to_isometry(const Pose3& pose);

/// Where a robot is: its base pose and every joint's position (mimic joints included, fixed ones 0).
struct Configuration {
  Pose2 base;
  std::vector<double> joints;
};

/// The configuration a share `t` (0…1) of the way from `from` to `to`: the base along the shorter turn.
Configuration between(const Configuration& from, const Configuration& to, double t);

class Robot {
 public:
  /// `initial_joints` override the description's initial positions, by joint name.
  Robot(std::shared_ptr<const RobotDescription> description, const Pose2& start, double dt,
        const std::map<std::string, double>& initial_joints = {});

  const RobotDescription& description() const { return *description_; }

  /// The wheel controller: a body velocity, clamped to the base's limits, as wheel speed targets.
  /// Throws core::Error(conflict) for a robot without a drive.
  void command_base(const Twist& twist);
  void command_position(int joint, double position);
  void command_velocity(int joint, double velocity);
  /// Targets for a named joint group (e.g. "arm", "head"), one per joint in the group's order:
  /// positions, or velocities when `velocities`. Throws not_found / bad_request on a wrong group or count.
  void command_group(std::string_view group, std::span<const double> targets, bool velocities = false);
  /// Opens or closes the gripper (throws conflict when the robot has none).
  void set_gripper(bool closed);
  bool gripper_closed() const { return gripper_closed_; }
  /// The fingers rest on something held at gripper joint position `position`: they close no further.
  void stop_gripper_at(double position);

  /// Advances the motors one tick and moves the base by the twist its wheels actually turn.
  void step(core::Random& random);

  const Pose2& pose() const { return pose_; }
  /// Places the robot (the uniform set-pose interface); its motion state is kept.
  void set_pose(const Pose2& pose) { pose_ = pose; }
  /// The body velocity of the last step, from the wheels' actual speeds.
  const Twist& twist() const { return twist_; }
  /// The wheels' actual speeds in the last step (zero without a drive).
  WheelSpeeds wheel_speeds() const;

  /// Index of a joint by name; throws core::Error(not_found) when there is none.
  int joint_index(std::string_view name) const;
  double joint_position(int joint) const;
  double joint_velocity(int joint) const;

  /// Every link's pose in the map frame (z up from the floor), in description order.
  std::vector<Eigen::Isometry3d> link_poses() const;
  /// The same for another configuration of this robot.
  std::vector<Eigen::Isometry3d> link_poses(const Configuration& configuration) const;
  Configuration configuration() const;
  /// The configuration as it is but with the gripper joint, and the joints that mimic it, at `position`.
  Configuration configuration_with_gripper_at(double position) const;
  /// Something solid stopped the last step a share `t` of the way from `from`: the base and the joints
  /// go back to that point, and the wheels', joints' and base's velocities become the share they achieved.
  void stop_at(const Configuration& from, double t);
  /// A sensor's pose in the map frame (one of this robot's description).
  Eigen::Isometry3d sensor_pose(const Sensor& sensor) const;
  /// Where a link's collision shape sits in the link's frame (its collision_origin as a transform).
  const Eigen::Isometry3d& collision_origin(std::size_t link) const { return chain_->collision_origins[link]; }

  void hash(core::StateHasher& hasher) const;

 private:
  /// The description's tree as link indices and fixed transforms, worked out once: a step asks for
  /// the links' poses several times (sensors, the sweep against obstacles, the physics bodies).
  struct Chain {
    struct Link {
      int parent = 0, child = 0;
      Eigen::Isometry3d origin;  ///< the joint's origin
    };
    std::vector<Link> joints;  ///< in the description's order (parents first)
    std::vector<Eigen::Isometry3d> collision_origins;  ///< per link
    struct Mount {
      std::size_t link = 0;
      Eigen::Isometry3d origin;
    };
    std::vector<Mount> sensors;  ///< per sensor of the description
  };

  std::shared_ptr<const RobotDescription> description_;
  std::shared_ptr<const Chain> chain_;
  double dt_;
  Pose2 pose_;
  Twist twist_;
  std::vector<std::optional<Motor>> motors_;  ///< per joint; none for fixed joints
  bool gripper_closed_ = false;
};

}  // namespace hrisim::robots
