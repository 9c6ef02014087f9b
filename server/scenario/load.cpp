#include "scenario/load.hpp"

#include "humans/motion.hpp"

#include <algorithm>
#include <fstream>
#include <functional>
#include <set>
#include <cmath>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"
#include "humans/motion.hpp"
#include "core/files.hpp"
#include "scenario/former_keys.hpp"
#include "scenario/load_context.hpp"
#include "scenario/load_warnings.hpp"
#include "scenario/read_actions.hpp"
#include "scenario/sound_settings.hpp"
#include "world/ros_map.hpp"

namespace hrisim::scenario {
namespace embedded {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace embedded

namespace {

using nlohmann::json;
using loading::Errors;
using loading::member;
using loading::read_point;
using loading::read_pose;


/// A controller's `type` (the schema admits only these names).
RobotController::Kind controller_kind(std::string_view type) {
  using Kind = RobotController::Kind;
  static constexpr std::pair<std::string_view, Kind> kKinds[] = {
      {"idle", Kind::idle}, {"goal", Kind::goal}, {"social", Kind::social}, {"teleop", Kind::teleop},
      {"dwa", Kind::dwa},   {"orca", Kind::orca}, {"social_force", Kind::social_force}, {"search", Kind::search}};
  for (const auto& [name, kind] : kKinds) {
    if (name == type) return kind;
  }
  return Kind::idle;
}


std::vector<Vec2> rectangle(const Pose2& centre, double length, double width) {
  std::vector<Vec2> corners;
  for (const auto& [sx, sy] : {std::pair{1.0, 1.0}, {-1.0, 1.0}, {-1.0, -1.0}, {1.0, -1.0}}) {
    const Pose2 corner = core::compose(centre, {sx * length / 2, sy * width / 2, 0.0});
    corners.emplace_back(corner.x, corner.y);
  }
  return corners;
}

std::vector<Vec2> wall_polygon(const Vec2& from, const Vec2& to, double thickness) {
  const Vec2 along = to - from;
  const double length = along.norm();
  const Vec2 middle = 0.5 * (from + to);
  const double theta = length > 0 ? std::atan2(along.y(), along.x()) : 0.0;
  return rectangle({middle.x(), middle.y(), theta}, std::max(length, thickness), thickness);
}


class Loader {
 public:
  Loader(const json& document, const LoadOptions& options, Errors& errors, Errors& warnings)
      : doc_(document), options_(options), errors_(errors), warnings_(warnings), context_(errors) {}

  std::shared_ptr<Model> load() {
    auto model = build_world();
    if (!model) return nullptr;
    model->name = doc_.at("name");
    model->description = doc_.value("description", "");
    model->dt = doc_.value("dt", kDefaultDt);
    model->time_limit = doc_.value("time_limit", kDefaultTimeLimit);
    read_locomotion(*model);
    read_places(*model);
    read_elevators(*model);
    model->activity_models = read_activity_models(member(doc_, "activity_models"), context_.names.locations, errors_);
    read_daily_life(*model);
    model->clips = read_clips(member(doc_, "clips"), options_.map_search_path, options_.limits.confine_files, errors_);
    read_agents(*model);
    model->heard = std::any_of(model->agents.begin(), model->agents.end(), [](const AgentDef& agent) { return agent.microphones.has_value(); });
    read_objects(*model);
    collect_routine_names(*model);
    read_groups(*model);
    read_routines(*model);
    read_steps(*model);
    read_async(*model);
    check_routine_cycles(*model);
    if (errors_.empty()) check_repeats(*model);
    read_task(*model);
    try {
      check_episode_ticks(model->time_limit, model->dt, options_.limits.max_episode_ticks,
                          model->task ? "task.max_episode_length" : "time_limit");
    } catch (const core::Error& e) {
      context_.error(model->task ? "/task/max_episode_length" : "/time_limit", e.what());
    }
    loading::warn_about_social_force_goals(*model, warnings_);
    loading::warn_about_unpublished_waits(*model, warnings_);
    return errors_.empty() ? model : nullptr;
  }

 private:

