#include <tinyxml2.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "core/json_schema.hpp"
#include "core/math.hpp"
#include "core/random.hpp"
#include "scenario/import.hpp"
#include "scenario/xml_reader.hpp"
#include "world/occupancy_grid.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::ordered_json;
using tinyxml2::XMLElement;

/// pedsim_ros adds a source's people again this often, s (its parameter spawn_period's default).
constexpr double kSpawnPeriod = 5.0;
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
/// The location at a queue's head is reached within this distance, m (the queue itself is joined at
/// the end of its line), and a
/// point everyone of a cluster heads for would jam them round it.
constexpr double kQueueRadius = 1.0;
/// Grid resolutions an imported scene may get, finest first, m: the finest whose grid has at most
/// kImportGridCells cells (a scene hundreds of metres across gets a coarser grid, with a warning).
constexpr double kImportResolutions[] = {0.05, 0.1, 0.2, 0.25, 0.5, 1.0};
/// Cells an imported scene's grid may have at most (and never more than --max-grid-cells): a grid
/// this size and its distance field are built in about a second and take about 50 MB.
constexpr double kImportGridCells = 4e6;

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

  /// The point of the disc nearest its centre that stands clear of every wall and is `wanted`; none
  /// when there is no such point.
  template <class Wanted>
  std::optional<core::Vec2> free_point(const core::Vec2& centre, double radius, const Wanted& wanted) const {
    if (clear(centre) && wanted(centre)) return centre;
    for (double ring = kGoalRingStep; ring <= radius + 1e-9; ring += kGoalRingStep) {
      const int directions = std::max(8, static_cast<int>(std::ceil(2.0 * std::numbers::pi * ring / kGoalRingStep)));
      for (int k = 0; k < directions; ++k) {
        const double angle = 2.0 * std::numbers::pi * k / directions;
        const core::Vec2 p = centre + ring * core::Vec2(std::cos(angle), std::sin(angle));
        if (clear(p) && wanted(p)) return p;
      }
    }
    return std::nullopt;
  }
};

/// The floor's connected regions at a person's clearance from the walls: a waypoint's goal is put in
/// a region its walkers start in (a disc across a wall has free points on both sides).
class Regions {
 public:
  Regions(const Walls& walls, const core::Vec2& low, const core::Vec2& high, double resolution)
      : grid_(resolution, low, static_cast<int>(std::ceil((high.x() - low.x()) / resolution)),
              static_cast<int>(std::ceil((high.y() - low.y()) / resolution))) {
    // Each wall two cells thick, so that no diagonal step crosses it.
    for (const auto& [a, b] : walls.segments) {
      const core::Vec2 along = (b - a).norm() > 1e-9 ? core::Vec2((b - a).normalized()) : core::Vec2(1.0, 0.0);
      const core::Vec2 side(-along.y() * resolution, along.x() * resolution);
      const core::Vec2 ends = along * resolution;
      grid_.fill_polygon({a - ends + side, b + ends + side, b + ends - side, a - ends - side});
    }
    const world::DistanceField field(grid_);
    label_.assign(static_cast<std::size_t>(grid_.width()) * grid_.height(), -1);
    int next = 0;
    for (std::size_t seed = 0; seed < label_.size(); ++seed) {
      if (label_[seed] >= 0 || field.distance(seed) < kWallClearance - resolution) continue;
      std::vector<std::size_t> frontier{seed};
      label_[seed] = next;
      while (!frontier.empty()) {
        const world::CellIndex c = grid_.cell_at(frontier.back());
        frontier.pop_back();
        for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const world::CellIndex n{c.x + dx, c.y + dy};
          if (!grid_.in_bounds(n)) continue;
          const std::size_t i = grid_.index(n);
          if (label_[i] >= 0 || field.distance(i) < kWallClearance - resolution) continue;
          label_[i] = next;
          frontier.push_back(i);
        }
      }
      ++next;
    }
  }

  /// The region of a point; -1 off the floor (too near a wall, or outside the map).
  int at(const core::Vec2& p) const {
    const world::CellIndex c = grid_.cell_of(p);
    return grid_.in_bounds(c) ? label_[grid_.index(c)] : -1;
  }

 private:
  world::OccupancyGrid grid_;
  std::vector<int> label_;
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

