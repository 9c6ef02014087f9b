#include <tinyxml2.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/json_schema.hpp"
#include "core/math.hpp"
#include "core/files.hpp"
#include "scenario/import.hpp"
#include "scenario/xml_reader.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::ordered_json;
using tinyxml2::XMLElement;

const std::set<std::string> kPrimitiveActions = {"goto_action", "wait_action", "publish_action", "lookat_action"};

/// A <goals> child is a scenario when it holds steps (elements with children, or AsyncActions);
/// a compound task holds actions only.
bool is_scenario(const XMLElement* element) {
  for (const XMLElement* child = element->FirstChildElement(); child; child = child->NextSiblingElement()) {
    if (std::string(child->Name()) == "AsyncActions" || child->FirstChildElement()) return true;
  }
  return false;
}

/// Slots named p1, p2, ... are taken in the order of their numbers; others in document order.
int slot_number(const XMLElement* slot) {
  const std::string name = slot->Name();
  int number = 0;
  if (name.size() < 2 || name[0] != 'p') return -1;
  const auto [end, ec] = std::from_chars(name.data() + 1, name.data() + name.size(), number);
  return ec == std::errc() && end == name.data() + name.size() ? number : -1;
}

class ImhusImporter {
 public:
  ImhusImporter(const ImportOptions& options, ImportResult& result) : options_(options), reader_(result) {}

  void run(const tinyxml2::XMLDocument& document) {
    const XMLElement* goals = nullptr;
    const XMLElement* map_name = nullptr;
    for (const XMLElement* top = document.FirstChildElement(); top; top = top->NextSiblingElement()) {
      const std::string name = top->Name();
      if (name == "map_name") {
        map_name = top;
      } else if (name == "agents") {
        read_agents(top);
      } else if (name == "poses") {
        read_poses(top);
      } else if (name == "social_space") {
        read_social_spaces(top);  // also accepted outside <poses>
      } else if (name == "goals") {
        goals = top;
      } else if (name == "groups") {
        read_groups(top);
      } else {
        reader_.warn(top, "unknown element <" + name + "> ignored");
      }
    }
    if (!goals) {
      reader_.fail(nullptr, "no <goals> element: the file has no scenario");
      return;
    }
    read_goals(goals);
    build_world(map_name);
  }

 private:
  void read_agents(const XMLElement* agents) {
    for (const XMLElement* agent = agents->FirstChildElement(); agent; agent = agent->NextSiblingElement()) {
      const std::string kind = agent->Name();
      const auto id = reader_.text(agent, "id");
      if (!id) continue;
      if (kind != "human" && kind != "robot") {
        reader_.warn(agent, "unknown agent type <" + kind + "> ignored");
        continue;
      }
      if (!agent_kinds_.emplace(*id, kind).second) reader_.fail(agent, "agent '" + *id + "' is declared twice");
      agent_order_.push_back(*id);
      agent_lines_[*id] = agent->GetLineNum();
    }
  }

  /// <group id="g" members="a b c"/>: the first member leads.
  void read_groups(const XMLElement* groups) {
    for (const XMLElement* group = groups->FirstChildElement(); group; group = group->NextSiblingElement()) {
      const auto id = reader_.text(group, "id");
      const auto members = reader_.text(group, "members");
      if (!id || !members) continue;
      ordered_json list = ordered_json::array();
      std::istringstream names(*members);
      for (std::string member; names >> member;) {
        if (!agent_kinds_.contains(member)) {
          reader_.fail(group, "unknown member '" + member + "' of group '" + *id + "'");
        }
        list.push_back(member);
      }
      if (list.size() < 2) reader_.fail(group, "group '" + *id + "' needs at least two members");
      if (agent_kinds_.contains(*id) || groups_.contains(*id)) reader_.fail(group, "'" + *id + "' is already an agent or group");
      groups_[*id] = {{"members", list}};
    }
  }

