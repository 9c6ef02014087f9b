#pragma once
// The Bullet world of a session: the static map, people as kinematic capsules that follow their
// bodies, robot links as kinematic bodies that follow the robot's joints, and movable objects (cups,
// boxes) as dynamic bodies that fall, rest and get pushed. One world and solver per session, bodies
// added in scenario order, a fixed time step, Bullet's double-precision build. Bullet's headers stay
// inside physics_world.cpp.
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "robots/description.hpp"
#include "world/outline.hpp"

namespace hrisim::physics {

/// Gravity, m/s² (along -z).
inline constexpr double kGravity = 9.81;
/// Bodies closer than this count as touching, m.
inline constexpr double kContactDistance = 1e-3;

/// Who a body belongs to, for contact reports.
struct BodyOwner {
  enum class Kind { map, human, robot, object };
  Kind kind = Kind::map;
  int index = -1;    ///< agent index (human, robot) or object index; -1 for the map
  std::string part;  ///< human: a body part (humans::body_part_name); robot: its link; object and map: its name
  bool operator==(const BodyOwner&) const = default;
};

/// Where two bodies touch: a point on the second body's surface and that surface's outward normal.
struct ContactPoint {
  Eigen::Vector3d point;
  Eigen::Vector3d normal;
  double distance = 0.0;  ///< m; negative: overlap
};

/// A force and a torque (N, N·m; world frame).
struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

/// A body's velocity (m/s, rad/s; world frame).
struct Twist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();
};

class PhysicsWorld {
 public:
  explicit PhysicsWorld(double dt);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  /// The floor (z = 0) and walls: every segment as a vertical face from the floor to `height`.
  int add_floor_and_walls(std::span<const world::Segment> segments, double height);
  /// A static prism: the polygon from the floor to `height` (furniture, obstacles).
  int add_static_prism(const std::vector<Eigen::Vector2d>& polygon, double height, BodyOwner owner);
  int add_kinematic(const robots::Shape& shape, const Eigen::Isometry3d& pose, BodyOwner owner);
  int add_dynamic(const robots::Shape& shape, double mass, const Eigen::Isometry3d& pose, BodyOwner owner);

  /// Places a dynamic body, at rest (the uniform set-pose interface: moving a cup before a test).
  void place(int body, const Eigen::Isometry3d& pose);
  /// Sets a dynamic body's velocity: a world built again from a state goes on as the state's went.
  void set_velocity(int body, const Twist& velocity);
  /// Moves a kinematic body (people, robot links) to where its owner is now.
  void set_kinematic_pose(int body, const Eigen::Isometry3d& pose);
  /// Takes a body out of the world (a person who left) or puts it back.
  void set_enabled(int body, bool enabled);

  /// Sets a body's friction coefficient (Bullet multiplies those of two bodies in contact).
  void set_friction(int body, double friction);

  /// Holds a dynamic body to another, as it is now, by a rigid joint (a grasp) until released. The
  /// held body stays dynamic: what it bumps into pushes on the joint (see hold_load). It does not
  /// collide with the `hand` bodies (the fingers that hold it).
  void attach(int body, int holder, std::span<const int> hand = {});
  void detach(int body);
  /// The body holding this one, -1 when free.
  int holder(int body) const;
  /// What the holder's joint applied to a held body during the last step: the force, and the torque
  /// about the body's centre of mass. Zero when the body is free.
  Wrench hold_load(int body) const;

  /// The smallest signed distance (m; negative: overlap) from `body`, placed at `pose`, to what is
  /// solid for it — the map (not the floor), doors, people and other robots' links; not movable
  /// objects, which it pushes, nor the links of its own owner — looking no farther than `reach`
  /// (nothing that near: `reach`). The body stays at `pose`.
  double clearance(int body, const Eigen::Isometry3d& pose, double reach);

  /// Advances the dynamic bodies one fixed step.
  void step();

  Eigen::Isometry3d pose(int body) const;
  Twist velocity(int body) const;
  const BodyOwner& owner(int body) const;
  /// Pairs of bodies (lower id first) touching after the last step, sorted.
  std::vector<std::pair<int, int>> touching() const;
  /// Where body `a` touches or overlaps body `on` most deeply as they are placed now (not after the
  /// last step): a point on `on`'s surface and its outward normal there; none when they are farther
  /// apart than kContactDistance.
  std::optional<ContactPoint> deepest_contact(int a, int on);
  /// What the world applied to a group of bodies during the last step, about `point`: the contact
  /// forces the solver resolved (pushing, being pushed) and the loads of the objects they hold.
  /// Contacts among the group do not count.
  Wrench external_wrench(std::span<const int> bodies, const Eigen::Vector3d& point) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hrisim::physics
