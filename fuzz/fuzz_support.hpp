#pragma once
// What the fuzz targets share: the options a server compiles uploads with (its bundled scenarios'
// folder, the default limits but smaller grids and episodes, so that one input stays quick), and a use
// of a compiled source that touches what a server would.
#include "scenario/source.hpp"
#include "sim/session.hpp"

namespace hrisim::fuzz {

inline scenario::SourceOptions source_options() {
  scenario::SourceOptions options;
  options.import.map_search_path = {HRISIM_SCENARIOS_DIR};
  options.load.map_search_path = {HRISIM_SCENARIOS_DIR};
  scenario::ScenarioLimits limits;
  limits.max_grid_cells = 1'000'000;
  limits.max_people = 200;
  limits.max_episode_ticks = 20'000;
  options.import.limits = options.load.limits = limits;
  return options;
}

/// Summarises a compiled scenario and its world geometry, as listing and map views do, and starts a
/// session of it for a few ticks, as creating one does.
inline void use(const scenario::CompiledSource& compiled) {
  if (!compiled.model) return;
  (void)scenario::summarize(*compiled.model);
  (void)scenario::world_geometry(*compiled.model);
  try {
    sim::Session session(compiled.model, 1);
    for (int tick = 0; tick < 3 && !session.state().finished; ++tick) session.tick();
  } catch (const core::Error&) {
    // A valid scenario a session refuses (a task that cannot place its human) says so; that is fine.
  }
}

}  // namespace hrisim::fuzz
