#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>

#include "core/json_schema.hpp"
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
/// Margin around everything the file places (obstacles, waypoints, agents) that makes up the map, m.
constexpr double kBoundsMargin = 1.0;
/// Pedsim agent types (Ped::Tagent::AgentType): 0 adult, 1 child, 2 robot, 3 elder.
const char* const kAgentTypes[] = {"adult", "child", "robot", "elder"};
/// A goal or a start is this far from every wall's centre line, m: an agent's radius (0.3), half the
/// wall's thickness and a margin, so that the agent's disc stands clear of the wall.
constexpr double kWallClearance = 0.4;
/// A cluster's agent is drawn again this many times at most when it lands too close to a wall.
constexpr int kPlacementTries = 50;
/// Goals are looked for within a waypoint's disc on rings this far apart, m.
constexpr double kGoalRingStep = 0.1;
/// A queue is reached within this distance of its head, m: its waiting line is not modelled, and a
/// point everyone of a cluster heads for would jam them round it.
constexpr double kQueueRadius = 1.0;
/// Grid resolutions an imported scene may get, finest first, m: the finest whose grid has at most
/// kImportGridCells cells (a scene hundreds of metres across gets a coarser grid, with a warning).
constexpr double kImportResolutions[] = {0.05, 0.1, 0.2, 0.25, 0.5, 1.0};
/// Cells an imported scene's grid may have at most (and never more than --max-grid-cells): a grid
/// this size and its distance field are built in about a second and take about 50 MB.
constexpr double kImportGridCells = 4e6;
/// A waypoint reached is one within this distance at least, m (Pedsim reads a missing or zero radius
/// as 0, which no walker would ever meet exactly).
constexpr double kMinWaypointRadius = 0.2;

/// A Pedsim waypoint: a disc of radius r, any point of which is what the file means.
struct Waypoint {
  double x = 0.0, y = 0.0, radius = 0.0;
  int line = 0;
};

struct Walls {
  std::vector<std::pair<core::Vec2, core::Vec2>> segments;

  bool clear(const core::Vec2& p) const {
    for (const auto& [a, b] : segments) {
      if ((core::closest_point_on_segment(p, a, b) - p).norm() < kWallClearance) return false;
    }
    return true;
  }

  /// The point of the disc nearest its centre that stands clear of every wall; the centre when none.
  core::Vec2 free_point(const core::Vec2& centre, double radius) const {
    if (clear(centre)) return centre;
    for (double ring = kGoalRingStep; ring <= radius + 1e-9; ring += kGoalRingStep) {
      const int directions = std::max(8, static_cast<int>(std::ceil(2.0 * std::numbers::pi * ring / kGoalRingStep)));
      for (int k = 0; k < directions; ++k) {
        const double angle = 2.0 * std::numbers::pi * k / directions;
        const core::Vec2 p = centre + ring * core::Vec2(std::cos(angle), std::sin(angle));
        if (clear(p)) return p;
      }
    }
    return centre;
  }
};

/// The axis-aligned extent of everything a file places.
struct Extent {
  core::Vec2 low{std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  core::Vec2 high = -low;
  void add(const core::Vec2& p, double margin = 0.0) {
    low = low.cwiseMin(p - core::Vec2(margin, margin));
    high = high.cwiseMax(p + core::Vec2(margin, margin));
  }
  bool empty() const { return low.x() > high.x(); }
};

}  // namespace

