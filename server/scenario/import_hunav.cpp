#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <limits>
#include <map>

#include "core/json_schema.hpp"
#include "core/math.hpp"
#include "core/random.hpp"
#include "core/text.hpp"
#include "scenario/import.hpp"
#include "scenario/xml_reader.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::ordered_json;

/// HuNavSim's behaviour ids (hunav_msgs/AgentBehavior: BEH_REGULAR 1 … BEH_THREATENING 6), by id - 1.
const char* const kBehaviours[] = {"regular", "impassive", "surprised", "scared", "curious", "threatening"};
/// Behaviour configurations (AgentBehavior: BEH_CONF_DEFAULT 0, CUSTOM 1, RANDOM_NORMAL 2, RANDOM_UNIFORM 3).
enum Configuration { kDefault = 0, kCustom = 1, kRandomNormal = 2, kRandomUniform = 3 };
/// hunav_loader's values for what an agent's block leaves out.
constexpr double kDefaultMaxVel = 1.0, kDefaultRadius = 0.35, kDefaultDuration = 40.0, kDefaultBehaviourVel = 1.0;
constexpr double kDefaultOtherForceFactor = 20.0;
/// hunav_loader clamps a custom behaviour's speed and extra robot repulsion to these.
constexpr double kMaxBehaviourVel = 1.8, kMaxOtherForceFactor = 25.0;
/// Margin around the agents and goals that makes up open ground when no map is given, m.
constexpr double kOpenGroundMargin = 2.0;
/// Seed of the draws of random behaviour configurations: the same file imports to the same people.
constexpr std::uint64_t kBehaviourSeed = 1;
/// Deeper nesting than this is refused before parsing: yaml-cpp's parser recurses once per level, and
/// HuNavSim's files nest five deep.
constexpr int kMaxNesting = 64;
/// Most YAML nodes a file may expand to, an alias counted again each time it is used (every node it
/// names is read again there): a 64 KB file aliasing one 10,000-goal list into 100 people expanded to a
/// million and took 56 s and 1.7 GB to import. A person of HuNavSim's own files takes 50 to 60 nodes, so
/// 2,000 people (--max-people's default) take about 120,000; a file just below this limit compiles in
/// about 4 s and 330 MB (measured: docs/limits.md).
constexpr std::size_t kMaxExpandedNodes = 200'000;

/// How deeply the text nests at most, over-counted: flow brackets (the most open anywhere on the line,
/// so `[[[…]]]` on one line counts), plus per line its indentation levels and the "- " and "? " that
/// open collections on it.
int nesting_bound(std::string_view text) {
  int flow = 0, deepest = 0;
  std::vector<std::size_t> indents;
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t indent = 0;
    while (i + indent < text.size() && text[i + indent] == ' ') ++indent;
    const std::size_t end = std::min(text.find('\n', i), text.size());
    int openers = 0, flow_on_line = flow;
    char quote = 0;
    for (std::size_t k = i + indent; k < end; ++k) {
      const char c = text[k];
      if (quote) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '#') {
        break;
      } else if (c == '[' || c == '{') {
        flow_on_line = std::max(flow_on_line, ++flow);
      } else if (c == ']' || c == '}') {
        flow = std::max(flow - 1, 0);
      } else if ((c == '-' || c == '?' || c == ':') && (k + 1 == end || text[k + 1] == ' ')) {
        ++openers;
      }
    }
    if (end > i + indent) {
      while (!indents.empty() && indents.back() >= indent) indents.pop_back();
      indents.push_back(indent);
    }
    deepest = std::max(deepest, flow_on_line + static_cast<int>(indents.size()) + openers);
    i = end + 1;
  }
  return deepest;
}

// A key a mapping does not have reads as an invalid node, whose type and mark throw: these ask first.
bool is_map(const YAML::Node& node) { return node.IsDefined() && node.IsMap(); }
bool is_sequence(const YAML::Node& node) { return node.IsDefined() && node.IsSequence(); }
bool is_scalar(const YAML::Node& node) { return node.IsDefined() && node.IsScalar(); }
int line_of(const YAML::Node& node) { return !node.IsDefined() || node.Mark().is_null() ? 0 : node.Mark().line + 1; }