/// A cluster's route: its waypoints' ids, each with the line of the element that adds it.
using Route = std::vector<std::pair<std::string, int>>;

/// Reads one Pedsim file: its elements (walls, waypoints, clusters), the map's extent and grid, each
/// waypoint's goal, the clusters' people and routes, then the native scenario.
class PedsimImporter {
 public:
  PedsimImporter(const ImportOptions& options, ImportResult& result) : options_(options), result_(result), reader_(result) {}

  void run(const tinyxml2::XMLDocument& document) {
    const XMLElement* root = document.FirstChildElement();
    const std::string root_name = root->Name();
    if (root_name != "scenario" && root_name != "welcome") {
      reader_.fail(root, "a Pedsim file has a <scenario> root element (or <welcome>, as libpedsim's examples)");
      return;
    }
    dialect_ = !options_.dialect.empty() ? options_.dialect : root_name == "welcome" ? "libpedsim" : "pedsim_ros";
    if (dialect_ != "pedsim_ros" && dialect_ != "libpedsim") {
      reader_.fail(nullptr, "unknown Pedsim dialect '" + dialect_ + "' (pedsim_ros or libpedsim)");
      return;
    }
    for (const XMLElement* element = root->FirstChildElement(); element; element = element->NextSiblingElement()) read_element(element);
    if (extent_.empty()) {
      reader_.fail(root, "the file places nothing: no <obstacle>, <waypoint> or <agent> with a position");
      return;
    }
    if (walls_.empty()) reader_.warn(root, "no <obstacle>: the map is open ground around the waypoints and agents");
    if (!choose_resolution(root)) return;
    place_goals();
    for (const XMLElement* cluster : clusters_) {
      if (!read_cluster(cluster)) break;
    }
    if (result_.errors.empty()) spawn_from_sources();
    write();
  }

 private:
  void read_element(const XMLElement* element) {
    const std::string name = element->Name();
    if (name == "obstacle") {
      const auto x1 = reader_.number(element, "x1"), y1 = reader_.number(element, "y1");
      const auto x2 = reader_.number(element, "x2"), y2 = reader_.number(element, "y2");
      if (!x1 || !y1 || !x2 || !y2) return;
      result_.origins.push_back({"/world/walls/" + std::to_string(walls_.size()), element->GetLineNum()});
      walls_.push_back({{"from", {*x1, *y1}}, {"to", {*x2, *y2}}});
      geometry_.segments.push_back({{*x1, *y1}, {*x2, *y2}});
      extent_.add({*x1, *y1});
      extent_.add({*x2, *y2});
    } else if (name == "waypoint" || name == "queue") {
      // pedsim_ros registers every queue as a waypoint too (its head).
      const auto id = reader_.text(element, "id");
      const auto x = reader_.number(element, "x"), y = reader_.number(element, "y");
      const double radius = name == "waypoint" ? reader_.optional_number(element, "r").value_or(0.0) : kQueueRadius;
      if (!id || !x || !y) return;
      // pedsim_ros's waypoint behaviours: 2 is a sink, whose walkers leave the scene on reaching it; 1
      // (a source) it does nothing with.
      if (reader_.optional_number(element, "b") == 2.0) sinks_.insert(*id);
      if (name == "queue") {
        // pedsim_ros reads `direction` in degrees; its line runs back from the head against it.
        const double direction = reader_.optional_number(element, "direction").value_or(0.0);
        queue_directions_[*id] = direction * std::numbers::pi / 180.0;
      }
      waypoints_[*id] = {*x, *y, std::max(radius, 0.0), element->GetLineNum()};
      extent_.add({*x, *y}, radius);
    } else if (name == "attraction") {
      const auto id = reader_.text(element, "id");
      const auto x = reader_.number(element, "x"), y = reader_.number(element, "y");
      const double width = reader_.optional_number(element, "width").value_or(1.0), height = reader_.optional_number(element, "height").value_or(1.0);
      const double strength = reader_.optional_number(element, "strength").value_or(1.0);
      if (!id || !x || !y) return;
      if (width <= 0 || height <= 0 || strength < 0) {
        reader_.fail(element, "an attraction's width and height must be more than 0 and its strength at least 0");
        return;
      }
      result_.origins.push_back({"/attractions/" + core::pointer_token(*id), element->GetLineNum()});
      attractions_[*id] = {{"x", *x}, {"y", *y}, {"width", width}, {"height", height}, {"strength", strength}};
      extent_.add({*x - width / 2, *y - height / 2});
      extent_.add({*x + width / 2, *y + height / 2});
    } else if (name == "agent" || name == "source") {
      clusters_.push_back(element);
      // The cluster's area (its attributes are checked, with errors, where its agents are made).
      if (element->Attribute("x") && element->Attribute("y")) {
        const core::Vec2 centre(element->DoubleAttribute("x"), element->DoubleAttribute("y"));
        const core::Vec2 half(std::abs(element->DoubleAttribute("dx")) / 2, std::abs(element->DoubleAttribute("dy")) / 2);
        extent_.add(centre - half);
        extent_.add(centre + half);
      }
    } else {
      reader_.warn(element, "unsupported element <" + name + "> ignored");
    }
  }

