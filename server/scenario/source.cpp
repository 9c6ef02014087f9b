#include "scenario/source.hpp"

#include <cmath>

namespace hrisim::scenario {

std::string_view to_string(SourceFormat format) {
  switch (format) {
    case SourceFormat::json: return "json";
    case SourceFormat::imhus_xml: return "imhus_xml";
    case SourceFormat::pedsim_xml: return "pedsim_xml";
    case SourceFormat::hunav_yaml: return "hunav_yaml";
  }
  return "json";
}

std::optional<SourceFormat> source_format(std::string_view name) {
  if (name == "json") return SourceFormat::json;
  if (name == "imhus" || name == "imhus_xml") return SourceFormat::imhus_xml;
  if (name == "pedsim" || name == "pedsim_xml") return SourceFormat::pedsim_xml;
  if (name == "hunav" || name == "hunav_yaml") return SourceFormat::hunav_yaml;
  return std::nullopt;
}

SourceFormat detect_source_format(std::string_view text) {
  const std::size_t first = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
  if (first == std::string_view::npos || text[first] == '{' || text[first] == '[') return SourceFormat::json;
  if (text[first] != '<') return text.find("agents:") != std::string_view::npos ? SourceFormat::hunav_yaml : SourceFormat::json;
  return detect_xml_format(text) == "pedsim" ? SourceFormat::pedsim_xml : SourceFormat::imhus_xml;
}

nlohmann::json SourceIssue::to_json() const {
  nlohmann::json issue = nlohmann::json::object();
  if (line > 0) issue["line"] = line;
  if (!pointer.empty() || line <= 0) issue["pointer"] = pointer;
  issue["message"] = message;
  return issue;
}

CompiledSource compile_source(std::string_view text, SourceFormat format, const SourceOptions& options) {
  CompiledSource compiled;
  compiled.format = format;
  auto adopt = [&](const LoadResult& loaded) {
    for (const auto& error : loaded.errors) compiled.errors.push_back({error.pointer, 0, error.message});
    for (const auto& warning : loaded.warnings) compiled.warnings.push_back({warning.pointer, 0, warning.message});
    compiled.model = loaded.model;
  };
  if (format == SourceFormat::json) {
    // Parsed once here to keep the document; load_scenario_text words the syntax errors.
    const nlohmann::json document = nlohmann::json::parse(text, nullptr, false);
    if (document.is_discarded()) {
      adopt(load_scenario_text(text, options.load));
      return compiled;
    }
    compiled.document = document;
    adopt(load_scenario(document, options.load));
    return compiled;
  }
  const ImportResult imported = format == SourceFormat::imhus_xml  ? import_imhus(text, options.import)
                                : format == SourceFormat::pedsim_xml ? import_pedsim(text, options.import)
                                                                     : import_hunav(text, options.import);
  for (const auto& error : imported.errors) compiled.errors.push_back({"", std::max(error.line, 1), error.message});
  for (const auto& warning : imported.warnings) compiled.warnings.push_back({"", std::max(warning.line, 1), warning.message});
  if (!compiled.errors.empty()) return compiled;
  compiled.document = nlohmann::json::parse(imported.scenario.dump());
  adopt(load_scenario(compiled.document, options.load));
  // What validation finds in an imported scenario is said at the line of the file it came from too.
  for (auto* issues : {&compiled.errors, &compiled.warnings}) {
    for (SourceIssue& issue : *issues) issue.line = origin_line(imported, issue.pointer);
  }
  return compiled;
}

nlohmann::json summarize(const Model& model) {
  int humans = 0;
  nlohmann::json robots = nlohmann::json::array();
  for (const AgentDef& agent : model.agents) {
    if (agent.kind == AgentKind::human) {
      ++humans;
    } else {
      robots.push_back({{"id", agent.id}, {"model", agent.robot_model ? nlohmann::json(agent.robot_model->name) : nlohmann::json()}});
    }
  }
  return {{"name", model.name},
          {"description", model.description},
          {"humans", humans},
          {"robots", robots},
          {"task", model.task ? nlohmann::json(model.task->name) : nlohmann::json()},
          {"duration", model.time_limit},
          {"steps", model.steps.size()},
          {"dt", model.dt}};
}

namespace {

nlohmann::json pose_json(const Pose2& pose) { return {{"x", pose.x}, {"y", pose.y}, {"theta", pose.theta}}; }
nlohmann::json point_json(const Vec2& p) { return nlohmann::json::array({p.x(), p.y()}); }

}  // namespace

nlohmann::json world_geometry(const Model& model) {
  const world::OccupancyGrid& grid = model.grid;
  const Vec2 low = grid.origin(), high = low + Vec2(grid.width() * grid.resolution(), grid.height() * grid.resolution());
  nlohmann::json walls = nlohmann::json::array();
  for (const world::Segment& segment : model.outline) {
    walls.push_back({{"from", point_json(segment.a)}, {"to", point_json(segment.b)},
                     {"top", std::isfinite(segment.top) ? nlohmann::json(segment.top) : nlohmann::json()}});
  }
  nlohmann::json obstacles = nlohmann::json::array();
  for (const Obstacle& obstacle : model.obstacles) {
    nlohmann::json polygon = nlohmann::json::array();
    for (const Vec2& p : obstacle.polygon) polygon.push_back(point_json(p));
    obstacles.push_back({{"name", obstacle.name}, {"polygon", polygon}, {"height", obstacle.height},
                         {"mesh", obstacle.mesh.empty() ? nlohmann::json() : nlohmann::json(obstacle.mesh)}});
  }
  nlohmann::json doors = nlohmann::json::array();
  for (const Door& door : model.doors) {
    doors.push_back({{"name", door.name}, {"from", point_json(door.from)}, {"to", point_json(door.to)}, {"thickness", door.thickness},
                     {"initially_open", door.initially_open}});
  }
  nlohmann::json elevators = nlohmann::json::array();
  for (const Elevator& elevator : model.elevators) {
    nlohmann::json names = nlohmann::json::array();
    for (const int d : elevator.doors) names.push_back(model.doors[d].name);
    elevators.push_back({{"name", elevator.name}, {"doors", names}});
  }
  nlohmann::json locations = nlohmann::json::array();
  for (const Location& location : model.locations) {
    nlohmann::json entry = pose_json(location.pose);
    entry["name"] = location.name;
    entry["radius"] = location.radius;
    locations.push_back(entry);
  }
  nlohmann::json spaces = nlohmann::json::array();
  for (const SocialSpace& space : model.social_spaces) {
    nlohmann::json slots = nlohmann::json::array();
    for (const Pose2& slot : space.slots) slots.push_back(pose_json(slot));
    spaces.push_back({{"name", space.name}, {"centre", pose_json(space.centre)}, {"slots", slots}});
  }
  nlohmann::json agents = nlohmann::json::array();
  for (const AgentDef& agent : model.agents) {
    agents.push_back({{"id", agent.id},
                      {"kind", agent.kind == AgentKind::human ? "human" : "robot"},
                      {"type", agent.kind == AgentKind::human ? nlohmann::json(agent.type) : nlohmann::json()},
                      {"model", agent.robot_model ? nlohmann::json(agent.robot_model->name) : nlohmann::json()},
                      {"radius", agent.radius},
                      {"start", pose_json(agent.start)}});
  }
  nlohmann::json objects = nlohmann::json::array();
  for (const MovableObject& object : model.objects) {
    static constexpr const char* kKinds[] = {"box", "cylinder", "sphere", "capsule"};
    nlohmann::json shape = {{"kind", kKinds[static_cast<int>(object.shape.kind)]}};
    if (object.shape.kind == robots::Shape::Kind::box) {
      shape["size"] = {object.shape.size.x(), object.shape.size.y(), object.shape.size.z()};
    } else {
      shape["radius"] = object.shape.radius;
      if (object.shape.kind != robots::Shape::Kind::sphere) shape["length"] = object.shape.length;
    }
    const core::Pose3& pose = object.pose;
    objects.push_back({{"name", object.name},
                       {"shape", shape},
                       {"mass", object.mass},
                       {"pose", {{"x", pose.x}, {"y", pose.y}, {"z", pose.z}, {"roll", pose.roll}, {"pitch", pose.pitch}, {"yaw", pose.yaw}}}});
  }
  return {{"name", model.name},
          {"bounds", {{"min", point_json(low)}, {"max", point_json(high)}}},
          {"walls", walls},
          {"obstacles", obstacles},
          {"doors", doors},
          {"elevators", elevators},
          {"locations", locations},
          {"social_spaces", spaces},
          {"agents", agents},
          {"objects", objects},
          {"dt", model.dt},
          {"time_limit", model.time_limit}};
}

}  // namespace hrisim::scenario