  std::shared_ptr<Model> build_world() {
    const json& world = doc_.at("world");
    std::optional<world::OccupancyGrid> grid;
    if (world.contains("map")) {
      const std::string name = world["map"];
      const auto path = core::find_file(options_.map_search_path, name, options_.limits.confine_files);
      if (!path) {
        context_.error("/world/map", "map '" + name + "' not found (a relative path, looked up next to the scenario and among the bundled scenarios)");
        return nullptr;
      }
      try {
        world::RosMapLimits limits{std::nullopt, options_.limits.max_grid_cells};
        if (options_.limits.confine_files) limits.folder = path->parent_path();
        grid = world::load_ros_map(*path, limits);
      } catch (const core::Error& e) {
        context_.error("/world/map", e.what());
        return nullptr;
      }
    } else if (world.contains("bounds")) {
      const Vec2 low = read_point(world["bounds"]["min"]), high = read_point(world["bounds"]["max"]);
      const double resolution = world.value("resolution", world::kDefaultGridResolution);
      if (!(high.x() > low.x() && high.y() > low.y())) {
        context_.error("/world/bounds", "max must be greater than min in x and y");
        return nullptr;
      }
      const double cells = std::ceil((high.x() - low.x()) / resolution) * std::ceil((high.y() - low.y()) / resolution);
      if (!(cells <= static_cast<double>(options_.limits.max_grid_cells))) {
        context_.error("/world/resolution", "the bounds at this resolution make " + std::to_string(static_cast<long double>(cells)) + " cells; at most " +
                                       std::to_string(options_.limits.max_grid_cells) + " (--max-grid-cells)");
        return nullptr;
      }
      try {
        grid.emplace(resolution, low, static_cast<int>(std::ceil((high.x() - low.x()) / resolution)),
                     static_cast<int>(std::ceil((high.y() - low.y()) / resolution)));
      } catch (const core::Error& e) {
        context_.error("/world/bounds", e.what());
        return nullptr;
      }
    } else {
      context_.error("/world", "needs either 'map' (a ROS map YAML file) or 'bounds'");
      return nullptr;
    }

    std::vector<Obstacle> obstacles;
    const json& walls = member(world, "walls");
    for (std::size_t i = 0; i < walls.size(); ++i) {
      const Vec2 from = read_point(walls[i]["from"]), to = read_point(walls[i]["to"]);
      const double thickness = walls[i].value("thickness", kDefaultWallThickness);
      Obstacle wall;
      wall.name = "wall " + std::to_string(i);
      wall.polygon = wall_polygon(from, to, thickness);
      const Vec2 middle = 0.5 * (from + to);
      wall.frame = {middle.x(), middle.y(), std::atan2(to.y() - from.y(), to.x() - from.x())};
      wall.length = (to - from).norm();
      wall.width = thickness;
      obstacles.push_back(std::move(wall));
    }
    const json& listed = member(world, "obstacles");
    std::set<std::string> names;
    for (std::size_t i = 0; i < listed.size(); ++i) {
      const json& entry = listed[i];
      Obstacle obstacle;
      obstacle.name = entry["name"];
      obstacle.height = entry.value("height", kDefaultObstacleHeight);
      if (!names.insert(obstacle.name).second) {
        context_.error("/world/obstacles/" + std::to_string(i) + "/name", "obstacle name '" + obstacle.name + "' is used twice");
      }
      Pose2 frame;
      if (entry.contains("box")) {
        frame = read_pose(entry["box"]);
        obstacle.polygon = rectangle(frame, entry["box"]["length"], entry["box"]["width"]);
      } else {
        for (const json& point : entry["polygon"]) obstacle.polygon.push_back(read_point(point));
        Vec2 centre = Vec2::Zero();
        for (const Vec2& p : obstacle.polygon) centre += p / static_cast<double>(obstacle.polygon.size());
        frame = {centre.x(), centre.y(), 0.0};
      }
      obstacle.mesh = entry.value("mesh", "");
      obstacle.frame = frame;
      if (entry.contains("box")) {
        obstacle.length = entry["box"]["length"];
        obstacle.width = entry["box"]["width"];
      } else {
        Eigen::AlignedBox2d bounds;
        for (const Vec2& p : obstacle.polygon) bounds.extend(p);
        obstacle.frame = {bounds.center().x(), bounds.center().y(), 0.0};
        obstacle.length = bounds.sizes().x();
        obstacle.width = bounds.sizes().y();
      }
      for (const auto& [anchor, pose] : member(entry, "anchors").items()) {
        obstacle.anchors[anchor] = core::compose(frame, read_pose(pose));
      }
      obstacles.push_back(std::move(obstacle));
    }
    for (const Obstacle& obstacle : obstacles) grid->fill_polygon(obstacle.polygon);
    auto model = std::make_shared<Model>(std::move(*grid));
    model->map_from_image = world.contains("map");
    if (model->map_from_image) {
      model->outline = world::occupied_outline(model->grid);
    } else {
      for (const Obstacle& obstacle : obstacles) world::append_edges(obstacle.polygon, model->outline, obstacle.height);
    }
    model->obstacles = std::move(obstacles);
    for (std::size_t o = 0; o < model->obstacles.size(); ++o) {
      const Obstacle& obstacle = model->obstacles[o];
      for (const auto& [anchor, pose] : obstacle.anchors) {
        model->seats.push_back({anchor == kDefaultSeatAnchor ? obstacle.name : obstacle.name + "/" + anchor, static_cast<int>(o), pose});
      }
    }
    const json& doors = member(world, "doors");
    for (std::size_t i = 0; i < doors.size(); ++i) {
      scenario::Door door{doors[i]["name"], read_point(doors[i]["from"]), read_point(doors[i]["to"]),
                          doors[i].value("thickness", kDefaultWallThickness), doors[i].value("open", false)};
      if (context_.names.doors.contains(door.name)) {
        context_.error("/world/doors/" + std::to_string(i) + "/name", "door name '" + door.name + "' is used twice");
      }
      context_.names.doors[door.name] = static_cast<int>(model->doors.size());
      model->doors.push_back(std::move(door));
    }
    return model;
  }

  void read_locomotion(Model& model) {
    const json& locomotion = member(doc_, "locomotion");
    default_avoidance_ = locomotion.value("avoidance", "orca") == "orca" ? humans::LocalAvoidance::orca
                                                                         : humans::LocalAvoidance::social_force;
    model.replan_distance = locomotion.value("replan_distance", kDefaultReplanDistance);
    // The schema has refused any other name.
    const humans::CrowdParams base =
        humans::crowd_preset(humans::crowd_preset_named(locomotion.value("preset", "hrisim")).value_or(humans::CrowdPreset::hrisim));
    model.orca = base.orca;
    model.social_force = base.social_force;
    model.personal_space = base.personal_space;
    model.headway = base.headway;
    const json& orca = member(locomotion, "orca");
    model.orca.neighbour_distance = orca.value("neighbour_distance", model.orca.neighbour_distance);
    model.orca.max_neighbours = orca.value("max_neighbours", model.orca.max_neighbours);
    model.orca.time_horizon = orca.value("time_horizon", model.orca.time_horizon);
    model.orca.obstacle_horizon = orca.value("obstacle_horizon", model.orca.obstacle_horizon);
    const json& sf = member(locomotion, "social_force");
    auto& p = model.social_force;
    p.desired_factor = sf.value("desired_factor", p.desired_factor);
    p.social_factor = sf.value("social_factor", p.social_factor);
    p.obstacle_factor = sf.value("obstacle_factor", p.obstacle_factor);
    p.obstacle_sigma = sf.value("obstacle_sigma", p.obstacle_sigma);
    p.relaxation_time = sf.value("relaxation_time", p.relaxation_time);
    p.lambda = sf.value("lambda", p.lambda);
    p.gamma = sf.value("gamma", p.gamma);
    p.n = sf.value("n", p.n);
    p.n_prime = sf.value("n_prime", p.n_prime);
    p.neighbour_distance = sf.value("neighbour_distance", p.neighbour_distance);
    const json& personal_space = member(locomotion, "personal_space");
    model.personal_space.from_robots = personal_space.value("from_robots", model.personal_space.from_robots);
    model.personal_space.from_people = personal_space.value("from_people", model.personal_space.from_people);
    const json& headway = member(locomotion, "headway");
    model.headway.time_gap = headway.value("time_gap", model.headway.time_gap);
    model.headway.horizon = headway.value("horizon", model.headway.horizon);
    model.headway.field_of_view = headway.value("field_of_view", model.headway.field_of_view);
  }