/// The line by which the document has expanded to more than `limit` nodes, or none: a walk that
/// visits what an alias names each time the alias is used, stopping there. The line is where the
/// node is used: an alias names an anchor earlier in the file, so a node whose own line lies before
/// its parent's is reached through an alias, and its parent's line is given.
std::optional<int> line_past_node_limit(const YAML::Node& root, std::size_t limit) {
  struct Visit {
    YAML::Node node;
    int line;
  };
  std::vector<Visit> pending{{root, line_of(root)}};
  std::size_t nodes = 1;
  while (!pending.empty()) {
    const Visit visit = std::move(pending.back());
    pending.pop_back();
    const auto reach = [&](const YAML::Node& child, int parent_line) {
      pending.push_back({child, std::max(line_of(child), parent_line)});
      return ++nodes > limit;
    };
    if (visit.node.IsMap()) {
      for (const auto& entry : visit.node) {
        if (reach(entry.first, visit.line)) return pending.back().line;
        if (reach(entry.second, pending.back().line)) return pending.back().line;
      }
    } else if (visit.node.IsSequence()) {
      for (const YAML::Node& element : visit.node) {
        if (reach(element, visit.line)) return pending.back().line;
      }
    }
  }
  return std::nullopt;
}

/// A point read from the file and the line it is on.
struct Point {
  std::string name;
  core::Vec2 p = core::Vec2::Zero();
  int line = 0;
};

struct Agent {
  std::string name;
  int line = 0;
  core::Vec2 start = core::Vec2::Zero();
  double heading = 0.0, radius = kDefaultRadius, max_vel = kDefaultMaxVel, goal_radius = 0.0;
  int group = -1;
  bool cyclic = true;
  ordered_json behaviour;
  std::vector<Point> goals;
};

/// Reads one HuNavSim agents file (hunav_agent_manager's agents.yaml, the hunav_loader node's
/// parameters): its agents with their behaviours, start poses and goals, their groups, then the
/// native scenario.
class HunavImporter {
 public:
  HunavImporter(const ImportOptions& options, ImportResult& result) : options_(options), result_(result) {}

  void run(const YAML::Node& root) {
    const auto found = find_parameters(root);
    if (!found) return;
    const YAML::Node& parameters = *found;
    const YAML::Node names = parameters["agents"];
    if (!is_sequence(names) || names.size() == 0) {
      fail(names ? names : parameters, "'agents' must list the agents' names (agents: [agent1, agent2])");
      return;
    }
    if (static_cast<int>(names.size()) > options_.limits.max_people) {
      fail(names, "the file lists more than the " + std::to_string(options_.limits.max_people) + " people a scenario may hold (--max-people)");
      return;
    }
    world_name_ = parameters["map"] && is_scalar(parameters["map"]) ? parameters["map"].Scalar() : "";
    // reset(), not =: assigning to a YAML::Node writes into the node it refers to.
    if (const YAML::Node goals = parameters["global_goals"]) {
      global_goals_.reset(goals);
      if (!is_map(goals)) fail(goals, "global_goals must map each goal's name to its point (1: {x: …, y: …})");
    }
    for (const YAML::Node& name : names) {
      if (!is_scalar(name) || name.Scalar().empty()) {
        fail(name, "an entry of 'agents' must be an agent's name");
        continue;
      }
      if (std::any_of(agents_.begin(), agents_.end(), [&](const Agent& a) { return a.name == name.Scalar(); })) {
        fail(name, "agent '" + name.Scalar() + "' is listed twice");
        continue;
      }
      const YAML::Node block = parameters[name.Scalar()];
      if (!is_map(block)) {
        fail(block ? block : name, "agent '" + name.Scalar() + "' has no block of its parameters (" + name.Scalar() + ": {init_pose: …, goals: …})");
        continue;
      }
      read_agent(name.Scalar(), block, key_line(parameters, name.Scalar()));
    }
    if (!result_.errors.empty()) return;
    write();
  }

 private:
  void fail(const YAML::Node& node, const std::string& message) { result_.errors.push_back({node ? line_of(node) : 0, message}); }
  void warn(const YAML::Node& node, const std::string& message) { result_.warnings.push_back({node ? line_of(node) : 0, message}); }