  /// The finest grid resolution whose grid fits the budget; a warning when it is not the default, an
  /// error (false) when none fits.
  bool choose_resolution(const XMLElement* root) {
    low_ = extent_.low - core::Vec2(kBoundsMargin, kBoundsMargin);
    high_ = extent_.high + core::Vec2(kBoundsMargin, kBoundsMargin);
    const core::Vec2 size = high_ - low_;
    const auto cells_at = [&](double resolution) { return std::ceil(size.x() / resolution) * std::ceil(size.y() / resolution); };
    const double budget = std::min(kImportGridCells, static_cast<double>(options_.limits.max_grid_cells));
    for (const double candidate : kImportResolutions) {
      resolution_ = candidate;
      if (cells_at(candidate) <= budget) break;
    }
    if (!(cells_at(resolution_) <= budget)) {
      reader_.fail(root, "the scene spans " + core::number_text(size.x()) + " x " + core::number_text(size.y()) + " m: more than a grid of " +
                             core::number_text(budget) + " cells of " + core::number_text(resolution_) + " m holds");
      return false;
    }
    if (resolution_ == kImportResolutions[0]) return true;
    reader_.warn(root, "the scene spans " + core::number_text(std::round(size.x())) + " x " + core::number_text(std::round(size.y())) +
                           " m: its grid gets " + core::number_text(resolution_) + " m cells (at " + core::number_text(kImportResolutions[0]) +
                           " m it would have " + core::number_text(cells_at(kImportResolutions[0])) + "); passages narrower than about " +
                           core::number_text(2 * resolution_ + 0.6) + " m may close");
    return true;
  }

  /// Each waypoint's goal: the free point of its disc nearest the centre (a centre on a wall's line is
  /// common: the disc's free part is what the file means) in a region the agents heading there start in.
  void place_goals() {
    const Regions regions(geometry_, low_, high_, resolution_);
    std::map<std::string, std::set<int>> starts;  // per waypoint: the regions of the clusters whose routes take it
    for (const XMLElement* cluster : clusters_) {
      if (cluster->IntAttribute("type") == 2) continue;  // a robot's route is not walked
      const std::set<int> from = cluster_regions(cluster, regions);
      for (const XMLElement* child = cluster->FirstChildElement(); child; child = child->NextSiblingElement()) {
        const char* id = child->Attribute("id");
        if (!id) continue;
        starts[id].insert(from.begin(), from.end());
        if (sinks_.contains(id)) break;  // the rest of the route is never walked
      }
    }
    for (const auto& [id, waypoint] : waypoints_) {
      const core::Vec2 centre(waypoint.x, waypoint.y);
      const std::set<int>& from = starts[id];
      const auto reachable = [&](const core::Vec2& p) { return from.empty() || from.contains(regions.at(p)); };
      auto goal = geometry_.free_point(centre, waypoint.radius, reachable);
      if (!goal) {
        goal = geometry_.free_point(centre, waypoint.radius, [](const core::Vec2&) { return true; }).value_or(centre);
        if (!from.empty()) {
          result_.warnings.push_back({waypoint.line, "waypoint '" + id + "': no free point of its disc can be reached from where the agents "
                                                     "heading there start; they will report it unreachable"});
        }
      }
      // At least the default radius: Pedsim reads a missing r as 0, a point no walker meets exactly.
      const double radius = std::max(waypoint.radius - (*goal - centre).norm(), kDefaultGoalRadius);
      goals_[id] = {*goal, radius};
      locations_[id] = {{"x", goal->x()}, {"y", goal->y()}, {"radius", radius}};
      result_.origins.push_back({"/locations/" + core::pointer_token(id), waypoint.line});
    }
  }