  void read_places(Model& model) {
    for (const auto& [name, entry] : member(doc_, "locations").items()) {
      context_.names.locations[name] = static_cast<int>(model.locations.size());
      model.locations.push_back({name, read_pose(entry), entry.value("radius", kDefaultGoalRadius)});
      context_.check_free(model, model.locations.back().pose.position(), "/locations/" + core::pointer_token(name),
                 "location '" + name + "'");
    }
    for (const auto& [name, entry] : member(doc_, "social_spaces").items()) {
      context_.names.social_spaces[name] = static_cast<int>(model.social_spaces.size());
      SocialSpace space{name, read_pose(entry), {}};
      for (std::size_t i = 0; i < entry["slots"].size(); ++i) {
        space.slots.push_back(core::compose(space.centre, read_pose(entry["slots"][i])));
        context_.check_free(model, space.slots.back().position(),
                   "/social_spaces/" + core::pointer_token(name) + "/slots/" + std::to_string(i),
                   "slot " + std::to_string(i) + " of social space '" + name + "'");
      }
      model.social_spaces.push_back(std::move(space));
    }
    for (const auto& [name, entry] : member(doc_, "attractions").items()) {
      model.attractions.push_back({name, Vec2(entry["x"].get<double>(), entry["y"].get<double>()), entry.value("width", 1.0), entry.value("height", 1.0),
                                   entry.value("strength", 1.0)});
    }
    for (const auto& [name, entry] : member(doc_, "queues").items()) {
      context_.names.queues[name] = static_cast<int>(model.queues.size());
      model.queues.push_back({name, read_pose(entry), entry.value("spacing", kQueueSpacing), entry.value("service_time", kQueueServiceTime)});
      context_.check_free(model, model.queues.back().head.position(), "/queues/" + core::pointer_token(name), "the head of queue '" + name + "'");
    }
  }

  void read_elevators(Model& model) {
    const json& elevators = member(doc_.at("world"), "elevators");
    std::set<int> used_doors;
    for (std::size_t e = 0; e < elevators.size(); ++e) {
      const json& entry = elevators[e];
      const std::string pointer = "/world/elevators/" + std::to_string(e);
      Elevator elevator;
      elevator.name = entry["name"];
      elevator.topic = entry.value("topic", "/elevator");
      for (std::size_t d = 0; d < entry["doors"].size(); ++d) {
        const int door = context_.resolve(context_.names.doors, entry["doors"][d], pointer + "/doors/" + std::to_string(d), "door");
        if (door >= 0 && !used_doors.insert(door).second) {
          context_.error(pointer + "/doors/" + std::to_string(d), "door '" + model.doors[door].name + "' already belongs to an elevator");
        }
        elevator.doors.push_back(door);
      }
      const json& spaces = member(entry, "social_spaces");
      for (std::size_t s = 0; s < spaces.size(); ++s) {
        elevator.social_spaces.push_back(
            context_.resolve(context_.names.social_spaces, spaces[s], pointer + "/social_spaces/" + std::to_string(s), "social space"));
      }
      elevator.start_floor = entry.value("start_floor", 1) - 1;
      if (elevator.start_floor >= static_cast<int>(elevator.doors.size())) {
        context_.error(pointer + "/start_floor", "floor " + std::to_string(elevator.start_floor + 1) + " has no door (" +
                                            std::to_string(elevator.doors.size()) + " doors)");
      }
      elevator.door_speed = entry.value("door_speed", kElevatorDoorSpeed);
      elevator.open_time = entry.value("open_time", kElevatorOpenTime);
      elevator.travel_time = entry.value("travel_time", kElevatorTravelTime);
      elevator.settle_time = entry.value("settle_time", kElevatorSettleTime);
      model.elevators.push_back(std::move(elevator));
    }
  }

  void read_agents(Model& model) {
    const std::size_t people = doc_.value("humans", json::array()).size() + doc_.value("robots", json::array()).size();
    if (people > static_cast<std::size_t>(options_.limits.max_people)) {
      context_.error("/humans", std::to_string(people) + " humans and robots: at most " + std::to_string(options_.limits.max_people) +
                           " in a scenario (--max-people)");
      return;
    }
    for (const char* section : {"humans", "robots"}) {
      const json list = doc_.value(section, json::array());
      const bool is_human = std::string(section) == "humans";
      for (std::size_t i = 0; i < list.size(); ++i) {
        const json& entry = list[i];
        const std::string pointer = std::string("/") + section + "/" + std::to_string(i);
        AgentDef agent;
        agent.id = entry["id"];
        agent.kind = is_human ? AgentKind::human : AgentKind::robot;
        agent.start = read_pose(entry["start"]);
        agent.radius = entry.value("radius", kDefaultAgentRadius);
        if (entry.contains("preferred_speed")) agent.preferred_speed = entry["preferred_speed"].get<double>();
        agent.avoidance = !entry.contains("avoidance")             ? default_avoidance_
                          : entry["avoidance"] == "social_force" ? humans::LocalAvoidance::social_force
                                                                 : humans::LocalAvoidance::orca;
        agent.type = entry.value("type", "adult");
        if (entry.contains("behaviour")) agent.behaviour = humans::read_behaviour(entry["behaviour"]);
        agent.enters_at = entry.value("enters_at", 0.0);
        if (entry.contains("activity_model")) agent.activity_model = find_activity_model(model, entry["activity_model"], pointer + "/activity_model");
        if (entry.contains("daily_schedule")) agent.daily_schedule = find_daily_schedule(model, entry["daily_schedule"], pointer + "/daily_schedule");
        if (agent.activity_model >= 0 && agent.daily_schedule >= 0) {
          context_.error(pointer, "human '" + agent.id + "' has both an activity_model and a daily_schedule: a schedule chooses the model in each room, give one of them");
        }
        if (context_.names.agents.contains(agent.id)) {
          context_.error(pointer + "/id", "agent id '" + agent.id + "' is used twice");
        }
        context_.names.agents[agent.id] = static_cast<int>(model.agents.size());
        if (!is_human) {
          context_.names.robots.insert(agent.id);
          read_robot_model(model, entry, pointer, agent);
        }
        place_start(model, agent, pointer + "/start", std::string(is_human ? "human" : "robot") + " '" + agent.id + "'");
        model.agents.push_back(std::move(agent));
      }
    }
  }