  static int key_line(const YAML::Node& map, const std::string& key) {
    for (const auto& entry : map) {
      if (is_scalar(entry.first) && entry.first.Scalar() == key) return line_of(entry.first);
    }
    return line_of(map);
  }

  /// The hunav_loader node's parameters: under hunav_loader (or ROS 2's /**) and ros__parameters, or
  /// the document itself when it lists the agents at its top.
  std::optional<YAML::Node> find_parameters(const YAML::Node& root) {
    if (!is_map(root)) {
      fail(root, "a HuNavSim agents file is a YAML mapping (hunav_loader: ros__parameters: agents: […])");
      return std::nullopt;
    }
    if (root["image"] && root["resolution"]) {
      fail(root, "this is a ROS map YAML: give it with --map beside a HuNavSim agents file");
      return std::nullopt;
    }
    for (const char* node : {"hunav_loader", "/**"}) {
      if (is_map(root[node]) && is_map(root[node]["ros__parameters"])) return root[node]["ros__parameters"];
    }
    if (is_map(root["ros__parameters"])) return root["ros__parameters"];
    if (root["agents"]) return root;
    fail(root, "not a HuNavSim agents file: expected hunav_loader: ros__parameters: agents: [names] and a block per agent "
               "(hunav_agent_manager/config/agents.yaml)");
    return std::nullopt;
  }

  /// A number of the block; `fallback` when absent, nothing (and an error) when not a number.
  std::optional<double> number(const YAML::Node& block, const std::string& key, const std::string& owner, std::optional<double> fallback) {
    const YAML::Node value = block[key];
    if (!value) {
      if (!fallback) fail(block, owner + ": missing '" + key + "'");
      return fallback;
    }
    const auto parsed = is_scalar(value) ? core::parse_number(value.Scalar()) : std::nullopt;
    if (!parsed) fail(value, owner + ": " + key + " must be a number" + (is_scalar(value) ? ", got '" + value.Scalar() + "'" : ""));
    return parsed;
  }

  std::optional<bool> flag(const YAML::Node& block, const std::string& key, const std::string& owner, bool fallback) {
    const YAML::Node value = block[key];
    if (!value) return fallback;
    const std::string text = is_scalar(value) ? core::lower_case(value.Scalar()) : "";
    if (text == "true" || text == "yes" || text == "on") return true;
    if (text == "false" || text == "no" || text == "off") return false;
    fail(value, owner + ": " + key + " must be true or false");
    return std::nullopt;
  }

  /// A whole number within [low, high]; `fallback` when absent.
  std::optional<int> whole(const YAML::Node& block, const std::string& key, const std::string& owner, int fallback, int low, int high,
                           const std::string& meaning) {
    if (!block[key]) return fallback;
    const auto value = number(block, key, owner, std::nullopt);
    if (!value) return std::nullopt;
    if (*value != std::floor(*value) || *value < low || *value > high) {
      fail(block[key], owner + ": " + key + " must be " + meaning);
      return std::nullopt;
    }
    return static_cast<int>(*value);
  }

  std::optional<Point> point(const YAML::Node& block, const std::string& key, const std::string& owner) {
    const YAML::Node value = block[key];
    if (!is_map(value)) {
      fail(value ? value : block, owner + ": '" + key + "' must be a block with x and y");
      return std::nullopt;
    }
    const auto x = number(value, "x", owner + "." + key, std::nullopt), y = number(value, "y", owner + "." + key, std::nullopt);
    if (!x || !y) return std::nullopt;
    extent_low_ = extent_low_.cwiseMin(core::Vec2(*x, *y));
    extent_high_ = extent_high_.cwiseMax(core::Vec2(*x, *y));
    return Point{key, {*x, *y}, line_of(value)};
  }

