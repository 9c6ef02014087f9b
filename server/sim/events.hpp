#pragma once
// What every phase of a tick shares: the simulation time of a tick, durations in whole ticks, and
// events stamped with the tick they happen at.
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/state_hash.hpp"
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// Simulation time at the state's tick, s.
inline double time_of(const scenario::Model& model, const State& state) { return static_cast<double>(state.tick) * model.dt; }

/// Whole ticks in a duration of simulation time.
inline std::int64_t ticks(const scenario::Model& model, double seconds) { return std::llround(seconds / model.dt); }

/// Records an event at the state's tick.
inline void emit(const scenario::Model& model, State& state, std::string kind, std::string subject,
                 nlohmann::json data = nlohmann::json::object()) {
  core::StateHasher digest;
  digest.add(state.events_digest).add(state.tick).add(std::string_view(kind)).add(std::string_view(subject)).add(std::string_view(data.dump()));
  state.events_digest = digest.value();
  state.events.push_back({state.tick, time_of(model, state), std::move(kind), std::move(subject), std::move(data)});
}

}  // namespace hrisim::sim