  /// An agent whose start is on a wall or an obstacle (files made for simulators that push such agents
  /// out, or whose map has moved) starts at the nearest spot within world::kSnapDistance where its
  /// body fits, with a warning; farther, or outside the map, that is an error.
  void place_start(const Model& model, AgentDef& agent, const std::string& pointer, const std::string& what) {
    const Vec2 at = agent.start.position();
    const world::CellIndex cell = model.grid.cell_of(at);
    if (model.grid.in_bounds(cell) && model.grid.blocked(at)) {
      if (const auto free = model.planner.nearest_traversable(model.grid.index(cell), agent.radius)) {
        const Vec2 moved = model.grid.center_of(model.grid.cell_at(*free));
        warnings_.push_back({pointer, what + " at (" + core::point_text(at) + ") is on a wall or an obstacle: moved to (" + core::point_text(moved) +
                                          "), the nearest spot where their body fits"});
        agent.start.x = moved.x();
        agent.start.y = moved.y();
        return;
      }
    }
    context_.check_free(model, at, pointer, what);
  }

  /// The search controller's person and strategy, and what it needs: a people detector, and rooms
  /// with lookouts (and, to search by presence, the person's daily schedule).
  void read_search(const Model& model, const json& controller, const std::string& pointer, AgentDef& robot) {
    RobotController& search = robot.controller;
    search.search_strategy = controller.value("strategy", "presence") == "sweep" ? RobotController::SearchStrategy::sweep
                                                                                : RobotController::SearchStrategy::presence;
    const std::string person = controller.value("person", "");
    const auto found = context_.names.agents.find(person);
    if (found == context_.names.agents.end() || model.agents[found->second].kind != AgentKind::human) {
      context_.error(pointer + "/person", "the search controller looks for a human of the scenario; '" + person + "' is none");
    } else {
      search.search_person = found->second;
      if (search.search_strategy == RobotController::SearchStrategy::presence && model.agents[found->second].daily_schedule < 0) {
        context_.error(pointer + "/strategy", "searching by presence needs '" + person + "' to live by a daily schedule (or use \"strategy\": \"sweep\")");
      }
    }
    if (!robot.people_detector) context_.error(pointer, "the search controller finds people with the robot's people_detector: give the robot one");
    if (model.rooms.empty()) context_.error(pointer, "the search controller looks into the scenario's rooms: declare them in 'rooms'");
    for (const Room& room : model.rooms) {
      if (room.lookout < 0) context_.error("/rooms/" + core::pointer_token(room.name), "the search controller looks into every room from its lookout: give '" + room.name + "' one");
    }
  }

  int find_daily_schedule(const Model& model, const std::string& name, const std::string& pointer) {
    for (std::size_t s = 0; s < model.daily_schedules.size(); ++s) {
      if (model.daily_schedules[s].name == name) return static_cast<int>(s);
    }
    context_.error(pointer, "unknown daily schedule '" + name + "'");
    return -1;
  }

  void read_daily_life(Model& model) {
    if (doc_.contains("clock")) model.clock = read_clock(doc_["clock"], errors_);
    model.rooms = read_rooms(member(doc_, "rooms"), context_.names.locations, errors_);
    model.daily_schedules = read_daily_schedules(member(doc_, "daily_schedules"), model.rooms, model.activity_models, errors_);
    if (!model.daily_schedules.empty() && !model.clock) context_.error("/daily_schedules", "daily schedules need the scenario's 'clock' (its start time of day and speed)");
  }

  int find_activity_model(const Model& model, const std::string& name, const std::string& pointer) {
    for (std::size_t m = 0; m < model.activity_models.size(); ++m) {
      if (model.activity_models[m].name == name) return static_cast<int>(m);
    }
    context_.error(pointer, "unknown activity model '" + name + "'");
    return -1;
  }