  void read_poses(const XMLElement* parent) {
    for (const XMLElement* pose = parent->FirstChildElement(); pose; pose = pose->NextSiblingElement()) {
      if (std::string(pose->Name()) == "social_space") {
        read_social_spaces(pose);
        continue;
      }
      if (!pose->Attribute("id")) {
        read_poses(pose);  // IMHuS wraps its poses in a <pose> element without attributes
        continue;
      }
      const auto id = reader_.text(pose, "id");
      const auto x = reader_.number(pose, "x"), y = reader_.number(pose, "y");
      const double theta = reader_.optional_number(pose, "theta").value_or(0.0);
      if (!x || !y) continue;
      if (poses_.contains(*id)) reader_.fail(pose, "pose '" + *id + "' is defined twice");
      poses_[*id] = core::Pose2{*x, *y, theta};
      ordered_json location{{"x", *x}, {"y", *y}, {"theta", theta}};
      if (const auto radius = reader_.optional_number(pose, "radius")) location["radius"] = *radius;
      locations_[*id] = location;
      reader_.result().origins.push_back({"/locations/" + core::pointer_token(*id), pose->GetLineNum()});
    }
  }

  void read_social_spaces(const XMLElement* parent) {
    for (const XMLElement* space = parent->FirstChildElement(); space; space = space->NextSiblingElement()) {
      const auto id = reader_.text(space, "id");
      const auto x = reader_.number(space, "x"), y = reader_.number(space, "y");
      if (!id || !x || !y) continue;
      std::vector<const XMLElement*> slots;
      for (const XMLElement* slot = space->FirstChildElement(); slot; slot = slot->NextSiblingElement()) slots.push_back(slot);
      if (std::all_of(slots.begin(), slots.end(), [](const XMLElement* s) { return slot_number(s) >= 0; })) {
        std::stable_sort(slots.begin(), slots.end(),
                         [](const XMLElement* a, const XMLElement* b) { return slot_number(a) < slot_number(b); });
      }
      ordered_json native{{"x", *x}, {"y", *y}, {"slots", ordered_json::array()}};
      for (const XMLElement* slot : slots) {
        native["slots"].push_back({{"x", reader_.optional_number(slot, "relativeX").value_or(0.0)},
                                   {"y", reader_.optional_number(slot, "relativeY").value_or(0.0)},
                                   {"theta", reader_.optional_number(slot, "theta").value_or(0.0)}});
      }
      if (native["slots"].empty()) {
        // IMHuS's own files leave placeholders ("TODO define as elevator_door1"): harmless unless used.
        reader_.warn(space, "social space '" + *id + "' has no slots and is left out");
        empty_spaces_[*id] = space->GetLineNum();
        continue;
      }
      social_spaces_[*id] = native;
      reader_.result().origins.push_back({"/social_spaces/" + core::pointer_token(*id), space->GetLineNum()});
      for (std::size_t k = 0; k < slots.size(); ++k) {
        reader_.result().origins.push_back({"/social_spaces/" + core::pointer_token(*id) + "/slots/" + std::to_string(k), slots[k]->GetLineNum()});
      }
    }
  }