ImportResult import_pedsim(std::string_view xml, const ImportOptions& options) {
  ImportResult result;
  tinyxml2::XMLDocument document;
  if (!parse_xml(xml, document, result)) return result;
  XmlReader reader(result);
  const XMLElement* root = document.FirstChildElement();
  const std::string root_name = root->Name();
  if (root_name != "scenario" && root_name != "welcome") {
    reader.fail(root, "a Pedsim file has a <scenario> root element (or <welcome>, as libpedsim's examples)");
    return result;
  }

  const std::string dialect = !options.dialect.empty() ? options.dialect : root_name == "welcome" ? "libpedsim" : "pedsim_ros";
  if (dialect != "pedsim_ros" && dialect != "libpedsim") {
    reader.fail(nullptr, "unknown Pedsim dialect '" + dialect + "' (pedsim_ros or libpedsim)");
    return result;
  }

  ordered_json walls = ordered_json::array();
  Walls geometry;
  Extent extent;
  std::map<std::string, Waypoint> waypoints;
  std::vector<const XMLElement*> clusters;
  for (const XMLElement* element = root->FirstChildElement(); element; element = element->NextSiblingElement()) {
    const std::string name = element->Name();
    if (name == "obstacle") {
      const auto x1 = reader.number(element, "x1"), y1 = reader.number(element, "y1");
      const auto x2 = reader.number(element, "x2"), y2 = reader.number(element, "y2");
      if (!x1 || !y1 || !x2 || !y2) continue;
      result.origins.push_back({"/world/walls/" + std::to_string(walls.size()), element->GetLineNum()});
      walls.push_back({{"from", {*x1, *y1}}, {"to", {*x2, *y2}}});
      geometry.segments.push_back({{*x1, *y1}, {*x2, *y2}});
      extent.add({*x1, *y1});
      extent.add({*x2, *y2});
    } else if (name == "waypoint" || name == "queue") {
      // pedsim_ros registers every queue as a waypoint too (its head, a point).
      const auto id = reader.text(element, "id");
      const auto x = reader.number(element, "x"), y = reader.number(element, "y");
      const double radius = name == "waypoint" ? reader.optional_number(element, "r").value_or(0.0) : kQueueRadius;
      if (!id || !x || !y) continue;
      if (const auto behaviour = reader.optional_number(element, "b"); behaviour && *behaviour != 0.0) {
        reader.warn(element, "waypoint '" + *id + "' is a " + (*behaviour == 1.0 ? "source" : "sink") +
                                 "; hrisim treats it as a plain waypoint");
      }
      if (name == "queue") reader.warn(element, "queue '" + *id + "' is walked to as a waypoint; its waiting line is not modelled");
      waypoints[*id] = {*x, *y, std::max(radius, 0.0), element->GetLineNum()};
      extent.add({*x, *y}, radius);
    } else if (name == "agent" || name == "source") {
      clusters.push_back(element);
      // The cluster's area (its attributes are checked, with errors, where its agents are made).
      if (element->Attribute("x") && element->Attribute("y")) {
        const core::Vec2 centre(element->DoubleAttribute("x"), element->DoubleAttribute("y"));
        const core::Vec2 half(std::abs(element->DoubleAttribute("dx")) / 2, std::abs(element->DoubleAttribute("dy")) / 2);
        extent.add(centre - half);
        extent.add(centre + half);
      }
    } else {
      reader.warn(element, "unsupported element <" + name + "> ignored");
    }
  }
  if (extent.empty()) {
    reader.fail(root, "the file places nothing: no <obstacle>, <waypoint> or <agent> with a position");
    return result;
  }
  if (walls.empty()) reader.warn(root, "no <obstacle>: the map is open ground around the waypoints and agents");
  const core::Vec2 map_low = extent.low - core::Vec2(kBoundsMargin, kBoundsMargin);
  const core::Vec2 map_high = extent.high + core::Vec2(kBoundsMargin, kBoundsMargin);
  const core::Vec2 size = map_high - map_low;
  const auto cells_at = [&](double resolution) { return std::ceil(size.x() / resolution) * std::ceil(size.y() / resolution); };
  const double budget = std::min(kImportGridCells, static_cast<double>(options.limits.max_grid_cells));
  double resolution = kImportResolutions[0];
  for (const double candidate : kImportResolutions) {
    resolution = candidate;
    if (cells_at(candidate) <= budget) break;
  }
  if (resolution != kImportResolutions[0]) {
    reader.warn(root, "the scene spans " + core::number_text(std::round(size.x())) + " x " + core::number_text(std::round(size.y())) +
                          " m: its grid gets " + core::number_text(resolution) + " m cells (at " + core::number_text(kImportResolutions[0]) +
                          " m it would have " + core::number_text(cells_at(kImportResolutions[0])) + "); passages narrower than about " +
                          core::number_text(2 * resolution + 0.6) + " m may close");
  }

  // Each waypoint's goal: the free point of its disc nearest the centre (a centre on a wall's line is
  // common: the disc's free part is what the file means).
  ordered_json locations = ordered_json::object();
  std::map<std::string, std::pair<core::Vec2, double>> goals;
  for (const auto& [id, waypoint] : waypoints) {
    const core::Vec2 centre(waypoint.x, waypoint.y);
    const core::Vec2 goal = geometry.free_point(centre, waypoint.radius);
    const double radius = std::max(waypoint.radius - (goal - centre).norm(), kMinWaypointRadius);
    goals[id] = {goal, radius};
    locations[id] = {{"x", goal.x()}, {"y", goal.y()}, {"radius", radius}};
    result.origins.push_back({"/locations/" + core::pointer_token(id), waypoint.line});
  }

  core::Random random(kPlacementSeed);
  ordered_json humans = ordered_json::array(), robots = ordered_json::array();
  ordered_json actions = ordered_json::array();
  ordered_json tasks = ordered_json::object();
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
    std::vector<std::pair<std::string, int>> route;  ///< waypoints, with the lines that add them
    for (const XMLElement* child = cluster->FirstChildElement(); child; child = child->NextSiblingElement()) {
      const std::string child_name = child->Name();
      if (child_name != "addwaypoint" && child_name != "addqueue") {
        reader.warn(child, "unsupported element <" + child_name + "> ignored");
        continue;
      }
      const auto id = reader.text(child, "id");
      if (!id) continue;
      if (!waypoints.contains(*id)) {
        reader.fail(child, std::string("unknown ") + (child_name == "addqueue" ? "queue" : "waypoint") + " '" + *id + "'");
      } else {
        route.push_back({*id, child->GetLineNum()});
      }
    }
    const std::string kind = kAgentTypes[static_cast<int>(type)];
    const bool robot = kind == "robot";
    if (robot && !route.empty()) {
      reader.warn(cluster, "the robot agent's route is not walked: a robot is driven by its controller or a client (give it one)");
    }
    // The cluster's route as a compound task its people walk over and over: Pedsim's agents cycle through
    // their waypoints until the simulation stops.
    const std::string task = "route_" + std::to_string(tasks.size() + 1);
    if (!robot && !route.empty() && n > 0) {
      ordered_json gotos = ordered_json::array();
      for (const auto& [waypoint, line] : route) {
        const auto& [goal, radius] = goals[waypoint];
        result.origins.push_back({"/tasks/" + task + "/" + std::to_string(gotos.size()), line});
        gotos.push_back({{"goto", {{"pose", {{"x", goal.x()}, {"y", goal.y()}}}, {"radius", radius}}}});
      }
      tasks[task] = gotos;
      result.origins.push_back({"/tasks/" + task, cluster->GetLineNum()});
    }
    for (int i = 0; i < static_cast<int>(n); ++i) {
      const std::string id = (robot ? "robot_" : "agent_") + std::to_string(counter++);
      // Drawn in the cluster's area, again when too close to a wall (Pedsim's clusters often overlap them).
      core::Vec2 start(*x, *y);
      for (int attempt = 0; attempt < kPlacementTries; ++attempt) {
        start = {*x + (dx > 0 ? random.uniform(-dx / 2, dx / 2) : 0.0), *y + (dy > 0 ? random.uniform(-dy / 2, dy / 2) : 0.0)};
        if ((dx <= 0 && dy <= 0) || geometry.clear(start)) break;
      }
      ordered_json agent{{"id", id}, {"start", {{"x", start.x()}, {"y", start.y()}}}};
      if (robot) {
        result.origins.push_back({"/robots/" + std::to_string(robots.size()), cluster->GetLineNum()});
        robots.push_back(agent);
        continue;
      }
      agent["type"] = kind;
      agent["avoidance"] = "social_force";
      result.origins.push_back({"/humans/" + std::to_string(humans.size()), cluster->GetLineNum()});
      humans.push_back(agent);
      if (tasks.contains(task)) {
        result.origins.push_back({"/steps/0/actions/" + std::to_string(actions.size()), cluster->GetLineNum()});
        actions.push_back({{"agent", id}, {"task", task}, {"repeat", true}});
      }
    }
  }

  ordered_json& out = result.scenario;
  out["name"] = options.source_name.empty() ? "pedsim" : std::filesystem::path(options.source_name).stem().string();
  out["description"] = "Imported from the Pedsim scenario " +
                       (options.source_name.empty() ? std::string("file") : options.source_name) +
                       ": every agent walks its route of waypoints over and over, as Pedsim's agents cycle through "
                       "theirs, with the social force model and " + dialect + "'s parameters.";
  out["world"] = {{"bounds", {{"min", {map_low.x(), map_low.y()}}, {"max", {map_high.x(), map_high.y()}}}},
                  {"walls", walls}};
  if (resolution != kImportResolutions[0]) out["world"]["resolution"] = resolution;
  out["locations"] = locations;
  out["locomotion"] = {{"avoidance", "social_force"}};
  if (dialect == "pedsim_ros") {
    out["locomotion"]["social_force"] = {{"obstacle_sigma", kPedsimRosObstacleSigma}, {"social_factor", kPedsimRosSocialFactor}};
  }
  out["humans"] = humans;
  out["robots"] = robots;
  if (!tasks.empty()) out["tasks"] = tasks;
  out["steps"] = ordered_json::array();
  if (!actions.empty()) out["steps"].push_back({{"name", "walk"}, {"actions", actions}});
  return result;
}

}  // namespace hrisim::scenario