  /// A robot's model, controller and sensors; its disc is its model's footprint.
  void read_robot_model(const Model& model, const json& entry, const std::string& pointer, AgentDef& agent) {
    if (entry.contains("model")) {
      const std::string name = entry["model"];
      agent.robot_model = robots::builtin_robot(name);
      if (!agent.robot_model) {
        context_.error(pointer + "/model", "unknown robot model '" + name + "' (known: " + core::join(robots::builtin_robot_names()) + ")");
      } else if (entry.contains("radius")) {
        context_.error(pointer + "/radius", "a robot with a model has its model's footprint (" + std::to_string(agent.robot_model->footprint_radius) + " m)");
      } else {
        agent.radius = agent.robot_model->footprint_radius;
      }
    }
    for (const char* needs_model : {"controller", "people_detector", "odometry"}) {
      if (entry.contains(needs_model) && !entry.contains("model")) context_.error(pointer + "/" + needs_model, "only a robot with a model has one");
    }
    if (entry.contains("controller")) {
      const json& controller = entry["controller"];
      const std::string type = controller["type"];
      using Kind = RobotController::Kind;
      agent.controller.kind = controller_kind(type);
      const json goal = controller.value("goal", json::object());
      if (goal.contains("location")) {
        const int location = context_.resolve(context_.names.locations, goal["location"], pointer + "/controller/goal/location", "location");
        if (location >= 0) agent.controller.goal = model.locations[location].pose;
        if (goal.contains("pose")) context_.error(pointer + "/controller/goal", "give either a location or a pose");
      } else if (goal.contains("pose")) {
        agent.controller.goal = read_pose(goal["pose"]);
        context_.check_free(model, agent.controller.goal->position(), pointer + "/controller/goal/pose", "goal of robot '" + agent.id + "'");
      }
      agent.controller.goal_radius = goal.value("radius", kDefaultGoalRadius);
      const bool drives = agent.controller.kind != Kind::idle && agent.controller.kind != Kind::teleop;
      if (drives && controller.contains("goal") && !goal.contains("location") && !goal.contains("pose")) {
        context_.error(pointer + "/controller/goal", "a goal is a location or a pose");
      }
      if (!drives && controller.contains("goal")) context_.error(pointer + "/controller/goal", "the " + type + " controller does not drive to a goal");
      if (agent.robot_model && !agent.robot_model->drive && agent.controller.kind != Kind::idle) {
        context_.error(pointer + "/controller/type", "robot model '" + agent.robot_model->name + "' has no drive");
      }
    }
    if (entry.contains("people_detector")) agent.people_detector = sensors::read_people_detector_params(entry["people_detector"]);
    if (entry.contains("microphones")) read_microphones(entry["microphones"], pointer + "/microphones", agent, errors_);
    if (agent.controller.kind == RobotController::Kind::search) read_search(model, entry["controller"], pointer + "/controller", agent);
    if (entry.contains("joints")) {
      if (!agent.robot_model) context_.error(pointer + "/joints", "only a robot with a model has joints");
      for (const auto& [joint, position] : entry["joints"].items()) {
        const std::string at = pointer + "/joints/" + core::pointer_token(joint);
        const int index = agent.robot_model ? agent.robot_model->find_joint(joint) : -1;
        if (!agent.robot_model) continue;
        if (index < 0) {
          context_.error(at, "robot model '" + agent.robot_model->name + "' has no joint '" + joint + "'");
          continue;
        }
        const robots::Joint& def = agent.robot_model->joints[index];
        if (def.type == robots::JointType::fixed || def.mimic) context_.error(at, "joint '" + joint + "' has no motor of its own");
        const double value = position.get<double>();
        if ((def.limits.lower && value < *def.limits.lower) || (def.limits.upper && value > *def.limits.upper)) {
          context_.error(at, "outside the joint's limits");
        }
        agent.initial_joints[joint] = value;
      }
    }
    if (entry.contains("odometry")) agent.odometry = sensors::read_odometry_params(entry["odometry"]);
  }

  void read_objects(Model& model) {
    const json list = doc_.value("objects", json::array());
    std::set<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
      const json& entry = list[i];
      const std::string pointer = "/objects/" + std::to_string(i);
      MovableObject object;
      object.name = entry["name"];
      if (!names.insert(object.name).second) context_.error(pointer + "/name", "object name '" + object.name + "' is used twice");
      const json& shape = entry["shape"];
      const std::string kind = shape["kind"];
      object.shape.kind = kind == "box" ? robots::Shape::Kind::box
                          : kind == "cylinder" ? robots::Shape::Kind::cylinder
                          : kind == "sphere" ? robots::Shape::Kind::sphere
                                             : robots::Shape::Kind::capsule;
      if (shape.contains("size")) object.shape.size = Eigen::Vector3d(shape["size"][0], shape["size"][1], shape["size"][2]);
      object.shape.radius = shape.value("radius", 0.0);
      object.shape.length = shape.value("length", 0.0);
      const bool sized = object.shape.kind == robots::Shape::Kind::box ? shape.contains("size")
                         : object.shape.kind == robots::Shape::Kind::sphere ? shape.contains("radius")
                                                                             : shape.contains("radius") && shape.contains("length");
      if (!sized) context_.error(pointer + "/shape", "a " + kind + " needs " + (kind == "box" ? "size" : kind == "sphere" ? "radius" : "radius and length"));
      object.mass = entry["mass"];
      const json& pose = entry["pose"];
      object.pose = {pose["x"], pose["y"], pose.value("z", 0.0), pose.value("roll", 0.0), pose.value("pitch", 0.0), pose.value("yaw", 0.0)};
      if (!model.grid.in_bounds(model.grid.cell_of({object.pose.x, object.pose.y}))) {
        context_.error(pointer + "/pose", "object '" + object.name + "' is outside the map");
      }
      model.objects.push_back(std::move(object));
    }
  }

  void collect_routine_names(Model& model) {
    for (const auto& [name, unused] : member(doc_, "routines").items()) {
      context_.names.routines[name] = static_cast<int>(model.routines.size());
      model.routines.push_back({name, {}});
    }
  }

  /// Declared groups, then the names that form_group actions create.
  void read_groups(Model& model) {
    for (const auto& [name, entry] : member(doc_, "groups").items()) {
      Group group{name, context_.members_of(entry["members"], "/groups/" + core::pointer_token(name) + "/members")};
      context_.names.groups[name] = static_cast<int>(model.groups.size());
      model.groups.push_back(std::move(group));
    }
    auto collect = [&](const json& action) {
      if (action.contains("form_group")) {
        const std::string name = action["form_group"]["group"];
        if (!context_.names.groups.contains(name)) {
          context_.names.groups[name] = static_cast<int>(model.groups.size());
          model.groups.push_back({name, {}});
        }
      }
    };
    for (const auto& [name, actions] : member(doc_, "routines").items()) {
      for (const json& action : actions) collect(action);
    }
    for (const json& step : doc_.at("steps")) {
      for (const json& action : step["actions"]) collect(action);
    }
  }