  void read_agent(const std::string& name, const YAML::Node& block, int line) {
    static const std::vector<std::string> kKnown = {"id", "skin", "behavior", "group_id", "max_vel", "radius", "init_pose", "goal_radius", "cyclic_goals", "goals"};
    const std::size_t errors = result_.errors.size();
    Agent agent;
    agent.name = name;
    agent.line = line;
    const auto start = point(block, "init_pose", name);
    const auto heading = is_map(block["init_pose"]) ? number(block["init_pose"], "h", name + ".init_pose", 0.0) : 0.0;
    const auto radius = number(block, "radius", name, kDefaultRadius), max_vel = number(block, "max_vel", name, kDefaultMaxVel);
    const auto goal_radius = number(block, "goal_radius", name, 0.0);
    const auto cyclic = flag(block, "cyclic_goals", name, true);
    const auto group = whole(block, "group_id", name, -1, -1, std::numeric_limits<int>::max(), "a group's number, or -1 for none");
    if (radius && (*radius <= 0 || *radius > 1)) fail(block["radius"], name + ": radius must be more than 0 and at most 1 m");
    if (max_vel && (*max_vel <= 0 || *max_vel > 3)) fail(block["max_vel"], name + ": max_vel must be more than 0 and at most 3 m/s");
    agent.behaviour = read_behaviour(block, name);
    const YAML::Node goals = block["goals"];
    if (goals && !is_sequence(goals)) fail(goals, name + ": goals must list the goals' names");
    std::vector<std::string> goal_names;
    for (const YAML::Node& goal : is_sequence(goals) ? goals : YAML::Node()) {
      if (!is_scalar(goal) || std::find(kKnown.begin(), kKnown.end(), goal.Scalar()) != kKnown.end()) {
        fail(goal, name + ": an entry of goals must name a goal's block");
        continue;
      }
      goal_names.push_back(goal.Scalar());
      // HuNavSim 1 gives each agent its goals' blocks; HuNavSim 2 names shared ones in global_goals.
      const YAML::Node& global_goals = global_goals_;  // read through const: indexing a Node may add the key
      const bool own = static_cast<bool>(block[goal.Scalar()]), shared = is_map(global_goals) && global_goals[goal.Scalar()];
      if (!own && !shared) {
        fail(goal, name + ": goal '" + goal.Scalar() + "' has no block (" + goal.Scalar() + ": {x: …, y: …}) here or in global_goals");
      } else if (auto p = own ? point(block, goal.Scalar(), name) : point(global_goals, goal.Scalar(), "global_goals")) {
        agent.goals.push_back(std::move(*p));
      }
    }
    for (const auto& entry : block) {
      const std::string key = is_scalar(entry.first) ? entry.first.Scalar() : "";
      const bool known = std::find(kKnown.begin(), kKnown.end(), key) != kKnown.end() ||
                         std::find(goal_names.begin(), goal_names.end(), key) != goal_names.end();
      if (!known) warn(entry.first, name + ": unknown key '" + key + "' ignored");
    }
    if (result_.errors.size() > errors) return;
    agent.start = start->p;
    agent.heading = *heading;
    agent.radius = *radius;
    agent.max_vel = *max_vel;
    agent.goal_radius = *goal_radius;
    agent.cyclic = *cyclic;
    agent.group = *group;
    agents_.push_back(std::move(agent));
  }

  /// HuNavSim 2 writes a behaviour's type by name ("Regular" … "Threatening"): its number (1 … 6).
  static std::optional<int> behaviour_named(const std::string& text) {
    for (int k = 0; k < 6; ++k) {
      const std::string name = kBehaviours[k];
      if (text.size() == name.size() && std::equal(text.begin(), text.end(), name.begin(), [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; })) {
        return k + 1;
      }
    }
    return std::nullopt;
  }

