#include "sim/physics_step.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "sim/carrying.hpp"
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

void store_objects(State& state, const PhysicsBodies& physics) {
  state.objects.resize(physics.objects.size());
  for (std::size_t o = 0; o < physics.objects.size(); ++o) {
    const physics::Twist velocity = physics.world->velocity(physics.objects[o]);
    state.objects[o] = {physics.world->pose(physics.objects[o]), velocity.linear, velocity.angular};
  }
}

/// The two finger contacts of a grasp, on the object's surface; none unless both fingers touch it.
std::optional<std::pair<physics::ContactPoint, physics::ContactPoint>> finger_contacts(physics::PhysicsWorld& world, std::span<const int> fingers,
                                                                                      int object) {
  const std::optional<physics::ContactPoint> first = world.deepest_contact(fingers[0], object);
  if (!first) return std::nullopt;
  const std::optional<physics::ContactPoint> second = world.deepest_contact(fingers[1], object);
  if (!second) return std::nullopt;
  return std::pair{*first, *second};
}

/// Whether two fingers pressing at these contacts hold the object by friction: the line between them
/// lies within both friction cones (an antipodal grasp; Nguyen 1988).
bool within_friction_cones(const physics::ContactPoint& a, const physics::ContactPoint& b, double friction) {
  const Eigen::Vector3d line = b.point - a.point;
  if (line.norm() < kMinGraspWidth) return false;
  const Eigen::Vector3d u = line.normalized();
  const double cos_cone = std::cos(std::atan(friction));
  // Each finger pushes into the object along the line, against its outward normal there.
  return u.dot(-a.normal) >= cos_cone && u.dot(b.normal) >= cos_cone;
}

/// Whether a held object's load exceeds what the grip's friction carries: the force across the grasp
/// line beyond the payload's weight, or the torque about it beyond the finger pads' torsional friction.
bool grip_overloaded(const physics::Wrench& load, const Eigen::Vector3d& from, const Eigen::Vector3d& to, const Eigen::Vector3d& centre,
                     const robots::Gripper& gripper) {
  const Eigen::Vector3d u = (to - from).normalized();
  const double across = (load.force - u * u.dot(load.force)).norm();
  const double twist = std::abs(u.dot(load.torque + (centre - 0.5 * (from + to)).cross(load.force)));
  const double capacity = gripper.payload * physics::kGravity;
  return across > capacity || twist > capacity * kFingerPadRadius;
}

/// A robot gripper's palm and finger bodies in the physics world.
struct Hand {
  int palm = -1;
  std::vector<int> fingers;       ///< bodies
  std::vector<int> finger_links;  ///< their links in the description
};

Hand hand_of(const RobotRuntime& runtime, const std::vector<int>& links) {
  const robots::RobotDescription& description = runtime.robot.description();
  Hand hand;
  hand.palm = links[description.find_link(description.joints[description.find_joint(description.gripper->joint)].parent)];
  for (const int joint : description.finger_joints()) {
    hand.finger_links.push_back(description.find_link(description.joints[joint].child));
    hand.fingers.push_back(links[hand.finger_links.back()]);
  }
  return hand;
}

/// Holds `object` by the palm as it is now, clear of the fingers and palm that hold it.
void hold_in(physics::PhysicsWorld& world, const Hand& hand, int object) {
  std::vector<int> holding = hand.fingers;
  holding.push_back(hand.palm);
  world.attach(object, hand.palm, holding);
}

/// Places the fingers' bodies as they are with the gripper joint at `position`.
void place_fingers(physics::PhysicsWorld& world, const robots::Robot& robot, const Hand& hand, double position) {
  const std::vector<Eigen::Isometry3d> poses = robot.link_poses(robot.configuration_with_gripper_at(position));
  for (std::size_t f = 0; f < hand.fingers.size(); ++f) {
    world.set_kinematic_pose(hand.fingers[f], poses[hand.finger_links[f]] * robot.collision_origin(hand.finger_links[f]));
  }
}

/// Where between the gripper's position a tick ago and now both fingers first touch `object`, to
/// within kGripResolution: a tick of fast fingers would otherwise end deep in it, where the contacts'
/// normals are the fingers' faces, not the object's surface. The fingers' bodies are left there.
double first_touch(physics::PhysicsWorld& world, const robots::Robot& robot, const Hand& hand, int object, double dt) {
  const int joint = robot.joint_index(robot.description().gripper->joint);
  double touching = robot.joint_position(joint), apart = touching - robot.joint_velocity(joint) * dt;
  while (std::abs(touching - apart) > kGripResolution) {
    const double middle = 0.5 * (touching + apart);
    place_fingers(world, robot, hand, middle);
    const bool both = std::all_of(hand.fingers.begin(), hand.fingers.end(), [&](int finger) { return world.deepest_contact(finger, object).has_value(); });
    (both ? touching : apart) = middle;
  }
  place_fingers(world, robot, hand, touching);
  return touching;
}

