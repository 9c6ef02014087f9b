#include "sim/physics_step.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "sim/doors_and_elevators.hpp"
#include "sim/events.hpp"

namespace hrisim::sim {
namespace {

using physics::BodyOwner;
using scenario::AgentKind;

/// A capsule of the body as the physics world's shape: centred, its axis along z (about which it is
/// round, so any x and y across it do).
Eigen::Isometry3d capsule_pose(const humans::Capsule& capsule) {
  const Eigen::Vector3d z = (capsule.to - capsule.from).normalized();
  const Eigen::Vector3d x = (std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(z).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.translation() = 0.5 * (capsule.from + capsule.to);
  return pose;
}

Eigen::Isometry3d upright(const Vec2& position, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Eigen::Vector3d(position.x(), position.y(), z));
  return pose;
}

robots::Shape capsule(double radius, double length) {
  robots::Shape shape;
  shape.kind = robots::Shape::Kind::capsule;
  shape.radius = radius;
  shape.length = length;
  return shape;
}

void store_object_poses(State& state, const PhysicsBodies& physics) {
  state.object_poses.resize(physics.objects.size());
  for (std::size_t o = 0; o < physics.objects.size(); ++o) state.object_poses[o] = physics.world->pose(physics.objects[o]);
}

/// Grasping: a closed gripper holds an object both its fingers touch, until it opens.
void update_grasps(const scenario::Model& model, State& state, PhysicsBodies& physics) {
  physics::PhysicsWorld& world = *physics.world;
  const auto touching = world.touching();
  auto touch = [&](int a, int b) { return std::binary_search(touching.begin(), touching.end(), std::pair{std::min(a, b), std::max(a, b)}); };
  for (std::size_t r = 0; r < state.robots.size(); ++r) {
    RobotRuntime& runtime = state.robots[r];
    const std::vector<int>& links = physics.robot_links[r];
    const robots::RobotDescription& description = runtime.robot.description();
    if (!description.gripper) continue;
    const std::string& id = model.agents[runtime.agent].id;
    if (runtime.held_object >= 0 && !runtime.robot.gripper_closed()) {
      world.detach(physics.objects[runtime.held_object]);
      emit(model, state, "release", id, {{"object", model.objects[runtime.held_object].name}});
      runtime.held_object = -1;
    }
    if (runtime.held_object >= 0 || !runtime.robot.gripper_closed()) continue;
    const robots::Joint& motor = description.joints[description.find_joint(description.gripper->joint)];
    std::vector<int> fingers;
    for (const int joint : description.finger_joints()) fingers.push_back(links[description.find_link(description.joints[joint].child)]);
    const int palm = links[description.find_link(motor.parent)];
    for (std::size_t o = 0; o < physics.objects.size() && palm >= 0; ++o) {
      if (world.holder(physics.objects[o]) >= 0) continue;
      const bool gripped =
          fingers.size() >= 2 && std::all_of(fingers.begin(), fingers.end(), [&](int finger) { return finger >= 0 && touch(finger, physics.objects[o]); });
      if (!gripped) continue;
      world.attach(physics.objects[o], palm);
      runtime.held_object = static_cast<int>(o);
      emit(model, state, "grasp", id, {{"object", model.objects[o].name}});
      break;
    }
  }
}

}  // namespace

PhysicsBodies build_physics(const scenario::Model& model, State& state, const HumanBodies& bodies) {
  PhysicsBodies physics;
  if (state.robots.empty() && model.objects.empty()) return physics;
  physics.world = std::make_unique<physics::PhysicsWorld>(model.dt);
  physics::PhysicsWorld& world = *physics.world;
  // The map: an image's outline as walls, or each obstacle (walls included) as a prism of its height.
  world.add_floor_and_walls(model.map_from_image ? std::span<const world::Segment>(model.outline) : std::span<const world::Segment>(),
                            scenario::kDefaultObstacleHeight);
  if (!model.map_from_image) {
    for (const scenario::Obstacle& obstacle : model.obstacles) world.add_static_prism(obstacle.polygon, obstacle.height, {BodyOwner::Kind::map, -1, obstacle.name});
  }
  for (std::size_t d = 0; d < model.doors.size(); ++d) {
    const scenario::Door& door = model.doors[d];
    robots::Shape slab;
    slab.size = Eigen::Vector3d(door.width(), door.thickness, scenario::kDefaultObstacleHeight);
    Eigen::Isometry3d pose = upright(0.5 * (door.from + door.to), 0.5 * scenario::kDefaultObstacleHeight);
    pose.rotate(Eigen::AngleAxisd(core::direction_to(door.from, door.to), Eigen::Vector3d::UnitZ()));
    physics.doors.push_back(world.add_kinematic(slab, pose, {BodyOwner::Kind::map, -1, door.name}));
    world.set_enabled(physics.doors.back(), door_blocks(state, static_cast<int>(d)));
  }
  std::array<int, humans::kBodyPartCount> no_bodies;
  no_bodies.fill(-1);
  physics.humans.assign(state.agents.size(), no_bodies);
  for (std::size_t i = 0; i < state.agents.size(); ++i) {
    if (model.agents[i].kind != AgentKind::human) continue;
    const int agent = static_cast<int>(i);
    // Bone lengths do not change, so each capsule keeps the length it has now.
    const humans::BodyCapsules& body = bodies.of(model, state, agent);
    for (int part = 0; part < humans::kBodyPartCount; ++part) {
      const humans::Capsule& solid = body[part];
      physics.humans[i][part] = world.add_kinematic(capsule(solid.radius, (solid.to - solid.from).norm()), capsule_pose(solid),
                                                    {BodyOwner::Kind::human, agent, std::string(humans::body_part_name(static_cast<humans::BodyPart>(part)))});
    }
  }
  physics.disc_robots.assign(state.agents.size(), -1);
  for (std::size_t i = 0; i < state.agents.size(); ++i) {
    const scenario::AgentDef& def = model.agents[i];
    if (def.kind != AgentKind::robot || def.robot_model) continue;
    robots::Shape disc;
    disc.kind = robots::Shape::Kind::cylinder;
    disc.radius = def.radius;
    disc.length = kDiscRobotHeight;
    physics.disc_robots[i] =
        world.add_kinematic(disc, upright(state.agents[i].position, 0.5 * kDiscRobotHeight), {BodyOwner::Kind::robot, static_cast<int>(i), "body"});
  }
  for (const RobotRuntime& runtime : state.robots) {
    const robots::RobotDescription& description = runtime.robot.description();
    const auto poses = runtime.robot.link_poses();
    std::vector<int>& links = physics.robot_links.emplace_back();
    for (std::size_t l = 0; l < description.links.size(); ++l) {
      const robots::Link& link = description.links[l];
      links.push_back(link.collision ? world.add_kinematic(*link.collision, poses[l] * robots::to_isometry(link.collision_origin),
                                                           {BodyOwner::Kind::robot, runtime.agent, link.name})
                                     : -1);
    }
  }
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    const scenario::MovableObject& object = model.objects[o];
    physics.objects.push_back(world.add_dynamic(object.shape, object.mass, robots::to_isometry(object.pose), {BodyOwner::Kind::object, static_cast<int>(o), object.name}));
  }
  store_object_poses(state, physics);
  return physics;
}