  /// The regions a cluster's area covers (sampled on a lattice; the nearest region within a metre of a
  /// point cluster).
  std::set<int> cluster_regions(const XMLElement* cluster, const Regions& regions) const {
    std::set<int> found;
    if (!cluster->Attribute("x") || !cluster->Attribute("y")) return found;
    const core::Vec2 centre(cluster->DoubleAttribute("x"), cluster->DoubleAttribute("y"));
    const core::Vec2 half(std::abs(cluster->DoubleAttribute("dx")) / 2, std::abs(cluster->DoubleAttribute("dy")) / 2);
    constexpr int kLattice = 5;
    for (int i = 0; i < kLattice; ++i) {
      for (int j = 0; j < kLattice; ++j) {
        const core::Vec2 p = centre + core::Vec2(half.x() * (2.0 * i / (kLattice - 1) - 1), half.y() * (2.0 * j / (kLattice - 1) - 1));
        if (const int region = regions.at(p); region >= 0) found.insert(region);
      }
    }
    if (found.empty()) {
      if (const auto near = geometry_.free_point(centre, 1.0, [&](const core::Vec2& p) { return regions.at(p) >= 0; })) found.insert(regions.at(*near));
    }
    return found;
  }

  Route read_route(const XMLElement* cluster) {
    Route route;
    for (const XMLElement* child = cluster->FirstChildElement(); child; child = child->NextSiblingElement()) {
      const std::string name = child->Name();
      if (name != "addwaypoint" && name != "addqueue") {
        reader_.warn(child, "unsupported element <" + name + "> ignored");
        continue;
      }
      const auto id = reader_.text(child, "id");
      if (!id) continue;
      if (!waypoints_.contains(*id)) {
        reader_.fail(child, std::string("unknown ") + (name == "addqueue" ? "queue" : "waypoint") + " '" + *id + "'");
      } else {
        route.push_back({*id, child->GetLineNum()});
      }
    }
    return route;
  }

  /// The route as a routine its people walk over and over (Pedsim's agents cycle through their
  /// waypoints until the simulation stops); its name.
  std::string route_routine(const XMLElement* cluster, const Route& route) {
    const std::string routine = "route_" + std::to_string(routines_.size() + 1);
    ordered_json gotos = ordered_json::array();
    for (const auto& [waypoint, line] : route) {
      const auto& [goal, radius] = goals_[waypoint];
      result_.origins.push_back({"/routines/" + routine + "/" + std::to_string(gotos.size()), line});
      // A queue's id, given by addqueue or addwaypoint alike, has its people wait in line there.
      if (queue_directions_.contains(waypoint)) {
        gotos.push_back({{"queue", waypoint}});
      } else {
        gotos.push_back({{"goto", {{"pose", {{"x", goal.x()}, {"y", goal.y()}}}, {"radius", radius}}}});
      }
      if (sinks_.contains(waypoint)) {  // whoever reaches a sink leaves: the rest of the route is never walked
        result_.origins.push_back({"/routines/" + routine + "/" + std::to_string(gotos.size()), line});
        gotos.push_back({{"leave", ordered_json::object()}});
        break;
      }
    }
    routines_[routine] = gotos;
    result_.origins.push_back({"/routines/" + routine, cluster->GetLineNum()});
    return routine;
  }