  void read_routines(Model& model) {
    loading::ActionReader reader(context_, model);
    for (const auto& [name, actions] : member(doc_, "routines").items()) {
      Routine& routine = model.routines[static_cast<std::size_t>(context_.names.routines[name])];
      for (std::size_t i = 0; i < actions.size(); ++i) {
        routine.actions.push_back(reader.read(actions[i], "/routines/" + core::pointer_token(name) + "/" + std::to_string(i), true));
      }
    }
  }

  void read_steps(Model& model) {
    loading::ActionReader reader(context_, model);
    const json& steps = doc_.at("steps");
    for (std::size_t s = 0; s < steps.size(); ++s) {
      Step step{steps[s]["name"], {}};
      for (std::size_t i = 0; i < steps[s]["actions"].size(); ++i) {
        const std::string pointer = "/steps/" + std::to_string(s) + "/actions/" + std::to_string(i);
        step.actions.push_back(reader.read(steps[s]["actions"][i], pointer, false));
      }
      model.steps.push_back(std::move(step));
    }
  }

  /// The benchmark task: its kind's defaults (seed 003 §5.3), then what the scenario overrides. A task's
  /// episode lasts its max_episode_length ticks, so the scenario gives no time_limit of its own.
  void read_task(Model& model) {
    if (!doc_.contains("task")) return;
    const json& entry = doc_["task"];
    TaskSettings task;
    task.name = entry["name"];
    task.kind = *task_kind(task.name);  // the schema allows only the known names
    const bool pick = task.kind == TaskKind::pick_and_place;
    if (pick) task.frame_skip = kPickFrameSkip;
    if (pick || task.kind == TaskKind::mirror_gesture) task.max_episode_length = kShortEpisodeLength;
    task.frame_skip = entry.value("frame_skip", task.frame_skip);
    task.gripper_frames = entry.value("gripper_frames", task.gripper_frames);
    task.max_episode_length = entry.value("max_episode_length", task.max_episode_length);
    if (pick && task.gripper_frames > task.frame_skip) {
      context_.error("/task/gripper_frames", "gripper_frames (" + std::to_string(task.gripper_frames) + ") is more than frame_skip (" +
                                        std::to_string(task.frame_skip) + ")");
    }
    if (doc_.contains("time_limit")) {
      context_.error("/time_limit", "a scenario with a task ends after task.max_episode_length ticks: give no time_limit");
    }
    model.time_limit = task.max_episode_length * model.dt;

    const auto agent_named = [&](const char* key, AgentKind kind) {
      const std::string pointer = std::string("/task/") + key;
      if (entry.contains(key)) {
        const int agent = model.find_agent(entry[key]);
        if (agent < 0 || model.agents[agent].kind != kind) {
          context_.error(pointer, "no " + std::string(kind == AgentKind::robot ? "robot" : "human") + " '" + entry[key].get<std::string>() + "'");
          return -1;
        }
        return agent;
      }
      for (std::size_t a = 0; a < model.agents.size(); ++a) {
        if (model.agents[a].kind == kind) return static_cast<int>(a);
      }
      context_.error(pointer.substr(0, 5), "the task needs a " + std::string(kind == AgentKind::robot ? "robot" : "human"));
      return -1;
    };
    task.robot = agent_named("robot", AgentKind::robot);
    if (task.robot >= 0) {
      const auto& robot_model = model.agents[task.robot].robot_model;
      const bool navigation = task.kind != TaskKind::pick_and_place && task.kind != TaskKind::mirror_gesture;
      // The arm tasks need the gripper: pick and place closes it, gesture mirroring points with its palm.
      if (!robot_model || (navigation && !robot_model->drive) ||
          (!navigation && (!robot_model->groups.contains("arm") || !robot_model->gripper))) {
        context_.error("/task/robot", "robot '" + model.agents[task.robot].id + "' needs a model with " +
                                 (navigation ? "a drive" : "an arm group and a gripper") + " for " + task.name);
      }
    }
    if (!pick) task.human = agent_named("human", AgentKind::human);

    if (entry.contains("spawn")) {
      task.spawn_min = read_point(entry["spawn"]["min"]);
      task.spawn_max = read_point(entry["spawn"]["max"]);
      if ((task.spawn_min.array() > task.spawn_max.array()).any()) context_.error("/task/spawn", "min is above max");
    }
    task.reach_distance = entry.value("reach_distance", task.reach_distance);
    task.collision_distance = entry.value("collision_distance", task.collision_distance);
    task.collision_penalty = entry.value("collision_penalty", task.collision_penalty);
    task.obstacle_penalty = entry.value("obstacle_penalty", task.obstacle_penalty);
    const json penalised = entry.value("penalised", json::array());
    for (std::size_t i = 0; i < penalised.size(); ++i) {
      const std::string name = penalised[i];
      const bool obstacle = std::any_of(model.obstacles.begin(), model.obstacles.end(), [&](const Obstacle& o) { return o.name == name; });
      const bool object = std::any_of(model.objects.begin(), model.objects.end(), [&](const MovableObject& o) { return o.name == name; });
      if (!obstacle && !object) context_.error("/task/penalised/" + std::to_string(i), "no obstacle or object '" + name + "'");
      task.penalised.push_back(name);
    }
    task.walking_styles = default_walking_styles();
    if (entry.contains("walking_styles")) {
      task.walking_styles.clear();
      for (const auto& [name, speed] : entry["walking_styles"].items()) task.walking_styles.push_back({name, speed.get<double>()});
      if (task.walking_styles.empty()) context_.error("/task/walking_styles", "at least one walking style");
    }
    task.lead_distance = entry.value("lead_distance", task.lead_distance);
    if (entry.contains("object")) {
      const std::string name = entry["object"];
      for (std::size_t o = 0; o < model.objects.size(); ++o) {
        if (model.objects[o].name == name) task.object = static_cast<int>(o);
      }
      if (task.object < 0) context_.error("/task/object", "no object '" + name + "'");
    } else if (pick) {
      context_.error("/task", "pick_and_place needs the object to carry ('object')");
    }
    if (entry.contains("target")) {
      const json& target = entry["target"];
      task.target = {target["x"], target["y"], target.value("z", 0.0)};
    } else if (pick) {
      context_.error("/task", "pick_and_place needs where to put the object ('target')");
    }
    task.reward_range = entry.value("reward_range", task.reward_range);
    task.place_weight = entry.value("place_weight", task.place_weight);
    task.human_distance = entry.value("human_distance", task.human_distance);
    task.pointing_reach = entry.value("pointing_reach", task.pointing_reach);
    task.camera = entry.value("camera", task.camera);
    task.image_width = entry.value("image_width", task.image_width);
    task.image_height = entry.value("image_height", task.image_height);
    if (task.kind == TaskKind::mirror_gesture && task.robot >= 0 && model.agents[task.robot].robot_model) {
      const auto& sensors = model.agents[task.robot].robot_model->sensors;
      const bool found = std::any_of(sensors.begin(), sensors.end(), [&](const robots::Sensor& sensor) {
        return sensor.name == task.camera && (sensor.type == "camera" || sensor.type == "rgbd_camera");
      });
      if (!found) context_.error("/task/camera", "robot '" + model.agents[task.robot].id + "' has no camera '" + task.camera + "'");
    }
    model.task = std::move(task);
  }

