#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "core/math.hpp"
#include "core/random.hpp"
#include "scenario/import.hpp"
#include "scenario/xml_reader.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::ordered_json;
using tinyxml2::XMLElement;

/// Seed of the importer's own generator: agents of a cluster are placed at the same spots every time.
constexpr std::uint64_t kPlacementSeed = 1;
/// Margin around the obstacles' extent that makes up the map, in metres.
constexpr double kBoundsMargin = 1.0;
/// Pedsim agent types (Ped::Tagent::AgentType): 0 adult, 1 child, 2 robot, 3 elder.
const char* const kAgentTypes[] = {"adult", "child", "robot", "elder"};

struct Waypoint {
  double x, y, radius;
  int line;
};

}  // namespace

ImportResult import_pedsim(std::string_view xml, const ImportOptions& options) {
  ImportResult result;
  tinyxml2::XMLDocument document;
  if (!parse_xml(xml, document, result)) return result;
  XmlReader reader(result);
  const XMLElement* root = document.FirstChildElement();
  if (std::string(root->Name()) != "scenario") {
    reader.fail(root, "a Pedsim file has a <scenario> root element");
    return result;
  }

  ordered_json walls = ordered_json::array();
  core::Vec2 low(std::numeric_limits<double>::max(), std::numeric_limits<double>::max());
  core::Vec2 high = -low;
  std::map<std::string, Waypoint> waypoints;
  std::vector<const XMLElement*> clusters;
  for (const XMLElement* element = root->FirstChildElement(); element; element = element->NextSiblingElement()) {
    const std::string name = element->Name();
    if (name == "obstacle") {
      const auto x1 = reader.number(element, "x1"), y1 = reader.number(element, "y1");
      const auto x2 = reader.number(element, "x2"), y2 = reader.number(element, "y2");
      if (!x1 || !y1 || !x2 || !y2) continue;
      walls.push_back({{"from", {*x1, *y1}}, {"to", {*x2, *y2}}});
      low = low.cwiseMin(core::Vec2(std::min(*x1, *x2), std::min(*y1, *y2)));
      high = high.cwiseMax(core::Vec2(std::max(*x1, *x2), std::max(*y1, *y2)));
    } else if (name == "waypoint") {
      const auto id = reader.text(element, "id");
      const auto x = reader.number(element, "x"), y = reader.number(element, "y");
      const auto radius = reader.number(element, "r");
      if (!id || !x || !y || !radius) continue;
      if (const auto behaviour = reader.optional_number(element, "b"); behaviour && *behaviour != 0.0) {
        reader.warn(element, "waypoint '" + *id + "' is a " + (*behaviour == 1.0 ? "source" : "sink") +
                                 "; hrisim treats it as a plain waypoint");
      }
      waypoints[*id] = {*x, *y, std::max(*radius, 0.05), element->GetLineNum()};
    } else if (name == "agent" || name == "source") {
      clusters.push_back(element);
    } else {
      reader.warn(element, "unsupported element <" + name + "> ignored");
    }
  }
  if (walls.empty()) {
    reader.fail(root, "no <obstacle>: the map's extent comes from the obstacles");
    return result;
  }
  const core::Vec2 map_low = low - core::Vec2(kBoundsMargin, kBoundsMargin);
  const core::Vec2 map_high = high + core::Vec2(kBoundsMargin, kBoundsMargin);
  auto inside = [&](double x, double y) { return x > low.x() && x < high.x() && y > low.y() && y < high.y(); };

  ordered_json locations = ordered_json::object();
  for (const auto& [id, waypoint] : waypoints) {
    if (!inside(waypoint.x, waypoint.y)) {
      result.warnings.push_back({waypoint.line, "<waypoint>: waypoint '" + id + "' at (" +
                                                    core::point_text({waypoint.x, waypoint.y}) + ") lies outside the walls and is left out"});
      continue;
    }
    locations[id] = {{"x", waypoint.x}, {"y", waypoint.y}, {"radius", waypoint.radius}};
  }

  core::Random random(kPlacementSeed);
  ordered_json humans = ordered_json::array(), robots = ordered_json::array();
  ordered_json actions = ordered_json::array();
  int counter = 0;
  for (const XMLElement* cluster : clusters) {
    const auto x = reader.number(cluster, "x"), y = reader.number(cluster, "y");
    const double dx = reader.optional_number(cluster, "dx").value_or(0.0), dy = reader.optional_number(cluster, "dy").value_or(0.0);
    const double n = reader.optional_number(cluster, "n").value_or(1.0);
    const double type = reader.optional_number(cluster, "type").value_or(0.0);
    if (!x || !y) continue;
    if (type < 0 || type > 3 || type != std::floor(type)) {
      reader.fail(cluster, "type must be 0 (adult), 1 (child), 2 (robot) or 3 (elder)");
      continue;
    }
    if (n < 0 || n != std::floor(n)) {
      reader.fail(cluster, "n must be a whole number of agents");
      continue;
    }
    // Checked before any agent is made: a few bytes of XML may ask for millions.
    if (counter + n > options.limits.max_people) {
      reader.fail(cluster, "with this cluster's agents the file has more than the " + std::to_string(options.limits.max_people) +
                               " people a scenario may hold (--max-people)");
      break;
    }
    if (std::string(cluster->Name()) == "source") {
      reader.warn(cluster, "a source spawns its agents once; Pedsim's respawning is not modelled");
    }
    std::vector<std::string> route;
    for (const XMLElement* child = cluster->FirstChildElement(); child; child = child->NextSiblingElement()) {
      const std::string child_name = child->Name();
      if (child_name != "addwaypoint") {
        reader.warn(child, "unsupported element <" + child_name + "> ignored");
        continue;
      }
      const auto id = reader.text(child, "id");
      if (!id) continue;
      if (!waypoints.contains(*id)) {
        reader.fail(child, "unknown waypoint '" + *id + "'");
      } else if (locations.contains(*id)) {
        route.push_back(*id);
      }
    }
    const std::string kind = kAgentTypes[static_cast<int>(type)];
    for (int i = 0; i < static_cast<int>(n); ++i) {
      const std::string id = (kind == "robot" ? "robot_" : "agent_") + std::to_string(counter++);
      const double px = *x + (dx > 0 ? random.uniform(-dx / 2, dx / 2) : 0.0);
      const double py = *y + (dy > 0 ? random.uniform(-dy / 2, dy / 2) : 0.0);
      ordered_json agent{{"id", id}, {"start", {{"x", px}, {"y", py}}}};
      if (kind == "robot") {
        robots.push_back(agent);
        continue;  // robots are driven by their controller, not by waypoints
      }
      agent["type"] = kind;
      agent["avoidance"] = "social_force";
      humans.push_back(agent);
      // Each waypoint a pose within its radius: Pedsim's waypoints are areas several agents share.
      for (const std::string& waypoint : route) {
        const Waypoint& w = waypoints[waypoint];
        actions.push_back({{"agent", id}, {"goto", {{"pose", {{"x", w.x}, {"y", w.y}}}, {"radius", w.radius}}}});
      }
    }
  }

  ordered_json& out = result.scenario;
  out["name"] = options.source_name.empty() ? "pedsim" : std::filesystem::path(options.source_name).stem().string();
  out["description"] = "Imported from the Pedsim scenario " +
                       (options.source_name.empty() ? std::string("file") : options.source_name) +
                       ": every agent walks its waypoints once, with the social force model.";
  out["world"] = {{"bounds", {{"min", {map_low.x(), map_low.y()}}, {"max", {map_high.x(), map_high.y()}}}},
                  {"walls", walls}};
  out["locations"] = locations;
  out["locomotion"] = {{"avoidance", "social_force"}};
  out["humans"] = humans;
  out["robots"] = robots;
  out["steps"] = ordered_json::array();
  if (!actions.empty()) out["steps"].push_back({{"name", "walk"}, {"actions", actions}});
  return result;
}

}  // namespace hrisim::scenario