  /// The behaviour as hrisim's scenario writes it: a name for HuNavSim's defaults, an object for a
  /// custom or random configuration (drawn here, once, as hunav_loader draws it at launch).
  ordered_json read_behaviour(const YAML::Node& block, const std::string& owner) {
    const YAML::Node node = block["behavior"];
    if (!node) return "regular";
    const std::string where = owner + ".behavior";
    const YAML::Node settings = is_map(node) ? node : YAML::Node(YAML::NodeType::Map);
    const YAML::Node type_node = is_map(node) ? node["type"] : node;
    const std::optional<int> named = is_scalar(type_node) ? behaviour_named(type_node.Scalar()) : std::nullopt;
    if (!named && is_scalar(type_node) && std::any_of(type_node.Scalar().begin(), type_node.Scalar().end(), [](unsigned char c) { return std::isalpha(c); })) {
      fail(type_node, (is_map(node) ? where + ": type" : owner + ": behavior") + " must be 1 (regular) … 6 (threatening) or its name (Regular … Threatening), got '" +
                          type_node.Scalar() + "'");
      return nullptr;
    }
    const auto type = named                ? named
                      : is_map(node) ? whole(node, "type", where, 1, 1, 6, "1 (regular) … 6 (threatening), or its name (Regular … Threatening)")
                                     : whole(block, "behavior", owner, 1, 1, 6, "1 (regular) … 6 (threatening), its name, or a block with type");
    const auto configuration = whole(settings, "configuration", where, kDefault, 0, 3, "0 (default), 1 (custom), 2 (random normal) or 3 (random uniform)");
    if (!type || !configuration) return nullptr;
    const std::string name = kBehaviours[*type - 1];
    if (*configuration == kDefault || name == "regular" || name == "impassive") return name;
    // hrisim's force factors are the scene's (locomotion.social_force), not each person's.
    for (const char* key : {"goal_force_factor", "obstacle_force_factor", "social_force_factor"}) {
      if (settings[key]) warn(settings[key], where + ": " + key + " is not read: everyone walks with HuNavSim's defaults (goal 2, obstacle 10, social 5)");
    }
    ordered_json behaviour{{"type", name}};
    if (*configuration == kCustom) {
      const auto duration = number(settings, "duration", where, kDefaultDuration), vel = number(settings, "vel", where, kDefaultBehaviourVel);
      const auto dist = number(settings, "dist", where, 0.0), force = number(settings, "other_force_factor", where, kDefaultOtherForceFactor);
      const auto once = flag(settings, "once", where, true);
      if (!duration || !vel || !dist || !force || !once) return nullptr;
      fill_behaviour(behaviour, std::max(*duration, 0.0), std::clamp(*vel, 0.0, kMaxBehaviourVel), std::max(*dist, 0.0),
                     std::clamp(*force, 0.0, kMaxOtherForceFactor));
      if (behaviour.contains("detection_distance") && behaviour["detection_distance"] == 0.0) {
        warn(node, where + ": dist is " + (settings["dist"] ? "0" : "not given (0)") + ": a " + name +
                       " person with a custom configuration then never sees the robot, as in HuNavSim");
      }
      behaviour["once"] = *once;
      return behaviour;
    }
    draw_behaviour(behaviour, *configuration == kRandomNormal, owner);
    warn(node, where + ": configuration " + (*configuration == kRandomNormal ? "random normal" : "random uniform") +
                   " drawn once at import (seed " + std::to_string(kBehaviourSeed) + "): " + behaviour.dump());
    return behaviour;
  }

  /// What each behaviour reads of `dist`: how far the robot is seen (surprised, scared), where the
  /// person stops from it (curious) or stands before it (threatening).
  static void fill_behaviour(ordered_json& behaviour, double duration, double vel, double dist, double force) {
    const std::string type = behaviour["type"];
    behaviour["duration"] = duration;
    if (type == "surprised" || type == "scared") behaviour["detection_distance"] = std::min(dist, 50.0);
    if (type == "curious" || type == "threatening") behaviour["distance"] = std::min(dist, 10.0);
    if (type == "scared" || type == "curious") behaviour["speed"] = vel;
    if (type == "scared") behaviour["force_factor"] = force;
  }

