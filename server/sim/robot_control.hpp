#pragma once
// Robots with a model: before the crowd moves, each built-in controller (path follower, social
// navigation, turning on the spot) or an external command picks the base's command; after it, motors
// and bases advance and the agents follow their bases.
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// The tick's phase in which robots decide.
void decide_robots(const scenario::Model& model, State& state);

/// The tick's phase in which robots move.
void move_robots(const scenario::Model& model, State& state);

}  // namespace hrisim::sim
