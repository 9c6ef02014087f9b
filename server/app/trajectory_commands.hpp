#pragma once
// `hrisim trajectories`: hrisim's crowd models against real pedestrians, a recorded file (ETH/UCY's
// four columns) predicted by the fixed protocol beside a constant-velocity baseline.
#include <string>
#include <vector>

namespace hrisim::app {

/// hrisim trajectories FILE [--json]: ADE and FDE of constant velocity, ORCA and the social force over
/// every window of FILE (humans/trajectory_prediction.hpp) with hrisim's default parameters, as a table
/// or as JSON. Exit 1 when FILE cannot be read or has no window, 2 on bad arguments.
int trajectories_command(const std::vector<std::string>& args);

}  // namespace hrisim::app
