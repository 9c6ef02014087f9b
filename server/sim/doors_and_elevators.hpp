#pragma once
// Doors and elevators (IMHuS): requests published on an elevator's topic queue floors; a cabin opens
// its door, waits, closes (reopening for someone in the doorway) and travels. Closed doors block
// walking, planning, range sensors and the physics world.
#include <cstddef>
#include <vector>

#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// The tick's phase: the messages published since the last tick reach the elevators, then every
/// elevator and its doors move on.
void update_doors_and_elevators(const scenario::Model& model, State& state);

/// A door that is not fully open blocks the way.
inline bool door_blocks(const State& state, int door) { return state.doors[door].phase != DoorPhase::open; }

/// Grid cells a disc of `radius` cannot take without touching a door that blocks: for the planner.
std::vector<std::size_t> blocked_door_cells(const scenario::Model& model, const State& state, double radius);

}  // namespace hrisim::sim