  /// A cluster's people, placed in its area, and their route; false once the people limit is passed.
  bool read_cluster(const XMLElement* cluster) {
    const auto x = reader_.number(cluster, "x"), y = reader_.number(cluster, "y");
    const double dx = reader_.optional_number(cluster, "dx").value_or(0.0), dy = reader_.optional_number(cluster, "dy").value_or(0.0);
    const double n = reader_.optional_number(cluster, "n").value_or(1.0);
    const double type = reader_.optional_number(cluster, "type").value_or(0.0);
    if (!x || !y) return true;
    if (type < 0 || type > 3 || type != std::floor(type)) {
      reader_.fail(cluster, "type must be 0 (adult), 1 (child), 2 (robot) or 3 (elder)");
      return true;
    }
    if (n < 0 || n != std::floor(n)) {
      reader_.fail(cluster, "n must be a whole number of agents");
      return true;
    }
    // Checked before any agent is made: a few bytes of XML may ask for millions.
    if (people_ + n > options_.limits.max_people) {
      reader_.fail(cluster, "with this cluster's agents the file has more than the " + std::to_string(options_.limits.max_people) +
                                " people a scenario may hold (--max-people)");
      return false;
    }
    const Route route = read_route(cluster);
    const std::string kind = kAgentTypes[static_cast<int>(type)];
    const bool robot = kind == "robot";
    if (robot && !route.empty()) {
      reader_.warn(cluster, "the robot agent's route is not walked: a robot is driven by its controller or a client (give it one)");
    }
    const std::string routine = !robot && !route.empty() && n > 0 ? route_routine(cluster, route) : "";
    const Area area{*x, *y, dx, dy};
    for (int i = 0; i < static_cast<int>(n); ++i) add_person(cluster, area, kind, routine, 0.0);
    if (std::string(cluster->Name()) == "source" && n > 0) sources_.push_back({cluster, area, static_cast<int>(n), routine});
    return true;
  }

  /// Where a cluster places its people: dx × dy around (x, y).
  struct Area {
    double x = 0.0, y = 0.0, dx = 0.0, dy = 0.0;
  };

  /// A person of a cluster, drawn in its area (again when too close to a wall: Pedsim's clusters often
  /// overlap them), walking the cluster's route from `enters_at` on.
  void add_person(const XMLElement* cluster, const Area& area, const std::string& kind, const std::string& routine, double enters_at) {
    const bool robot = kind == "robot";
    const std::string id = (robot ? "robot_" : "agent_") + std::to_string(people_++);
    core::Vec2 start(area.x, area.y);
    for (int attempt = 0; attempt < kPlacementTries; ++attempt) {
      start = {area.x + (area.dx > 0 ? random_.uniform(-area.dx / 2, area.dx / 2) : 0.0), area.y + (area.dy > 0 ? random_.uniform(-area.dy / 2, area.dy / 2) : 0.0)};
      if ((area.dx <= 0 && area.dy <= 0) || geometry_.clear(start)) break;
    }
    ordered_json agent{{"id", id}, {"start", {{"x", start.x()}, {"y", start.y()}}}};
    ordered_json& list = robot ? robots_ : humans_;
    result_.origins.push_back({std::string(robot ? "/robots/" : "/humans/") + std::to_string(list.size()), cluster->GetLineNum()});
    if (robot) {
      list.push_back(agent);
      return;
    }
    agent["type"] = kind;
    agent["avoidance"] = "social_force";
    if (enters_at > 0.0) agent["enters_at"] = enters_at;
    list.push_back(agent);
    if (routine.empty()) return;
    result_.origins.push_back({"/steps/0/actions/" + std::to_string(actions_.size()), cluster->GetLineNum()});
    actions_.push_back({{"agent", id}, {"routine", routine}, {"repeat", true}});
  }

