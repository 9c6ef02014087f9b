#pragma once
// Attractions (scenario::Attraction, Pedsim's <attraction>): walking people near one may turn aside to
// it for a while, then go on with what they were doing.
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// The tick's draws: each walking person (on their own way, not in a line, a seat, a group's
/// formation, a reaction or an attraction already) near an attraction turns aside to it with its
/// probability (event "attracted").
void draw_people_to_attractions(const scenario::Model& model, State& state);

}  // namespace hrisim::sim
