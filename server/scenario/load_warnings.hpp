#pragma once
// What a scenario that loads may still get wrong, said as warnings at the parts concerned: goals a
// social-force person stops short of, waits for messages nothing sends.
#include "scenario/load_context.hpp"
#include "scenario/model.hpp"

namespace hrisim::scenario::loading {

/// Goals of social-force humans closer to an obstacle than such a human can get: it may stop short
/// of them (pedsim's σ = 0.8 m keeps a walker heading at a wall about 1.35 m away).
void warn_about_social_force_goals(const Model& model, Errors& warnings);

/// Waits for a message that no publish action and no elevator door ever sends: the step would hold
/// until the time limit (an IMHuS elevator choreography on a map without its elevator).
void warn_about_unpublished_waits(const Model& model, Errors& warnings);

}  // namespace hrisim::scenario::loading
