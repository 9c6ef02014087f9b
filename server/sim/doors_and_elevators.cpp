#include "sim/doors_and_elevators.hpp"

#include <algorithm>

#include "sim/events.hpp"

namespace hrisim::sim {
namespace {

void set_door(const scenario::Model& model, State& state, int door, DoorPhase phase) {
  if (state.doors[door].phase == phase) return;
  state.doors[door].phase = phase;
  for (const scenario::Elevator& elevator : model.elevators) {
    if (std::find(elevator.doors.begin(), elevator.doors.end(), door) == elevator.doors.end()) continue;
    state.topics[elevator.topic + "/" + model.doors[door].name + "_state"] = std::string(phase_name(phase));
  }
  emit(model, state, model.doors[door].name, events::DoorState{door, phase});
}

bool someone_in_doorway(const scenario::Model& model, const State& state, int door) {
  const scenario::Door& geometry = model.doors[door];
  for (std::size_t a = 0; a < state.agents.size(); ++a) {
    if (!state.agents[a].active) continue;
    const Vec2& p = state.agents[a].position;
    const double clearance = model.agents[a].radius + geometry.thickness / 2 + scenario::kElevatorCurtainReach;
    if ((core::closest_point_on_segment(p, geometry.from, geometry.to) - p).norm() < clearance) return true;
  }
  return false;
}

/// Someone is still on their way into the cabin (to a place in it) or out of it through the open door.
bool rider_on_the_way(const scenario::Model& model, const scenario::Elevator& elevator, const State& state, int door) {
  const scenario::Door& doorway = model.doors[door];
  return std::any_of(state.agents.begin(), state.agents.end(), [&](const AgentState& agent) {
    if (!agent.active || !agent.navigation.under_way) return false;
    if (std::find(elevator.social_spaces.begin(), elevator.social_spaces.end(), agent.reservation.space.value) != elevator.social_spaces.end()) return true;
    // Leaving: the next legs of the path go through the doorway.
    Vec2 from = agent.position;
    for (std::size_t k = agent.navigation.path_index; k < agent.navigation.path.size() && k < agent.navigation.path_index + 3; ++k) {
      if (core::segments_cross(from, agent.navigation.path[k], doorway.from, doorway.to)) return true;
      from = agent.navigation.path[k];
    }
    return false;
  });
}

void update_elevator(const scenario::Model& model, State& state, int index) {
  const scenario::Elevator& elevator = model.elevators[index];
  ElevatorState& cabin = state.elevators[index];
  const int door = elevator.doors[cabin.floor];
  DoorState& door_state = state.doors[door];
  const double step = elevator.door_speed * model.dt / std::max(model.doors[door].width(), 1e-6);
  using Phase = ElevatorState::Phase;
  switch (cabin.phase) {
    case Phase::idle:
      if (cabin.queue.empty()) break;
      if (cabin.queue.front() == cabin.floor) {
        cabin.queue.pop_front();
        cabin.phase = Phase::opening;
        set_door(model, state, door, DoorPhase::opening);
      } else {
        cabin.destination = cabin.queue.front();
        cabin.phase = Phase::travelling;
        cabin.until_tick = state.tick + ticks(model, elevator.travel_time + elevator.settle_time);
        emit(model, state, elevator.name, events::ElevatorDeparted{cabin.floor, cabin.destination});
      }
      break;
    case Phase::travelling:
      if (state.tick >= cabin.until_tick) {
        cabin.floor = cabin.destination;
        cabin.phase = Phase::idle;
        emit(model, state, elevator.name, events::ElevatorArrived{index, cabin.floor});
      }
      break;
    case Phase::opening:
      door_state.opening = std::min(1.0, door_state.opening + step);
      if (door_state.opening >= 1.0) {
        cabin.phase = Phase::open;
        cabin.until_tick = std::max(cabin.reopened_until_tick, state.tick + ticks(model, elevator.open_time));
        set_door(model, state, door, DoorPhase::open);
      }
      break;
    case Phase::open: {
      // Asked again for this floor: stay open longer; asked for another floor: close and go.
      while (!cabin.queue.empty() && cabin.queue.front() == cabin.floor) {
        cabin.queue.pop_front();
        cabin.until_tick = state.tick + ticks(model, elevator.open_time);
      }
      const bool due = state.tick >= cabin.until_tick || (!cabin.queue.empty() && state.tick >= cabin.reopened_until_tick);
      const bool held = due && state.tick < cabin.until_tick + ticks(model, scenario::kElevatorPassengerHold) &&
                        rider_on_the_way(model, elevator, state, door);
      // The light curtain: a door does not start closing on someone standing in it.
      if (due && !held && !someone_in_doorway(model, state, door)) {
        cabin.phase = Phase::closing;
        set_door(model, state, door, DoorPhase::closing);
      }
      break;
    }
    case Phase::closing:
      if (someone_in_doorway(model, state, door)) {
        cabin.phase = Phase::opening;
        cabin.reopened_until_tick = state.tick + ticks(model, scenario::kElevatorReopenHold);
        set_door(model, state, door, DoorPhase::opening);
        break;
      }
      door_state.opening = std::max(0.0, door_state.opening - step);
      if (door_state.opening <= 0.0) {
        cabin.phase = Phase::idle;
        set_door(model, state, door, DoorPhase::closed);
        for (AgentState& agent : state.agents) {
          if (std::find(elevator.social_spaces.begin(), elevator.social_spaces.end(), agent.reservation.space.value) != elevator.social_spaces.end()) {
            agent.reservation.space = {};
            agent.reservation.slot = {};
          }
        }
      }
      break;
  }
}

}  // namespace

void update_doors_and_elevators(const scenario::Model& model, State& state) {
  // Requests published since the last tick reach the elevators in the order they were made.
  for (const Message& message : state.inbox) {
    for (std::size_t e = 0; e < model.elevators.size(); ++e) {
      const scenario::Elevator& elevator = model.elevators[e];
      if (message.topic != elevator.request_topic()) continue;
      int floor = -1;
      for (std::size_t d = 0; d < elevator.doors.size(); ++d) {
        if (message.text == model.doors[elevator.doors[d]].name || message.text == "floor" + std::to_string(d + 1)) floor = static_cast<int>(d);
      }
      if (floor < 0) {
        emit(model, state, elevator.name, events::ElevatorIgnoredRequest{message.text});
        continue;
      }
      std::deque<int>& queue = state.elevators[e].queue;
      if (queue.empty() || queue.back() != floor) queue.push_back(floor);
    }
  }
  state.inbox.clear();
  for (std::size_t e = 0; e < model.elevators.size(); ++e) update_elevator(model, state, static_cast<int>(e));
}

std::vector<std::size_t> blocked_door_cells(const scenario::Model& model, const State& state, double radius) {
  std::vector<std::size_t> cells;
  const world::OccupancyGrid& grid = model.grid;
  for (std::size_t d = 0; d < model.doors.size(); ++d) {
    if (!door_blocks(state, static_cast<int>(d))) continue;
    const scenario::Door& door = model.doors[d];
    // Cells whose centre a disc of `radius` could not occupy without touching the closed door.
    const double reach = radius + door.thickness / 2 + grid.resolution() / 2;
    const world::CellIndex low = grid.cell_of(door.from.cwiseMin(door.to) - Vec2(reach, reach));
    const world::CellIndex high = grid.cell_of(door.from.cwiseMax(door.to) + Vec2(reach, reach));
    for (int y = std::max(low.y, 0); y <= std::min(high.y, grid.height() - 1); ++y) {
      for (int x = std::max(low.x, 0); x <= std::min(high.x, grid.width() - 1); ++x) {
        const Vec2 centre = grid.center_of({x, y});
        if ((core::closest_point_on_segment(centre, door.from, door.to) - centre).norm() < reach) cells.push_back(grid.index({x, y}));
      }
    }
  }
  return cells;
}

}  // namespace hrisim::sim