  void read_async(Model& model) {
    const json& async = member(doc_, "async");
    std::set<int> handled;
    for (std::size_t i = 0; i < async.size(); ++i) {
      const int routine = context_.resolve(context_.names.routines, async[i]["routine"], "/async/" + std::to_string(i) + "/routine", "routine");
      if (routine >= 0) {
        model.async_routines.push_back(routine);
        handled.insert(routine);
      }
    }
    const json& requests = member(doc_, "requests");
    for (std::size_t i = 0; i < requests.size(); ++i) {
      const std::string pointer = "/requests/" + std::to_string(i);
      Request request;
      request.time = requests[i]["time"];
      request.routine = context_.resolve(context_.names.routines, requests[i]["routine"], pointer + "/routine", "routine");
      if (request.routine >= 0 && !handled.contains(request.routine)) {
        context_.error(pointer + "/routine", "no entry of 'async' answers routine '" + requests[i]["routine"].get<std::string>() + "'");
      }
      if (requests[i].contains("robot")) {
        const std::string robot = requests[i]["robot"];
        if (!context_.names.robots.contains(robot)) {
          context_.error(pointer + "/robot", "'" + robot + "' is not a robot of this scenario");
        } else {
          request.robot = context_.names.agents[robot];
        }
      } else if (context_.names.robots.empty()) {
        context_.error(pointer, "a request needs a robot, and the scenario has none");
      } else {
        request.robot = context_.names.agents[*context_.names.robots.begin()];
        for (std::size_t a = 0; a < model.agents.size(); ++a) {
          if (model.agents[a].kind == AgentKind::robot) {
            request.robot = static_cast<int>(a);
            break;
          }
        }
      }
      model.requests.push_back(request);
    }
    std::stable_sort(model.requests.begin(), model.requests.end(),
                     [](const Request& a, const Request& b) { return a.time < b.time; });
  }

  void check_routine_cycles(const Model& model) {
    // Depth-first search over routine → routine calls; a routine on the current path reached again is a cycle.
    std::vector<int> state(model.routines.size(), 0);  // 0 unseen, 1 on path, 2 done
    std::function<bool(int)> visit = [&](int routine) {
      if (state[routine] == 1) return true;
      if (state[routine] == 2) return false;
      state[routine] = 1;
      for (const Action& action : model.routines[routine].actions) {
        if (action.kind == Action::Kind::run_routine && action.target >= 0 && visit(action.target)) {
          context_.error(action.pointer + "/routine", "routine '" + model.routines[routine].name + "' calls itself through '" +
                                                 model.routines[action.target].name + "'");
          state[routine] = 2;
          return false;
        }
      }
      state[routine] = 2;
      return false;
    };
    for (std::size_t t = 0; t < model.routines.size(); ++t) visit(static_cast<int>(t));
  }

  /// A routine repeated forever must take time each round, or the person would run it without end in one tick.
  void check_repeats(const Model& model) {
    std::function<bool(int, std::set<int>&)> takes_time = [&](int routine, std::set<int>& seen) {
      if (routine < 0 || !seen.insert(routine).second) return false;
      for (const Action& action : model.routines[routine].actions) {
        using K = Action::Kind;
        switch (action.kind) {
          case K::wait_duration:
            if (action.value > 0.0) return true;
            break;
          case K::run_routine:
            if (takes_time(action.target, seen)) return true;
            break;
          case K::go_to_location: case K::go_to_social_space: case K::go_to_pose: case K::wait_message: case K::harass:
          case K::request: case K::play_motion: case K::say: case K::sit_on: case K::pick_up: case K::put_down: case K::join_queue:
          case K::leave:  // the person is gone: nothing repeats
            return true;
          default:
            break;
        }
      }
      return false;
    };
    const auto check = [&](const Action& action) {
      std::set<int> seen;
      if (action.kind == Action::Kind::run_routine && action.repeat && action.target >= 0 && !takes_time(action.target, seen)) {
        context_.error(action.pointer + "/repeat", "routine '" + model.routines[action.target].name +
                                                       "' repeats forever without an action that takes time (a goto, a wait, a motion, …)");
      }
    };
    for (const Routine& routine : model.routines) std::for_each(routine.actions.begin(), routine.actions.end(), check);
    for (const Step& step : model.steps) std::for_each(step.actions.begin(), step.actions.end(), check);
  }