void place_people_and_doors(const scenario::Model& model, const State& state, PhysicsBodies& physics, const HumanBodies& bodies) {
  physics::PhysicsWorld& world = *physics.world;
  for (std::size_t d = 0; d < physics.doors.size(); ++d) world.set_enabled(physics.doors[d], door_blocks(state, static_cast<int>(d)));
  // People touch robots only: a body far from every robot is left out of the world, which spares
  // Bullet most of its kinematic bodies in a crowd.
  std::vector<Vec2> robots_at;
  for (std::size_t i = 0; i < state.agents.size(); ++i) {
    if (state.agents[i].active && model.agents[i].kind == AgentKind::robot) robots_at.push_back(state.agents[i].position);
  }
  for (std::size_t i = 0; i < physics.humans.size(); ++i) {
    const auto& parts = physics.humans[i];
    if (parts[0] < 0) continue;
    const AgentState& agent = state.agents[i];
    const bool near_a_robot = std::any_of(robots_at.begin(), robots_at.end(), [&](const Vec2& robot) {
      return (robot - agent.position).squaredNorm() <= kHumanContactRange * kHumanContactRange;
    });
    const bool present = agent.active && near_a_robot;
    if (present) {
      const humans::BodyCapsules& body = bodies.of(model, state, static_cast<int>(i));
      for (int part = 0; part < humans::kBodyPartCount; ++part) world.set_kinematic_pose(parts[part], capsule_pose(body[part]));
    }
    for (const int part : parts) world.set_enabled(part, present);
  }
  // Robots without a model walk with the crowd.
  for (std::size_t i = 0; i < physics.disc_robots.size(); ++i) {
    if (physics.disc_robots[i] < 0) continue;
    world.set_enabled(physics.disc_robots[i], state.agents[i].active);
    world.set_kinematic_pose(physics.disc_robots[i], upright(state.agents[i].position, 0.5 * kDiscRobotHeight));
  }
}