/// Before the world steps, with the links where the robots moved them: an open gripper lets go, and a
/// closing one takes an object both its fingers reach within their friction cones — before the solver
/// would push it out from between them.
void grasp_and_release(const scenario::Model& model, State& state, PhysicsBodies& physics) {
  physics::PhysicsWorld& world = *physics.world;
  for (std::size_t r = 0; r < state.robots.size(); ++r) {
    RobotRuntime& runtime = state.robots[r];
    if (!runtime.robot.description().gripper || !state.agents[runtime.agent].active) continue;
    const robots::Gripper& gripper = *runtime.robot.description().gripper;
    const std::string& id = model.agents[runtime.agent].id;
    if (!runtime.robot.gripper_closed()) {
      runtime.slipped = false;
      if (runtime.held_object < 0) continue;
      world.detach(physics.objects[runtime.held_object]);
      emit(model, state, id, events::Release{model.objects[runtime.held_object].name});
      runtime.held_object = -1;
      continue;
    }
    const Hand hand = hand_of(runtime, physics.robot_links[r]);
    if (runtime.held_object >= 0 || runtime.slipped || hand.palm < 0 || hand.fingers.size() != 2 ||
        std::find(hand.fingers.begin(), hand.fingers.end(), -1) != hand.fingers.end()) {
      continue;
    }
    for (std::size_t o = 0; o < physics.objects.size(); ++o) {
      const int object = physics.objects[o];
      if (physics.carried[o] || world.holder(object) >= 0 || !finger_contacts(world, hand.fingers, object)) continue;
      const double touch = first_touch(world, runtime.robot, hand, object, model.dt);
      const auto contacts = finger_contacts(world, hand.fingers, object);
      if (!contacts || !within_friction_cones(contacts->first, contacts->second, gripper.friction)) {
        place_fingers(world, runtime.robot, hand, runtime.robot.joint_position(runtime.robot.joint_index(gripper.joint)));
        continue;
      }
      runtime.robot.stop_gripper_at(touch);
      hold_in(world, hand, object);
      const Eigen::Isometry3d palm_inverse = world.pose(hand.palm).inverse();
      runtime.held_object = static_cast<int>(o);
      runtime.grasped_at = state.tick;
      runtime.grip_position = touch;
      runtime.grip_from = palm_inverse * contacts->first.point;
      runtime.grip_to = palm_inverse * contacts->second.point;
      emit(model, state, id, events::Grasp{model.objects[o].name});
      break;
    }
  }
}

/// After the world stepped: a held object whose load the grip alone cannot carry slips out. While it
/// touches anything besides the hand (resting on a table, pushed against a wall), what it touches
/// shares the load, and the grip is not checked: contact forces are not a grip load.
void check_grips(const scenario::Model& model, State& state, PhysicsBodies& physics) {
  physics::PhysicsWorld& world = *physics.world;
  for (std::size_t r = 0; r < state.robots.size(); ++r) {
    RobotRuntime& runtime = state.robots[r];
    if (runtime.held_object < 0 || static_cast<double>(state.tick - runtime.grasped_at) * model.dt < kGripSettleTime) continue;
    const int held = physics.objects[runtime.held_object];
    const auto touching = world.touching();
    if (std::any_of(touching.begin(), touching.end(), [&](const auto& pair) { return pair.first == held || pair.second == held; })) continue;
    const Eigen::Isometry3d palm = world.pose(hand_of(runtime, physics.robot_links[r]).palm);
    if (!grip_overloaded(world.hold_load(held), palm * runtime.grip_from, palm * runtime.grip_to, world.pose(held).translation(),
                         *runtime.robot.description().gripper)) {
      continue;
    }
    world.detach(held);
    emit(model, state, model.agents[runtime.agent].id, events::Slip{model.objects[runtime.held_object].name});
    runtime.held_object = -1;
    runtime.slipped = true;
  }
}

/// Objects people carry leave the world while carried; one put down (placed by the choreography) or
/// dropped by a person who left rejoins it where it is, at rest.
void hand_over_carried(const scenario::Model& model, State& state, PhysicsBodies& physics, const HumanBodies& bodies) {
  std::vector<bool> carried(physics.objects.size(), false);
  for (std::size_t a = 0; a < state.agents.size(); ++a) {
    AgentState& person = state.agents[a];
    if (!person.carrying.object.valid()) continue;
    if (!person.active) {
      state.objects[person.carrying.object.value] = ObjectState{carried_pose(model, state, bodies, static_cast<int>(a))};
      emit(model, state, model.agents[a].id, events::Dropped{model.objects[person.carrying.object.value].name});
      person.carrying.object = {};
      continue;
    }
    carried[person.carrying.object.value] = true;
  }
  for (std::size_t o = 0; o < physics.objects.size(); ++o) {
    if (carried[o] == physics.carried[o]) continue;
    if (!carried[o]) physics.world->place(physics.objects[o], state.objects[o].pose);
    physics.world->set_enabled(physics.objects[o], !carried[o]);
  }
  physics.carried = std::move(carried);
}