  const json& doc_;
  const LoadOptions& options_;
  Errors& errors_;
  Errors& warnings_;
  loading::Context context_;
  humans::LocalAvoidance default_avoidance_ = humans::LocalAvoidance::orca;
};

}  // namespace

int Model::find_agent(const std::string& id) const {
  for (std::size_t i = 0; i < agents.size(); ++i) {
    if (agents[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

std::optional<Action> Model::say_clip(const std::string& name) const {
  for (std::size_t c = 0; c < clips.size(); ++c) {
    if (clips[c].first != name) continue;
    Action say;
    say.kind = Action::Kind::say;
    say.target = static_cast<int>(c);
    say.value = static_cast<double>(clips[c].second->samples.size()) / clips[c].second->sample_rate;
    return say;
  }
  return std::nullopt;
}

int Model::find_seat(const std::string& obstacle, const std::string& anchor) const {
  const std::string name = anchor.empty() || anchor == kDefaultSeatAnchor ? obstacle : obstacle + "/" + anchor;
  for (std::size_t s = 0; s < seats.size(); ++s) {
    if (seats[s].name == name) return static_cast<int>(s);
  }
  return -1;
}

std::optional<Action> Model::look_at_object(const std::string& name) const {
  Action look;
  look.kind = Action::Kind::look_at_object;
  for (std::size_t o = 0; o < objects.size(); ++o) {
    if (objects[o].name != name) continue;
    look.target = static_cast<int>(o);
    return look;
  }
  for (const Obstacle& obstacle : obstacles) {
    if (obstacle.name != name || obstacle.polygon.empty()) continue;
    Vec2 centre = Vec2::Zero();
    for (const Vec2& corner : obstacle.polygon) centre += corner;
    centre /= static_cast<double>(obstacle.polygon.size());
    look.pose = {centre.x(), centre.y(), 0.0};
    return look;
  }
  return std::nullopt;
}

int Model::find_routine(const std::string& name) const {
  for (std::size_t i = 0; i < routines.size(); ++i) {
    if (routines[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<WalkingStyle> default_walking_styles() { return {{"slow", 0.5}, {"normal", 1.0}, {"brisk", 1.4}}; }

namespace {
constexpr std::pair<TaskKind, const char*> kTaskNames[] = {
    {TaskKind::approach_human, "approach_human"},
    {TaskKind::follow_human, "follow_human"},
    {TaskKind::approach_human_apartment, "approach_human_apartment"},
    {TaskKind::pick_and_place, "pick_and_place"},
    {TaskKind::mirror_gesture, "mirror_gesture"},
};
}  // namespace

std::optional<TaskKind> task_kind(std::string_view name) {
  for (const auto& [kind, n] : kTaskNames) {
    if (name == n) return kind;
  }
  return std::nullopt;
}

const core::JsonSchema& scenario_schema() {
  static const core::JsonSchema schema = [] {
    for (int i = 0; i < embedded::kEmbeddedCount; ++i) {
      if (embedded::kEmbedded[i].first == "scenario.schema.json") {
        return core::JsonSchema(json::parse(embedded::kEmbedded[i].second));
      }
    }
    throw core::Error(core::ErrorCode::internal, "scenario schema is not embedded");
  }();
  return schema;
}

double social_force_standoff(const humans::SocialForceParams& params, double radius, double speed) {
  const double drive = params.desired_factor * speed / params.relaxation_time;
  if (drive <= 0.0 || params.obstacle_factor <= drive) return radius;
  return radius + params.obstacle_sigma * std::log(params.obstacle_factor / drive);
}

LoadResult load_scenario(const json& document, const LoadOptions& options) {
  LoadResult result;
  result.errors = scenario_schema().validate(document);
  const std::vector<FormerKey> former = find_former_keys(document);
  for (const FormerKey& key : former) (key.current_too ? result.errors : result.warnings).push_back(former_key_issue(key));
  if (!result.errors.empty()) return result;  // meaning is checked on well-formed documents only
  if (former.empty()) {
    Loader loader(document, options, result.errors, result.warnings);
    result.model = loader.load();
    return result;
  }
  // Former keys are read as the current ones, and what reading finds is said where the document has it.
  const json current = with_current_keys(document, former);
  const std::size_t warned = result.warnings.size();
  Loader loader(current, options, result.errors, result.warnings);
  result.model = loader.load();
  for (core::ValidationError& error : result.errors) error.pointer = pointer_as_written(error.pointer, former);
  for (std::size_t i = warned; i < result.warnings.size(); ++i) result.warnings[i].pointer = pointer_as_written(result.warnings[i].pointer, former);
  return result;
}

void check_episode_ticks(double time_limit, double dt, std::int64_t max_ticks, const std::string& what) {
  const double ticks = std::ceil(time_limit / dt);
  if (ticks <= static_cast<double>(max_ticks)) return;
  std::ostringstream message;
  message << what << " " << time_limit << " s at dt " << dt << " s is " << ticks << " ticks; an episode may last at most " << max_ticks
          << " (--max-episode-ticks)";
  throw core::Error(core::ErrorCode::bad_request, message.str(), {{"max_episode_ticks", max_ticks}});
}

json parse_scenario_json(std::string_view text) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's byte count is 1-based: the offending character is at offset byte - 1.
    const auto [line, column] = core::line_and_column(text, e.byte > 0 ? e.byte - 1 : 0);
    const std::string message = e.what();
    const std::size_t reason = message.find(": ", message.find("syntax error"));
    throw core::Error(core::ErrorCode::bad_request, "invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) +
                                                        (reason == std::string::npos ? "" : ": " + message.substr(reason + 2)));
  } catch (const json::out_of_range&) {
    throw core::Error(core::ErrorCode::bad_request, "invalid JSON: a number is too large for a double");
  }
}

LoadResult load_scenario_text(std::string_view text, const LoadOptions& options) {
  json document;
  try {
    document = parse_scenario_json(text);
  } catch (const core::Error& e) {
    return {nullptr, {{"", e.what()}}, {}};
  }
  return load_scenario(document, options);
}

LoadResult load_scenario_file(const std::filesystem::path& file, LoadOptions options) {
  std::string text;
  try {
    text = core::read_file(file);
  } catch (const core::Error& e) {
    return {nullptr, {{"", e.what()}}, {}};
  }
  options.map_search_path.insert(options.map_search_path.begin(), file.parent_path().empty() ? "." : file.parent_path());
  return load_scenario_text(text, options);
}

}  // namespace hrisim::scenario
