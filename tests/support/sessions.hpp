#pragma once
// A live session in a known state, for tests of what front ends build from one.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "scenario/load.hpp"
#include "sim/session.hpp"

namespace hrisim::testing {

/// The bundled elevator with its robot, two seconds in (people walking, a laser reading taken).
inline std::unique_ptr<sim::Session> elevator_session() {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/elevator.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  auto session = std::make_unique<sim::Session>(loaded.model, 1);
  for (int tick = 0; tick < 120; ++tick) session->tick();
  return session;
}

}  // namespace hrisim::testing