  /// hunav_loader's random configurations: normal or uniform draws around its defaults, per behaviour.
  void draw_behaviour(ordered_json& behaviour, bool normal, const std::string& owner) {
    core::Random random = core::Random(kBehaviourSeed).stream(owner);
    const auto draw = [&](double mean, double spread, double low, double high) {
      return normal ? random.normal(mean, spread) : random.uniform(low, high);
    };
    const std::string type = behaviour["type"];
    const double duration = draw(40.0, 15.0, 25.0, 60.0);
    double vel = 0.0, dist = 0.0, force = kDefaultOtherForceFactor;
    if (type == "curious") {
      vel = normal ? std::max(random.normal(0.8, 0.35), 0.4) : random.uniform(0.6, 1.2);
      dist = draw(1.5, 0.3, 1.0, 2.5);
    } else if (type == "surprised") {
      dist = normal ? std::max(random.normal(4.5, 2.5), 1.5) : random.uniform(2.0, 6.0);
    } else if (type == "scared") {
      vel = draw(0.8, 0.35, 0.6, 1.2);
      dist = normal ? std::max(random.normal(4.5, 2.5), 1.5) : random.uniform(2.0, 6.0);
      force = draw(20.0, 6.0, 10.0, 25.0);
    } else {
      dist = draw(1.4, 0.3, 0.8, 1.9);
    }
    // Centimetres and hundredths of a second: what a person would write.
    const auto rounded = [](double value) { return std::round(value * 100.0) / 100.0; };
    fill_behaviour(behaviour, rounded(std::max(duration, 0.0)), rounded(std::clamp(vel, 0.0, 3.0)), rounded(std::max(dist, 0.0)),
                   rounded(std::max(force, 0.0)));
  }

  /// The world: --map's, else the map the file's `map` names in a folder maps are looked up in
  /// (NAME.yaml, maps/NAME.yaml), else open ground round the agents and goals.
  ordered_json world() {
    if (options_.map) {
      std::string error;
      if (auto world = world_from_file(*options_.map, error)) return *world;
      result_.errors.push_back({0, error});
      return nullptr;
    }
    // Named as the loader finds it: relative to the folders both look in.
    if (!world_name_.empty() && world_name_.find_first_of("/\\") == std::string::npos && world_name_ != "." && world_name_ != "..") {
      for (const auto& folder : options_.map_search_path) {
        for (const std::string& candidate : {world_name_ + ".yaml", "maps/" + world_name_ + ".yaml"}) {
          if (std::filesystem::is_regular_file(folder / candidate)) return {{"map", candidate}};
        }
      }
    }
    result_.warnings.push_back({0, "no map" + (world_name_.empty() ? std::string() : " for world '" + world_name_ + "'") +
                                       ": the people walk on open ground; give the world's occupancy map with --map"});
    const core::Vec2 margin(kOpenGroundMargin, kOpenGroundMargin);
    return {{"bounds", {{"min", {extent_low_.x() - margin.x(), extent_low_.y() - margin.y()}}, {"max", {extent_high_.x() + margin.x(), extent_high_.y() + margin.y()}}}}};
  }

  /// An agent's goals as a routine; its name.
  std::string goals_routine(const Agent& agent) {
    const std::string routine = agent.name + "_goals";
    ordered_json gotos = ordered_json::array();
    for (const Point& goal : agent.goals) {
      // At least the default radius: hunav_loader reads a missing goal_radius as 0.
      result_.origins.push_back({"/routines/" + core::pointer_token(routine) + "/" + std::to_string(gotos.size()), goal.line});
      gotos.push_back({{"goto", {{"pose", {{"x", goal.p.x()}, {"y", goal.p.y()}}}, {"radius", std::max(agent.goal_radius, kDefaultGoalRadius)}}}});
    }
    routines_[routine] = gotos;
    return routine;
  }