  void read_goals(const XMLElement* goals) {
    // IMHuS groups them as <compound_tasks> and <scenarios>; without those, each child is classified.
    std::vector<const XMLElement*> scenarios;
    for (const XMLElement* element = goals->FirstChildElement(); element; element = element->NextSiblingElement()) {
      const std::string group = element->Name();
      if (group == "compound_tasks" || group == "scenarios") {
        for (const XMLElement* child = element->FirstChildElement(); child; child = child->NextSiblingElement()) {
          if (group == "scenarios") {
            scenarios.push_back(child);
          } else {
            task_elements_.emplace(child->Name(), child);
          }
        }
      } else if (is_scenario(element)) {
        scenarios.push_back(element);
      } else {
        task_elements_.emplace(element->Name(), element);
      }
    }
    const XMLElement* chosen = nullptr;
    std::string available;
    for (const XMLElement* scenario : scenarios) {
      available += (available.empty() ? "" : ", ") + std::string(scenario->Name());
      if (!chosen && (options_.scenario.empty() || options_.scenario == scenario->Name())) chosen = scenario;
    }
    if (!chosen) {
      reader_.fail(goals, options_.scenario.empty() ? "the file defines no scenario"
                                                   : "no scenario '" + options_.scenario + "' (the file has: " + available + ")");
      return;
    }
    name_ = chosen->Name();
    for (const auto& [task, element] : task_elements_) {
      ordered_json actions = ordered_json::array();
      for (const XMLElement* action = element->FirstChildElement(); action; action = action->NextSiblingElement()) {
        if (auto native = read_action(action, true)) actions.push_back(std::move(*native));
      }
      if (actions.empty()) reader_.fail(element, "compound task '" + task + "' has no actions");
      tasks_[task] = actions;
    }
    steps_ = read_steps(chosen);
    // Files keep agents' initial poses in a scenario of their own (IMHuS's `init`): an agent the chosen
    // scenario does not place starts where another scenario's first step puts it.
    for (const XMLElement* scenario : scenarios) {
      if (scenario != chosen) note_initial_poses(scenario);
    }
    // A robot choreography X_robot runs beside X: its step i joins step i of X.
    for (const XMLElement* scenario : scenarios) {
      if (std::string(scenario->Name()) != name_ + "_robot") continue;
      const ordered_json robot_steps = read_steps(scenario);
      for (std::size_t i = 0; i < robot_steps.size(); ++i) {
        if (i < steps_.size()) {
          for (const auto& action : robot_steps[i]["actions"]) steps_[i]["actions"].push_back(action);
        } else {
          steps_.push_back(robot_steps[i]);
        }
      }
    }
  }

  /// The regular steps of a scenario element; its AsyncActions are collected on the way.
  ordered_json read_steps(const XMLElement* scenario) {
    ordered_json steps = ordered_json::array();
    for (const XMLElement* step = scenario->FirstChildElement(); step; step = step->NextSiblingElement()) {
      if (std::string(step->Name()) == "AsyncActions") {
        for (const XMLElement* response = step->FirstChildElement(); response; response = response->NextSiblingElement()) {
          if (std::string(response->Name()) != "async_action_res") {
            reader_.fail(response, "AsyncActions holds async_action_res elements, not <" + std::string(response->Name()) + ">");
            continue;
          }
          if (const auto task = reader_.text(response, "taskID")) {
            if (require_task(response, *task)) async_.push_back({{"routine", *task}});
          }
        }
        continue;
      }
      ordered_json actions = ordered_json::array();
      for (const XMLElement* action = step->FirstChildElement(); action; action = action->NextSiblingElement()) {
        if (auto native = read_action(action, false, steps.empty())) actions.push_back(std::move(*native));
      }
      if (actions.empty()) {
        reader_.warn(step, "step '" + std::string(step->Name()) + "' has no actions and is left out");
        continue;
      }
      steps.push_back({{"name", step->Name()}, {"actions", actions}});
    }
    return steps;
  }

  bool require_task(const XMLElement* element, const std::string& task) {
    if (task_elements_.contains(task)) return true;
    reader_.fail(element, "unknown compound task '" + task + "'");
    return false;
  }

