#pragma once
// HuNavSim agent files a test builds: issue 40's alias bomb, whose aliases multiply a few bytes into
// thousands of goals.
#include <string>

namespace hrisim::testing {

/// `agents` people whose block, written once under an anchor with a list of `goals` goals, is aliased
/// into every other one (100 agents, 10,000 goals: a 64 KB file that took 56 s and 1.7 GB). Lines: 3
/// the names, 4 the anchored block, 8 on the aliases.
inline std::string aliased_goals(int agents, int goals) {
  std::string yaml = "hunav_loader:\n  ros__parameters:\n    agents: [a0";
  for (int i = 1; i < agents; ++i) yaml += ", a" + std::to_string(i);
  yaml += "]\n    a0: &agent\n      init_pose: {x: 1, y: 1}\n      g: {x: 2, y: 2}\n      goals: [g";
  for (int g = 1; g < goals; ++g) yaml += ", g";
  yaml += "]\n";
  for (int i = 1; i < agents; ++i) yaml += "    a" + std::to_string(i) + ": *agent\n";
  return yaml;
}

}  // namespace hrisim::testing