  void write() {
    ordered_json world_json = world();
    if (world_json.is_null()) return;
    ordered_json humans = ordered_json::array(), actions = ordered_json::array(), groups = ordered_json::object();
    std::map<int, std::vector<const Agent*>> members;
    for (const Agent& agent : agents_) {
      result_.origins.push_back({"/humans/" + std::to_string(humans.size()), agent.line});
      humans.push_back({{"id", agent.name},
                        {"start", {{"x", agent.start.x()}, {"y", agent.start.y()}, {"theta", agent.heading}}},
                        {"radius", agent.radius},
                        {"preferred_speed", agent.max_vel},
                        {"behaviour", agent.behaviour}});
      if (agent.group >= 0) members[agent.group].push_back(&agent);
    }
    // A group walks its first member's goals in formation (HuNavSim's group members share them).
    std::vector<const Agent*> walkers;
    for (const Agent& agent : agents_) {
      const auto group = members.find(agent.group);
      if (group == members.end() || group->second.size() < 2) walkers.push_back(&agent);
      else if (group->second.front() == &agent) walkers.push_back(&agent);
    }
    for (const Agent* agent : walkers) {
      const auto group = members.find(agent->group);
      const bool in_group = group != members.end() && group->second.size() >= 2;
      std::string group_name;
      if (in_group) {
        group_name = "group_" + std::to_string(agent->group);
        ordered_json names = ordered_json::array();
        for (const Agent* member : group->second) {
          names.push_back(member->name);
          const bool same = member->goals.size() == agent->goals.size() &&
                            std::equal(member->goals.begin(), member->goals.end(), agent->goals.begin(), [](const Point& a, const Point& b) { return (a.p - b.p).norm() < 1e-9; });
          if (!same) {
            result_.warnings.push_back({member->line, member->name + ": walks with group " + std::to_string(agent->group) + ", whose goals are " +
                                                          agent->name + "'s (its first member's); its own are not walked"});
          }
        }
        groups[group_name] = {{"members", names}};
        result_.origins.push_back({"/groups/" + core::pointer_token(group_name), agent->line});
      }
      if (agent->goals.empty()) continue;
      result_.origins.push_back({"/steps/0/actions/" + std::to_string(actions.size()), agent->line});
      ordered_json action = in_group ? ordered_json{{"group", group_name}} : ordered_json{{"agent", agent->name}};
      action["routine"] = goals_routine(*agent);
      if (agent->cyclic) action["repeat"] = true;
      actions.push_back(action);
    }
    ordered_json& out = result_.scenario;
    const std::string file = options_.source_name.empty() ? std::string("a HuNavSim agents file") : "the HuNavSim agents file " + options_.source_name;
    out["name"] = options_.source_name.empty() ? "hunav" : std::filesystem::path(options_.source_name).stem().string();
    out["description"] = "Imported from " + file + (world_name_.empty() ? "" : " (world '" + world_name_ + "')") +
                         ": every person walks their goals (over and over when cyclic) with HuNavSim's behaviour, by the social "
                         "force model with HuNavSim's parameters.";
    out["world"] = world_json;
    out["locomotion"] = {{"avoidance", "social_force"},
                         {"social_force", {{"desired_factor", kHunavGoalForceFactor}, {"obstacle_factor", kHunavObstacleForceFactor},
                                           {"social_factor", kHunavSocialForceFactor}, {"obstacle_sigma", kHunavObstacleSigma}}}};
    out["humans"] = humans;
    out["robots"] = ordered_json::array();
    if (!groups.empty()) out["groups"] = groups;
    if (!routines_.empty()) out["routines"] = routines_;
    out["steps"] = ordered_json::array();
    if (!actions.empty()) out["steps"].push_back({{"name", "walk"}, {"actions", actions}});
  }

  const ImportOptions& options_;
  ImportResult& result_;
  std::string world_name_;
  YAML::Node global_goals_;  ///< HuNavSim 2's goals shared by name (absent in HuNavSim 1's files)
  std::vector<Agent> agents_;
  core::Vec2 extent_low_{std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
  core::Vec2 extent_high_ = -extent_low_;
  ordered_json routines_ = ordered_json::object();
};

}  // namespace

ImportResult import_hunav(std::string_view yaml, const ImportOptions& options) {
  ImportResult result;
  if (!check_utf8(yaml, result)) return result;
  if (nesting_bound(yaml) > kMaxNesting) {
    result.errors.push_back({0, "the YAML nests more than " + std::to_string(kMaxNesting) + " levels deep; a HuNavSim agents file nests five"});
    return result;
  }
  try {
    const YAML::Node root = YAML::Load(std::string(yaml));
    if (const auto line = line_past_node_limit(root, kMaxExpandedNodes)) {
      result.errors.push_back({*line, "the YAML expands to more than " + std::to_string(kMaxExpandedNodes) + " nodes by line " + std::to_string(*line) +
                                          " (an alias counts each time it is used: what it names is read again there); a HuNavSim agents file "
                                          "has a few dozen per person"});
      return result;
    }
    HunavImporter(options, result).run(root);
  } catch (const YAML::Exception& e) {
    const int line = e.mark.is_null() ? 0 : e.mark.line + 1;
    result.errors.push_back({line, "malformed YAML" + (line > 0 ? " at line " + std::to_string(line) : std::string()) + ": " + e.msg});
  }
  return result;
}

}  // namespace hrisim::scenario
