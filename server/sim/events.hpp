#pragma once
// What every phase of a tick shares: the simulation time of a tick, durations in whole ticks, and
// events stamped with the tick they happen at.
#include <cmath>
#include <cstdint>
#include <string>

#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// Simulation time at the state's tick, s.
inline double time_of(const scenario::Model& model, const State& state) { return static_cast<double>(state.tick) * model.dt; }

/// Whole ticks in a duration of simulation time.
inline std::int64_t ticks(const scenario::Model& model, double seconds) { return std::llround(seconds / model.dt); }

/// Records an event at the state's tick, and folds it into the state's events digest.
void emit(const scenario::Model& model, State& state, std::string subject, EventData data);

}  // namespace hrisim::sim
