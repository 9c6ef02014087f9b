#include "sim/robot_runtime.hpp"

#include <algorithm>
#include <cmath>

#include "core/portable_math.hpp"

namespace hrisim::sim {

RobotRuntime::RobotRuntime(int agent_index, const scenario::AgentDef& def, double dt, const core::Random& session_random)
    : agent(agent_index),
      robot(def.robot_model, def.start, dt, def.initial_joints),
      controller(def.controller),
      motor_random(session_random.stream("robot." + def.id + ".motors")),
      sensor_random(session_random.stream("robot." + def.id + ".sensors")),
      odometry(def.odometry),
      odometry_schedule{1.0 / def.odometry.rate, 0} {
  for (const robots::Sensor& mount : def.robot_model->sensors) {
    if (mount.type == "imu") {
      const Eigen::Isometry3d at = robot.sensor_pose(mount);
      ImuReading reading;
      reading.sensor = mount.name;
      imus.push_back({&mount, at, Eigen::Vector3d::Zero(), std::move(reading)});
    }
    if (mount.type == "force_torque") force_torque_sensors.push_back({&mount, def.robot_model->links_from(mount.link), {mount.name, -1, {}, {}}});
    if (mount.type != "laser" && mount.type != "infrared") continue;
    const sensors::LaserParams params =
        sensors::read_laser_params(mount.range, mount.type == "laser" ? sensors::LaserParams{} : sensors::infrared_defaults());
    LaserReading reading;
    reading.sensor = mount.name;
    reading.angle_min = params.start_angle();
    reading.angle_increment = params.increment();
    reading.range_min = params.min_range;
    reading.range_max = params.max_range;
    lasers.push_back({&mount, sensors::Laser(params), {1.0 / params.rate, 0}, std::move(reading)});
  }
  if (def.microphones) {
    sensors::MicrophoneArray array = *sensors::microphone_array(*def.robot_model);
    const std::vector<sensors::Vec3> positions = array.positions;
    hearing.emplace(Hearing{sensors::Microphones(std::move(array), *def.microphones),
                            sensors::DirectionOfArrival(positions, def.sound_direction),
                            sensors::AudioHistory(static_cast<int>(positions.size()), def.sound_direction.window),
                            {},
                            {1.0 / def.sound_direction.rate, 0},
                            std::nullopt,
                            -1,
                            session_random.stream("robot." + def.id + ".microphones")});
  }
  if (def.people_detector) {
    people_detector.emplace(*def.people_detector);
    people_schedule = {1.0 / def.people_detector->rate, 0};
  }
}

Eigen::Isometry3d RobotRuntime::microphones_pose() const {
  const int link = robot.description().find_link(hearing->microphones.array().link);
  return robot.link_poses()[static_cast<std::size_t>(link)];
}

void RobotRuntime::hash(core::StateHasher& hasher) const {
  robot.hash(hasher);
  hasher.add(command.linear).add(command.angular);
  for (const std::uint64_t word : motor_random.state()) hasher.add(word);
  for (const std::uint64_t word : sensor_random.state()) hasher.add(word);
  odometry.hash(hasher);
  for (const LaserSensor& sensor : lasers) hasher.add(sensor.schedule.next_tick);
  const auto add = [&](const Eigen::Vector3d& v) { hasher.add(v.x()).add(v.y()).add(v.z()); };
  for (const ImuSensor& imu : imus) {
    add(imu.last_pose.translation());
    add(imu.last_velocity);
    add(imu.reading.angular_velocity);
    add(imu.reading.linear_acceleration);
  }
  for (const ForceTorqueSensor& sensor : force_torque_sensors) {
    add(sensor.reading.force);
    add(sensor.reading.torque);
  }
  hasher.add(people_schedule.next_tick).add(odometry_schedule.next_tick);
  if (hearing) {
    for (const float sample : hearing->history.samples()) hasher.add(static_cast<double>(sample));
    hasher.add(hearing->block.first_sample).add(hearing->direction_schedule.next_tick).add(hearing->reading_tick);
    hasher.add(hearing->reading.has_value());
    if (hearing->reading) hasher.add(hearing->reading->azimuth).add(hearing->reading->power);
    for (const std::uint64_t word : hearing->random.state()) hasher.add(word);
  }
  for (const Contact& contact : contacts) hasher.add(contact.agent).add(contact.object).add(std::string_view(contact.part));
  hasher.add(held_object).add(grasped_at).add(grip_position).add(slipped);
  for (const Eigen::Vector3d* point : {&grip_from, &grip_to}) hasher.add(point->x()).add(point->y()).add(point->z());
  // What the controller and the sensors hold: the latest readings are state too.
  hasher.add(static_cast<int>(controller.kind)).add(controller.goal.has_value());
  hasher.add(static_cast<std::uint64_t>(search.looked_into.size()));
  for (const std::uint8_t done : search.looked_into) hasher.add(done != 0);
  hasher.add(search.room).add(search.scanning).add(search.turned).add(search.last_heading);
  hasher.add(search.closest).add(search.closer_tick).add(search.found);
  for (const LaserSensor& sensor : lasers) {
    hasher.add(sensor.reading.tick).add(sensor.reading.pose.x).add(sensor.reading.pose.y).add(sensor.reading.pose.theta).add(sensor.reading.height);
    hasher.add(std::span<const double>(sensor.reading.ranges));
  }
  hasher.add(people.tick).add(static_cast<std::uint64_t>(people.people.size()));
  for (const sensors::Detection& person : people.people) {
    hasher.add(person.agent).add(person.position.x()).add(person.position.y()).add(person.velocity.x()).add(person.velocity.y());
    hasher.add(person.range).add(person.bearing).add(person.face_visible);
  }
  hasher.add(odometry_reading.tick).add(odometry_reading.pose.x).add(odometry_reading.pose.y).add(odometry_reading.pose.theta);
  hasher.add(odometry_reading.twist.linear).add(odometry_reading.twist.angular);
}

bool due(Schedule& schedule, std::int64_t tick, double dt) {
  if (tick < schedule.next_tick) return false;
  // The k-th reading is at the first tick at or after k × period: no drift from rounding.
  const auto reading = static_cast<std::int64_t>(std::floor(tick * dt / schedule.period + 1e-9)) + 1;
  schedule.next_tick = static_cast<std::int64_t>(std::ceil(reading * schedule.period / dt - 1e-9));
  return true;
}

void add_human_body(sensors::RayScene& scene, const humans::BodyCapsules& body, double height) {
  for (const humans::Capsule& capsule : body) {
    const Eigen::Vector3d axis = capsule.to - capsule.from;
    const double r = capsule.radius;
    // The stretch of the axis within r of the plane.
    double t0 = 0.0, t1 = 1.0;
    if (std::abs(axis.z()) > 1e-9) {
      const double a = (height - r - capsule.from.z()) / axis.z(), b = (height + r - capsule.from.z()) / axis.z();
      t0 = std::max(0.0, std::min(a, b));
      t1 = std::min(1.0, std::max(a, b));
      if (t0 > t1) continue;
    } else if (std::abs(capsule.from.z() - height) >= r) {
      continue;
    }
    // Circles a radius apart along it cover a limb lying in the plane; a steep one needs one.
    const int circles = 1 + static_cast<int>(axis.head<2>().norm() * (t1 - t0) / r);
    for (int k = 0; k < circles; ++k) {
      const double t = t0 + (k + 0.5) / circles * (t1 - t0);
      const Eigen::Vector3d centre = capsule.from + t * axis;
      const double off_plane = centre.z() - height;
      if (std::abs(off_plane) >= r) continue;
      scene.add(sensors::Circle{Vec2(centre.x(), centre.y()), std::sqrt(r * r - off_plane * off_plane)});
    }
  }
}

}  // namespace hrisim::sim