  std::optional<ordered_json> read_action(const XMLElement* action, bool in_task, bool first_step = false) {
    const std::string tag = action->Name();
    ordered_json native = ordered_json::object();
    if (const char* entity = action->Attribute("entityID")) {
      if (in_task) {
        reader_.fail(action, "actions of a compound task do not name an entityID");
        return std::nullopt;
      }
      if (groups_.contains(entity)) {
        // What the native format lets a group do: walk in formation, wait, look, or run a compound task.
        const bool compound_task = action->Attribute("taskID") && !kPrimitiveActions.contains(tag) && tag != "request_action";
        if (tag != "goto_action" && tag != "wait_action" && tag != "lookat_action" && !compound_task) {
          reader_.fail(action, "a group (" + std::string(entity) + ") can be given a goto_action, wait_action, lookat_action or a compound task (taskID)");
          return std::nullopt;
        }
        native["group"] = entity;
        for (const auto& member : groups_[entity]["members"]) acting_.insert(member.get<std::string>());
      } else if (!agent_kinds_.contains(entity)) {
        reader_.fail(action, "unknown entity '" + std::string(entity) + "' (not declared in <agents> or <groups>)");
        return std::nullopt;
      } else {
        native["agent"] = entity;
        acting_.insert(entity);
      }
    } else if (!in_task) {
      reader_.fail(action, "step action <" + tag + "> needs an entityID");
      return std::nullopt;
    }
    if (const char* task = action->Attribute("taskID"); task && !kPrimitiveActions.contains(tag) && tag != "request_action") {
      if (!require_task(action, task)) return std::nullopt;
      native["routine"] = task;
    } else if (tag == "goto_action") {
      if (!read_goto(action, native)) return std::nullopt;
    } else if (tag == "wait_action") {
      if (action->Attribute("duration")) {
        const auto duration = reader_.optional_number(action, "duration");
        if (!duration) return std::nullopt;
        native["wait"] = {{"duration", *duration}};
      } else if (action->Attribute("topic") && action->Attribute("event")) {
        native["wait"] = {{"topic", action->Attribute("topic")}, {"message", action->Attribute("event")}};
      } else {
        reader_.fail(action, "wait_action needs duration, or topic and event");
        return std::nullopt;
      }
    } else if (tag == "publish_action") {
      const auto topic = reader_.text(action, "topic"), message = reader_.text(action, "msg");
      if (!topic || !message) return std::nullopt;
      native["publish"] = {{"topic", *topic}, {"message", *message}};
    } else if (tag == "request_action") {
      const auto task = reader_.text(action, "taskID");
      if (!task || !require_task(action, *task)) return std::nullopt;
      if (native.contains("agent") && agent_kinds_[native["agent"].get<std::string>()] != "robot") {
        reader_.fail(action, "only a robot makes requests");
        return std::nullopt;
      }
      native["request"] = {{"routine", *task}};
    } else if (tag == "lookat_action") {
      if (const auto angle = reader_.optional_number(action, "angle")) {
        native["look_at"] = {{"angle", *angle}};
      } else {
        reader_.fail(action, "lookat_action needs an angle");
        return std::nullopt;
      }
    } else {
      reader_.fail(action, "unknown action <" + tag + "> (expected goto_action, wait_action, publish_action, "
                           "lookat_action, or an element with a taskID)");
      return std::nullopt;
    }
    if (first_step && native.contains("goto")) note_first_pose(native);
    native[kLineKey] = action->GetLineNum();  // moved to the origins once the actions have their places
    return native;
  }

  bool read_goto(const XMLElement* action, ordered_json& native) {
    if (const char* pose_id = action->Attribute("poseID")) {
      const auto pose = poses_.find(pose_id);
      if (pose == poses_.end()) {
        reader_.fail(action, "unknown pose '" + std::string(pose_id) + "'");
        return false;
      }
      ordered_json go{{"location", pose_id}};
      const double dx = reader_.optional_number(action, "relativeX").value_or(0.0);
      const double dy = reader_.optional_number(action, "relativeY").value_or(0.0);
      const double dtheta = reader_.optional_number(action, "relativeTheta").value_or(0.0);
      if (dx != 0.0 || dy != 0.0 || dtheta != 0.0) {
        // IMHuS offsets are along the map axes; native offsets are in the location's frame.
        const double c = std::cos(pose->second.theta), s = std::sin(pose->second.theta);
        go["offset"] = {{"x", c * dx + s * dy}, {"y", -s * dx + c * dy}, {"theta", dtheta}};
      }
      native["goto"] = go;
      return true;
    }
    if (const char* space = action->Attribute("socialSpaceID")) {
      if (const auto empty = empty_spaces_.find(space); empty != empty_spaces_.end()) {
        reader_.fail(action, "social space '" + std::string(space) + "' has no slots (line " + std::to_string(empty->second) + ")");
        return false;
      }
      if (!social_spaces_.contains(space)) {
        reader_.fail(action, "unknown social space '" + std::string(space) + "'");
        return false;
      }
      native["goto"] = {{"social_space", space}};
      return true;
    }
    if (action->Attribute("x") && action->Attribute("y")) {
      const auto x = reader_.number(action, "x"), y = reader_.number(action, "y");
      if (!x || !y) return false;
      ordered_json go{{"pose", {{"x", *x}, {"y", *y}, {"theta", reader_.optional_number(action, "theta").value_or(0.0)}}}};
      if (const auto radius = reader_.optional_number(action, "radius")) go["radius"] = *radius;
      native["goto"] = go;
      return true;
    }
    reader_.fail(action, "goto_action needs poseID, socialSpaceID, or x and y");
    return false;
  }