/// After the world stepped: a carried object is where the hand is.
void place_carried(const scenario::Model& model, State& state, const HumanBodies& bodies) {
  for (std::size_t a = 0; a < state.agents.size(); ++a) {
    const AgentState& person = state.agents[a];
    if (person.carrying.object.valid()) state.objects[person.carrying.object.value] = ObjectState{carried_pose(model, state, bodies, static_cast<int>(a))};
  }
}

}  // namespace

namespace {

/// The world of the model with the agents and doors as the state has them, and the movable objects at
/// `objects` (their poses and velocities): the model's at the start, the state's when built again.
PhysicsBodies build_world(const scenario::Model& model, const State& state, const HumanBodies& bodies, std::span<const ObjectState> objects) {
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
      links.push_back(link.collision ? world.add_kinematic(*link.collision, poses[l] * runtime.robot.collision_origin(l),
                                                           {BodyOwner::Kind::robot, runtime.agent, link.name})
                                     : -1);
    }
    // The fingers are of the gripper's material.
    if (description.gripper) {
      for (const int finger : hand_of(runtime, links).fingers) {
        if (finger >= 0) world.set_friction(finger, description.gripper->friction);
      }
    }
  }
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    const scenario::MovableObject& object = model.objects[o];
    physics.objects.push_back(world.add_dynamic(object.shape, object.mass, objects[o].pose, {BodyOwner::Kind::object, static_cast<int>(o), object.name}));
    world.set_velocity(physics.objects.back(), {objects[o].linear_velocity, objects[o].angular_velocity});
  }
  physics.carried.assign(physics.objects.size(), false);
  physics.built_at_tick = state.tick;
  return physics;
}

}  // namespace

PhysicsBodies build_physics(const scenario::Model& model, State& state, const HumanBodies& bodies) {
  std::vector<ObjectState> at_start;
  for (const scenario::MovableObject& object : model.objects) at_start.push_back({robots::to_isometry(object.pose)});
  PhysicsBodies physics = build_world(model, state, bodies, at_start);
  if (physics.world) store_objects(state, physics);
  return physics;
}

PhysicsBodies build_physics_again(const scenario::Model& model, const State& state, const HumanBodies& bodies) {
  PhysicsBodies physics = build_world(model, state, bodies, state.objects);
  if (!physics.world) return physics;
  physics::PhysicsWorld& world = *physics.world;
  for (std::size_t r = 0; r < state.robots.size(); ++r) {
    const RobotRuntime& runtime = state.robots[r];
    if (!state.agents[runtime.agent].active) {
      for (const int body : physics.robot_links[r]) {
        if (body >= 0) world.set_enabled(body, false);
      }
      continue;
    }
    if (runtime.held_object < 0) continue;
    // The grasp again, as the hand and the object are now.
    hold_in(world, hand_of(runtime, physics.robot_links[r]), physics.objects[runtime.held_object]);
  }
  for (const AgentState& person : state.agents) {
    if (!person.carrying.object.valid() || !person.active) continue;
    physics.carried[person.carrying.object.value] = true;
    world.set_enabled(physics.objects[person.carrying.object.value], false);
  }
  return physics;
}

void rebuild_physics_when_due(const scenario::Model& model, const State& state, PhysicsBodies& physics, const HumanBodies& bodies) {
  const std::int64_t every = std::max<std::int64_t>(1, std::llround(kPhysicsRebuildInterval / model.dt));
  if (state.tick % every != 0 || !physics.world) return;
  physics = build_physics_again(model, state, bodies);
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
  const robots::Configuration to = moved.configuration();
  const auto clearance = [&](std::size_t l, const std::vector<Eigen::Isometry3d>& poses) {
    return world.clearance(links[l], poses[l] * moved.collision_origin(l), physics::kContactDistance);
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

void step_physics(const scenario::Model& model, State& state, PhysicsBodies& physics, const HumanBodies& bodies) {
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
      runtime.slipped = false;
      continue;
    }
    const auto poses = runtime.robot.link_poses();
    const auto& description = runtime.robot.description().links;
    for (std::size_t l = 0; l < description.size(); ++l) {
      if (links[l] >= 0) world.set_kinematic_pose(links[l], poses[l] * runtime.robot.collision_origin(l));
    }
  }
  hand_over_carried(model, state, physics, bodies);
  grasp_and_release(model, state, physics);
  world.step();
  check_grips(model, state, physics);
  store_objects(state, physics);
  place_carried(model, state, bodies);
}

}  // namespace hrisim::sim
