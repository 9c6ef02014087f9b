#pragma once
// People's reactions to a robot in view, by their behaviour (humans::Behaviour, HuNavSim's): the
// surprised stop and look, the scared keep away, the curious approach and follow, the threatening
// stand in the robot's way. The reaction replaces where the person wanted to go for as long as the
// robot has been in view for the behaviour's duration; a once-only reaction does not come back.
#include <optional>

#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// The velocity person `agent` prefers this tick given its reaction, if any, to the nearest robot in
/// view; sets `watching_heading` when the reaction faces the robot. Emits "reaction_started" and
/// "reaction_ended".
core::Vec2 react_to_robots(const scenario::Model& model, State& state, int agent, const core::Vec2& preferred,
                           std::optional<double>& watching_heading);

}  // namespace hrisim::sim