double free_share(PhysicsBodies& physics, std::size_t robot, const robots::Robot& moved, const robots::Configuration& from) {
  physics::PhysicsWorld& world = *physics.world;
  const std::vector<int>& links = physics.robot_links[robot];
  const auto& description = moved.description().links;
  const robots::Configuration to = moved.configuration();
  const auto clearance = [&](std::size_t l, const std::vector<Eigen::Isometry3d>& poses) {
    return world.clearance(links[l], poses[l] * robots::to_isometry(description[l].collision_origin), physics::kContactDistance);
  };
  const auto poses_at = [&](double t) { return moved.link_poses(robots::between(from, to, t)); };
  // Enough samples that no link moves farther than kSweepStep between two: none jumps a thin wall.
  const std::vector<Eigen::Isometry3d> start = moved.link_poses(from), end = moved.link_poses();
  double travel = 0.0;
  for (std::size_t l = 0; l < links.size(); ++l) travel = std::max(travel, (end[l].translation() - start[l].translation()).norm());
  if (travel == 0.0) return 1.0;  // standing still goes nowhere deeper
  const int samples = std::max(1, static_cast<int>(std::ceil(travel / kSweepStep)));
  // How deep each link may overlap: kPenetrationSlop, or as deep as it already is (a person who walked
  // into the robot: it may move, but not deeper). Measured only for links that come close.
  std::vector<std::optional<double>> limits(links.size());
  const auto limit = [&](std::size_t l) {
    if (!limits[l]) limits[l] = std::min(-kPenetrationSlop, clearance(l, start));
    return *limits[l];
  };
  std::vector<std::size_t> blocking;
  for (int k = 1; k <= samples; ++k) {
    const std::vector<Eigen::Isometry3d> poses = k == samples ? end : poses_at(static_cast<double>(k) / samples);
    for (std::size_t l = 0; l < links.size(); ++l) {
      if (links[l] < 0) continue;
      const double nearest = clearance(l, poses);
      if (nearest < -kPenetrationSlop && nearest < limit(l)) blocking.push_back(l);
    }
    if (blocking.empty()) continue;
    // Where between the last free sample and this one the blocking links stop.
    double free = static_cast<double>(k - 1) / samples, blocked = static_cast<double>(k) / samples;
    while ((blocked - free) * travel > kStopResolution) {
      const double middle = 0.5 * (free + blocked);
      const std::vector<Eigen::Isometry3d> there = poses_at(middle);
      const bool clear = std::all_of(blocking.begin(), blocking.end(), [&](std::size_t l) { return clearance(l, there) >= limit(l); });
      (clear ? free : blocked) = middle;
    }
    return free;
  }
  return 1.0;
}

void step_physics(const scenario::Model& model, State& state, PhysicsBodies& physics) {
  physics::PhysicsWorld& world = *physics.world;
  for (std::size_t r = 0; r < state.robots.size(); ++r) {
    RobotRuntime& runtime = state.robots[r];
    const std::vector<int>& links = physics.robot_links[r];
    const bool active = state.agents[runtime.agent].active;
    for (const int body : links) {
      if (body >= 0) world.set_enabled(body, active);
    }
    if (!active) {
      if (runtime.held_object >= 0) world.detach(physics.objects[runtime.held_object]);  // it drops what it held
      runtime.held_object = -1;
      continue;
    }
    const auto poses = runtime.robot.link_poses();
    const auto& description = runtime.robot.description().links;
    for (std::size_t l = 0; l < description.size(); ++l) {
      if (links[l] >= 0) world.set_kinematic_pose(links[l], poses[l] * robots::to_isometry(description[l].collision_origin));
    }
  }
  world.step();
  update_grasps(model, state, physics);
  store_object_poses(state, physics);
}

}  // namespace hrisim::sim
