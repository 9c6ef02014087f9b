#pragma once
// Robots with a model: before the crowd moves, each built-in controller (path follower, social
// navigation, turning on the spot) or an external command picks the base's command; after it, motors
// and bases advance — as far as walls, furniture, doors, people and other robots let their links —
// and the agents follow their bases.
#include "scenario/model.hpp"
#include "sim/physics_step.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// The tick's phase in which robots decide.
void decide_robots(const scenario::Model& model, State& state);

/// The tick's phase in which robots move: each as far along its motion as nothing solid stops it.
void move_robots(const scenario::Model& model, State& state, PhysicsBodies& physics);

}  // namespace hrisim::sim
