#pragma once
// Sensing: after the tick, the sensors of robots with a model read the world, each at its own rate and
// from its robot's sensor stream — odometry, lasers and infrared, the people detector — and the bumper
// reports what the robot's links touch (contact events as contacts start and end).
#include "scenario/model.hpp"
#include "sensors/ray_scene.hpp"
#include "sim/human_bodies.hpp"
#include "sim/physics_step.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// The map, closed doors, movable objects, people and other robots at `height`, as range sensors see
/// them (robot `robot_agent` itself left out).
sensors::RayScene range_scene(const scenario::Model& model, const State& state, const HumanBodies& bodies, double height, int robot_agent);

/// The tick's sensing phase.
void sense(const scenario::Model& model, State& state, const PhysicsBodies& physics, const HumanBodies& bodies);

}  // namespace hrisim::sim