  /// The poses another scenario's first step sends agents to with a poseID, as fallback starts.
  void note_initial_poses(const XMLElement* scenario) {
    const XMLElement* step = scenario->FirstChildElement();
    while (step && std::string(step->Name()) == "AsyncActions") step = step->NextSiblingElement();
    if (!step) return;
    for (const XMLElement* action = step->FirstChildElement(); action; action = action->NextSiblingElement()) {
      const char* entity = action->Attribute("entityID");
      const char* pose = action->Attribute("poseID");
      if (std::string(action->Name()) != "goto_action" || !entity || !pose || !poses_.contains(pose) || fallback_starts_.contains(entity)) continue;
      const core::Pose2& p = poses_.at(pose);
      fallback_starts_[entity] = {{"x", p.x}, {"y", p.y}, {"theta", p.theta}};
    }
  }

  /// IMHuS agents appear at the pose of their first goto in the first step; hrisim starts them there.
  void note_first_pose(const ordered_json& native) {
    if (!native.contains("agent")) return;
    const std::string agent = native["agent"];
    if (starts_.contains(agent)) return;
    const ordered_json& go = native["goto"];
    if (go.contains("location") && !go.contains("offset")) {
      const core::Pose2& pose = poses_.at(go["location"].get<std::string>());
      starts_[agent] = {{"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}};
    } else if (go.contains("pose")) {
      starts_[agent] = go["pose"];
    }
  }

  void build_world(const XMLElement* map_name) {
    ordered_json& out = reader_.result().scenario;
    out = ordered_json::object();
    out["name"] = name_;
    out["description"] = "Imported from the IMHuS choreography " +
                         (options_.source_name.empty() ? std::string("file") : options_.source_name) + ", scenario " + name_ + ".";
    std::string error;
    if (options_.map) {
      if (auto world = world_from_file(*options_.map, error)) {
        out["world"] = *world;
      } else {
        reader_.fail(nullptr, error);
      }
    } else if (!map_name || !map_name->Attribute("name")) {
      reader_.fail(nullptr, "no <map_name name=...>: give the map with --map");
    } else {
      const std::string map = map_name->Attribute("name");
      const auto found = core::find_file(options_.map_search_path, std::filesystem::path("maps") / (map + ".world.json"),
                                         options_.limits.confine_files);
      if (!found) {
        reader_.fail(map_name, "unknown map '" + map + "': no maps/" + map + ".world.json among the bundled scenarios (use --map FILE)");
      } else if (auto world = world_from_file(*found, error)) {
        out["world"] = *world;
      } else {
        reader_.fail(map_name, error);
      }
    }
    // A bundled world names the social spaces its elevators clear; keep those this file defines.
    if (out.contains("world") && out["world"].contains("elevators")) {
      for (auto& elevator : out["world"]["elevators"]) {
        if (!elevator.contains("social_spaces")) continue;
        ordered_json kept = ordered_json::array();
        for (const auto& space : elevator["social_spaces"]) {
          if (social_spaces_.contains(space.get<std::string>())) {
            kept.push_back(space);
          } else {
            reader_.warn(nullptr, "the map's elevator clears social space '" + space.get<std::string>() +
                                      "', which this file does not define");
          }
        }
        elevator["social_spaces"] = kept;
      }
    }
    out["locations"] = locations_;
    out["social_spaces"] = social_spaces_;
    out["humans"] = ordered_json::array();
    out["robots"] = ordered_json::array();
    for (const std::string& id : agent_order_) {
      const bool human = agent_kinds_[id] == "human";
      ordered_json start;
      if (starts_.contains(id)) {
        start = starts_[id];
      } else if (acting_.contains(id) && fallback_starts_.contains(id)) {
        start = fallback_starts_[id];
      } else if (!human && (poses_.contains("initial_pose_" + id) || poses_.contains("initial_pose_robot"))) {
        const core::Pose2& pose = poses_.at(poses_.contains("initial_pose_" + id) ? "initial_pose_" + id : "initial_pose_robot");
        start = {{"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}};
      } else if (!acting_.contains(id)) {
        reader_.warn(nullptr, std::string(human ? "human" : "robot") + " '" + id + "' takes no part in scenario '" + name_ +
                                  "' (no initial pose, no action) and is left out");
        continue;
      } else {
        reader_.fail(nullptr, std::string(human ? "human" : "robot") + " '" + id +
                                  "' has no initial pose: give it a goto_action with a poseID in the first step" +
                                  (human ? "" : ", or define the pose initial_pose_robot"));
        continue;
      }
      auto& list = out[human ? "humans" : "robots"];
      reader_.result().origins.push_back({std::string(human ? "/humans/" : "/robots/") + std::to_string(list.size()), agent_lines_[id]});
      list.push_back({{"id", id}, {"start", start}});
    }
    if (!groups_.empty()) out["groups"] = groups_;
    out["routines"] = tasks_;  // IMHuS's compound tasks are hrisim's routines
    out["steps"] = steps_;
    out["async"] = async_;
    // Each action's line, now that it has its place (a robot choreography's steps join the scenario's).
    const auto take_lines = [&](ordered_json& actions, const std::string& pointer) {
      for (std::size_t a = 0; a < actions.size(); ++a) {
        if (!actions[a].contains(kLineKey)) continue;
        reader_.result().origins.push_back({pointer + "/" + std::to_string(a), actions[a][kLineKey].get<int>()});
        actions[a].erase(kLineKey);
      }
    };
    for (auto& [task, actions] : out["routines"].items()) take_lines(actions, "/routines/" + core::pointer_token(task));
    for (std::size_t s = 0; s < out["steps"].size(); ++s) take_lines(out["steps"][s]["actions"], "/steps/" + std::to_string(s) + "/actions");
  }

  /// Where an action was read, kept on it until it has its place in the scenario (not a native key).
  static constexpr const char* kLineKey = "_xml_line";

  const ImportOptions& options_;
  XmlReader reader_;
  std::string name_;
  std::map<std::string, std::string> agent_kinds_;
  std::vector<std::string> agent_order_;
  std::map<std::string, int> agent_lines_;
  std::map<std::string, core::Pose2> poses_;
  ordered_json locations_ = ordered_json::object();
  ordered_json social_spaces_ = ordered_json::object();
  std::map<std::string, const XMLElement*> task_elements_;
  ordered_json tasks_ = ordered_json::object();
  ordered_json groups_ = ordered_json::object();
  ordered_json steps_ = ordered_json::array();
  ordered_json async_ = ordered_json::array();
  std::map<std::string, ordered_json> starts_;
  std::map<std::string, ordered_json> fallback_starts_;  ///< from other scenarios' first steps
  std::map<std::string, int> empty_spaces_;             ///< social spaces without slots, by their line
  std::set<std::string> acting_;  ///< agents some step action names
};

}  // namespace

ImportResult import_imhus(std::string_view xml, const ImportOptions& options) {
  ImportResult result;
  tinyxml2::XMLDocument document;
  if (!parse_xml(xml, document, result)) return result;
  ImhusImporter(options, result).run(document);
  return result;
}

}  // namespace hrisim::scenario