  /// pedsim_ros's sources add their n people again every kSpawnPeriod for as long as the simulation
  /// runs: here every round until the time limit whose people fit in the people limit, each person
  /// entering at their round's time (adults, as pedsim_ros spawns them).
  void spawn_from_sources() {
    for (const Source& source : sources_) {
      const int rounds = static_cast<int>(std::ceil(kDefaultTimeLimit / kSpawnPeriod)) - 1;
      const int room = std::max(options_.limits.max_people - people_, 0) / source.n;
      if (room < rounds) {
        reader_.warn(source.element, "this source adds " + std::to_string(source.n) + " people every " + core::number_text(kSpawnPeriod) +
                                         " s: only the first " + std::to_string(room) + " of its " + std::to_string(rounds) +
                                         " rounds fit in the people a scenario may hold (--max-people)");
      }
      for (int round = 1; round <= std::min(rounds, room); ++round) {
        for (int i = 0; i < source.n; ++i) add_person(source.element, source.area, "adult", source.routine, round * kSpawnPeriod);
      }
    }
  }

  void write() {
    ordered_json& out = result_.scenario;
    out["name"] = options_.source_name.empty() ? "pedsim" : std::filesystem::path(options_.source_name).stem().string();
    out["description"] = "Imported from the Pedsim scenario " + (options_.source_name.empty() ? std::string("file") : options_.source_name) +
                         ": every agent walks its route of waypoints over and over, as Pedsim's agents cycle through "
                         "theirs, with the social force model and " + dialect_ + "'s parameters.";
    out["world"] = {{"bounds", {{"min", {low_.x(), low_.y()}}, {"max", {high_.x(), high_.y()}}}}, {"walls", walls_}};
    if (resolution_ != kImportResolutions[0]) out["world"]["resolution"] = resolution_;
    out["locations"] = locations_;
    if (!attractions_.empty()) out["attractions"] = attractions_;
    if (!queue_directions_.empty()) {
      ordered_json queues = ordered_json::object();
      for (const auto& [id, direction] : queue_directions_) {
        const core::Vec2& head = goals_[id].first;
        queues[id] = {{"x", head.x()}, {"y", head.y()}, {"theta", direction}};
        result_.origins.push_back({"/queues/" + core::pointer_token(id), waypoints_[id].line});
      }
      out["queues"] = queues;
    }
    out["locomotion"] = {{"avoidance", "social_force"}};
    if (dialect_ == "pedsim_ros") {
      out["locomotion"]["social_force"] = {{"obstacle_sigma", kPedsimRosObstacleSigma}, {"social_factor", kPedsimRosSocialFactor}};
    }
    out["humans"] = humans_;
    out["robots"] = robots_;
    if (!routines_.empty()) out["routines"] = routines_;
    out["steps"] = ordered_json::array();
    if (!actions_.empty()) out["steps"].push_back({{"name", "walk"}, {"actions", actions_}});
  }

  const ImportOptions& options_;
  ImportResult& result_;
  XmlReader reader_;
  std::string dialect_;
  ordered_json walls_ = ordered_json::array();
  Walls geometry_;
  Extent extent_;
  std::map<std::string, Waypoint> waypoints_;
  std::map<std::string, double> queue_directions_;
  std::set<std::string> sinks_;
  ordered_json attractions_ = ordered_json::object();  ///< waypoints whose walkers leave the scene on reaching them (b="2")
  /// A source's cluster, its area and people per round, and their route's routine.
  struct Source {
    const XMLElement* element;
    Area area;
    int n;
    std::string routine;
  };
  std::vector<Source> sources_;  ///< per queue (a waypoint too): the way its line faces, rad
  std::vector<const XMLElement*> clusters_;
  core::Vec2 low_ = core::Vec2::Zero(), high_ = core::Vec2::Zero();
  double resolution_ = kImportResolutions[0];
  std::map<std::string, std::pair<core::Vec2, double>> goals_;  ///< per waypoint: its goal and the radius it is reached within
  ordered_json locations_ = ordered_json::object();
  core::Random random_{kPlacementSeed};
  int people_ = 0;
  ordered_json humans_ = ordered_json::array(), robots_ = ordered_json::array();
  ordered_json actions_ = ordered_json::array();
  ordered_json routines_ = ordered_json::object();
};

}  // namespace

ImportResult import_pedsim(std::string_view xml, const ImportOptions& options) {
  ImportResult result;
  tinyxml2::XMLDocument document;
  if (!parse_xml(xml, document, result)) return result;
  PedsimImporter(options, result).run(document);
  return result;
}

}  // namespace hrisim::scenario
