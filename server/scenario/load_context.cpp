#include "scenario/load_context.hpp"

#include <algorithm>

#include "world/occupancy_grid.hpp"

namespace hrisim::scenario::loading {

const json& member(const json& object, const char* key) {
  static const json kEmpty = json::object();
  const auto found = object.find(key);
  return found == object.end() ? kEmpty : *found;
}

std::vector<int> Context::members_of(const json& list, const std::string& pointer) {
  std::vector<int> members;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const int agent = resolve(names.agents, list[i], pointer + "/" + std::to_string(i), "agent");
    if (agent < 0) continue;
    if (std::find(members.begin(), members.end(), agent) != members.end()) {
      error(pointer + "/" + std::to_string(i), "agent '" + list[i].get<std::string>() + "' is listed twice");
    }
    members.push_back(agent);
  }
  return members;
}

int Context::resolve(const std::map<std::string, int>& table, const std::string& name, const std::string& pointer,
                     const std::string& what) {
  const auto found = table.find(name);
  if (found != table.end()) return found->second;
  std::string known;
  for (const auto& [candidate, unused] : table) known += (known.empty() ? "" : ", ") + candidate;
  error(pointer, "unknown " + what + " '" + name + "'" + (known.empty() ? " (none defined)" : " (known: " + known + ")"));
  return -1;
}

void Context::check_free(const Model& model, const Vec2& p, const std::string& pointer, const std::string& what) {
  if (!model.grid.in_bounds(model.grid.cell_of(p))) {
    error(pointer, what + " at (" + core::point_text(p) + ") is outside the map");
    return;
  }
  if (!model.grid.blocked(p)) return;
  for (const Obstacle& obstacle : model.obstacles) {
    if (world::contains(obstacle.polygon, p)) {
      error(pointer, what + " at (" + core::point_text(p) + ") is inside obstacle \"" + obstacle.name + "\"");
      return;
    }
  }
  error(pointer, what + " at (" + core::point_text(p) + ") is on an occupied or unknown cell of the map");
}

}  // namespace hrisim::scenario::loading
