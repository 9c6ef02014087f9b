#include "sim/sensing.hpp"

#include <algorithm>
#include <cmath>

#include "sim/choreography.hpp"
#include "sim/doors_and_elevators.hpp"
#include "sim/events.hpp"

namespace hrisim::sim {
namespace {

/// What the robot's links touch in the physics world now (the floor does not count).
std::vector<Contact> contacts_of(const physics::PhysicsWorld& world, int robot_agent) {
  std::vector<Contact> contacts;
  for (const auto& [first, second] : world.touching()) {
    const physics::BodyOwner& a = world.owner(first);
    const physics::BodyOwner& b = world.owner(second);
    const bool mine_first = a.kind == physics::BodyOwner::Kind::robot && a.index == robot_agent;
    const bool mine_second = b.kind == physics::BodyOwner::Kind::robot && b.index == robot_agent;
    if (mine_first == mine_second) continue;  // not this robot's, or two of its own links
    const physics::BodyOwner& other = mine_first ? b : a;
    if (other.kind == physics::BodyOwner::Kind::map && other.part == "floor") continue;
    Contact contact;
    if (other.kind == physics::BodyOwner::Kind::human || other.kind == physics::BodyOwner::Kind::robot) contact.agent = other.index;
    if (other.kind == physics::BodyOwner::Kind::object) contact.object = other.index;
    contact.part = other.part;
    if (std::find(contacts.begin(), contacts.end(), contact) == contacts.end()) contacts.push_back(contact);
  }
  return contacts;
}

Eigen::Vector3d noise(core::Random& random, double deviation) {
  return {random.normal(0.0, deviation), random.normal(0.0, deviation), random.normal(0.0, deviation)};
}

/// The IMUs from how their mounts moved over the last two ticks.
void read_imus(const scenario::Model& model, const State& state, RobotRuntime& runtime) {
  for (RobotRuntime::ImuSensor& imu : runtime.imus) {
    const Eigen::Isometry3d now = runtime.robot.sensor_pose(*imu.mount);
    const Eigen::Vector3d velocity = (now.translation() - imu.last_pose.translation()) / model.dt;
    const Eigen::Vector3d acceleration = (velocity - imu.last_velocity) / model.dt;
    const Eigen::AngleAxisd turn(imu.last_pose.rotation().transpose() * now.rotation());
    imu.reading.tick = state.tick;
    imu.reading.orientation = Eigen::Quaterniond(now.rotation());
    imu.reading.angular_velocity = turn.axis() * (turn.angle() / model.dt) + noise(runtime.sensor_random, kImuGyroNoise);
    // An accelerometer at rest feels the floor pushing up: the specific force, gravity included.
    imu.reading.linear_acceleration = now.rotation().transpose() * (acceleration + Eigen::Vector3d(0.0, 0.0, physics::kGravity)) +
                                      noise(runtime.sensor_random, kImuAccelerationNoise);
    imu.last_pose = now;
    imu.last_velocity = velocity;
  }
}

/// The force/torque sensors from what the physics world applied to the links beyond them.
void read_force_torque(const State& state, const physics::PhysicsWorld& world, const std::vector<int>& link_bodies, RobotRuntime& runtime) {
  for (RobotRuntime::ForceTorqueSensor& sensor : runtime.force_torque_sensors) {
    std::vector<int> bodies;
    for (const int link : sensor.links) {
      if (link_bodies[link] >= 0) bodies.push_back(link_bodies[link]);
    }
    const Eigen::Isometry3d at = runtime.robot.sensor_pose(*sensor.mount);
    const physics::Wrench wrench = world.external_wrench(bodies, at.translation());
    sensor.reading.tick = state.tick;
    sensor.reading.force = at.rotation().transpose() * wrench.force + noise(runtime.sensor_random, kForceNoise);
    sensor.reading.torque = at.rotation().transpose() * wrench.torque + noise(runtime.sensor_random, kTorqueNoise);
  }
}

}  // namespace

sensors::RayScene range_scene(const scenario::Model& model, const State& state, const HumanBodies& bodies, double height, int robot_agent) {
  sensors::RayScene scene(model.outline, height);
  for (std::size_t d = 0; d < model.doors.size(); ++d) {
    if (!door_blocks(state, static_cast<int>(d))) continue;
    const scenario::Door& door = model.doors[d];
    std::vector<world::Segment> edges;
    const Vec2 across = core::left_normal((door.to - door.from).normalized()) * (0.5 * door.thickness);
    world::append_edges({door.from - across, door.to - across, door.to + across, door.from + across}, edges);
    for (const world::Segment& edge : edges) scene.add(edge);
  }
  for (std::size_t o = 0; o < state.objects.size(); ++o) {
    // Movable objects as their footprint at this height, taken upright (a lying cup reads as standing).
    const scenario::MovableObject& object = model.objects[o];
    const Eigen::Isometry3d& pose = state.objects[o].pose;
    const robots::Shape& shape = object.shape;
    const double half_height = shape.kind == robots::Shape::Kind::box      ? 0.5 * shape.size.z()
                               : shape.kind == robots::Shape::Kind::sphere ? shape.radius
                                                                            : 0.5 * shape.length + (shape.kind == robots::Shape::Kind::capsule ? shape.radius : 0.0);
    if (std::abs(pose.translation().z() - height) > half_height) continue;
    const Vec2 centre(pose.translation().x(), pose.translation().y());
    if (shape.kind != robots::Shape::Kind::box) {
      scene.add(sensors::Circle{centre, shape.radius});
      continue;
    }
    const Eigen::Vector3d x_axis = pose.rotation().col(0);
    const Vec2 along = Vec2(x_axis.x(), x_axis.y()).normalized();
    const Vec2 u = 0.5 * shape.size.x() * along, v = 0.5 * shape.size.y() * core::left_normal(along);
    std::vector<world::Segment> edges;
    world::append_edges({centre - u - v, centre + u - v, centre + u + v, centre - u + v}, edges);
    for (const world::Segment& edge : edges) scene.add(edge);
  }
  for (std::size_t i = 0; i < state.agents.size(); ++i) {
    const AgentState& agent = state.agents[i];
    if (!agent.active || static_cast<int>(i) == robot_agent) continue;
    const scenario::AgentDef& def = model.agents[i];
    if (def.kind == scenario::AgentKind::human) {
      add_human_body(scene, bodies.of(model, state, static_cast<int>(i)), height);
    } else if (!def.robot_model || height < def.robot_model->height) {
      scene.add(sensors::Circle{agent.position, def.radius});
    }
  }
  return scene;
}

void sense(const scenario::Model& model, State& state, const PhysicsBodies& physics, const HumanBodies& bodies) {
  for (std::size_t r = 0; r < state.robots.size(); ++r) {
    RobotRuntime& runtime = state.robots[r];
    if (!state.agents[runtime.agent].active) continue;
    const std::string& id = model.agents[runtime.agent].id;
    read_imus(model, state, runtime);
    read_force_torque(state, *physics.world, physics.robot_links[r], runtime);
    if (runtime.robot.description().drive) {
      runtime.odometry.update(runtime.robot.twist(), model.dt, runtime.sensor_random);
      if (due(runtime.odometry_schedule, state.tick, model.dt)) runtime.odometry_reading = {state.tick, runtime.odometry.pose(), runtime.odometry.twist()};
    }
    for (RobotRuntime::LaserSensor& sensor : runtime.lasers) {
      if (!due(sensor.schedule, state.tick, model.dt)) continue;
      const Eigen::Isometry3d mount = runtime.robot.sensor_pose(*sensor.mount);
      const Vec2 origin(mount.translation().x(), mount.translation().y());
      const Eigen::Vector3d forward = mount.rotation().col(0);
      const double heading = std::atan2(forward.y(), forward.x());
      const sensors::RayScene scene = range_scene(model, state, bodies, mount.translation().z(), runtime.agent);
      sensor.laser.scan(scene, origin, heading, runtime.sensor_random, sensor.reading.ranges);
      sensor.reading.tick = state.tick;
      sensor.reading.pose = {origin.x(), origin.y(), heading};
      sensor.reading.height = mount.translation().z();
    }
    if (runtime.people_detector && due(runtime.people_schedule, state.tick, model.dt)) {
      // The detector looks from the first laser's mount (else the base centre) at torso height.
      Pose2 from = runtime.robot.pose();
      if (!runtime.lasers.empty()) {
        const Eigen::Isometry3d mount = runtime.robot.sensor_pose(*runtime.lasers.front().mount);
        const Eigen::Vector3d forward = mount.rotation().col(0);
        from = {mount.translation().x(), mount.translation().y(), std::atan2(forward.y(), forward.x())};
      }
      const sensors::RayScene scene = range_scene(model, state, bodies, kPeopleDetectorHeight, runtime.agent);
      std::vector<sensors::PersonTruth> people;
      for (std::size_t i = 0; i < state.agents.size(); ++i) {
        if (state.agents[i].active && model.agents[i].kind == scenario::AgentKind::human) {
          people.push_back({static_cast<int>(i), state.agents[i].position, state.agents[i].velocity, kPersonRadius, state.agents[i].heading});
        }
      }
      runtime.people_detector->detect(scene, from.position(), from.theta, people, runtime.sensor_random, runtime.people.people);
      runtime.people.tick = state.tick;
    }
    std::vector<Contact> contacts = contacts_of(*physics.world, runtime.agent);
    const auto with = [&](const Contact& contact) -> std::string {
      if (contact.agent >= 0) return model.agents[contact.agent].id;
      if (contact.object >= 0) return model.objects[contact.object].name;
      return "map";
    };
    for (const Contact& contact : contacts) {
      if (std::find(runtime.contacts.begin(), runtime.contacts.end(), contact) == runtime.contacts.end()) {
        emit(model, state, id, events::ContactStart{with(contact), contact.part});
        if (contact.agent >= 0) startle(model, state, contact.agent, runtime.agent);
      }
    }
    for (const Contact& contact : runtime.contacts) {
      if (std::find(contacts.begin(), contacts.end(), contact) == contacts.end()) {
        emit(model, state, id, events::ContactEnd{with(contact), contact.part});
      }
    }
    runtime.contacts = std::move(contacts);
  }
}

}  // namespace hrisim::sim
