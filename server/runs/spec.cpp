#include "runs/spec.hpp"

#include <algorithm>
#include <set>

#include "core/build_info.hpp"
#include "core/error.hpp"
#include "metrics/gates.hpp"
#include "scenario/model.hpp"

namespace hrisim::runs {

nlohmann::json scenario_controller(const nlohmann::json& document) {
  const auto robots = document.find("robots");
  if (robots == document.end() || !robots->is_array() || robots->empty() || !(*robots)[0].is_object()) return nullptr;
  const auto controller = (*robots)[0].find("controller");
  return controller == (*robots)[0].end() ? nlohmann::json() : *controller;
}

nlohmann::json effective_controller(const nlohmann::json& document, const nlohmann::json& requested) {
  if (!requested.is_object()) return requested;  // with_controller says what is wrong with it
  const nlohmann::json own = scenario_controller(document);
  nlohmann::json effective = own.is_object() ? own : nlohmann::json::object();
  for (const auto& [key, value] : requested.items()) {
    if (value.is_null()) {
      effective.erase(key);
      continue;
    }
    // Another place to go keeps the scenario's arrival radius unless it gives its own.
    const bool keeps_radius = key == "goal" && value.is_object() && !value.contains("radius") && effective.contains("goal") &&
                              effective["goal"].is_object() && effective["goal"].contains("radius");
    const nlohmann::json radius = keeps_radius ? effective["goal"]["radius"] : nlohmann::json();
    effective[key] = value;
    if (keeps_radius) effective["goal"]["radius"] = radius;
  }
  // What the scenario gave another type and the new type does not take is left behind, unless asked for
  // (then the loader says why it cannot be).
  const std::string type = effective.contains("type") && effective["type"].is_string() ? effective["type"].get<std::string>() : "";
  const auto keep_only_if_asked = [&](const char* key) {
    if (!requested.contains(key)) effective.erase(key);
  };
  if (type == "idle" || type == "teleop") keep_only_if_asked("goal");
  if (type != "search") {
    keep_only_if_asked("person");
    keep_only_if_asked("strategy");
  }
  return effective;
}

scenario::LoadResult with_controller(nlohmann::json document, const nlohmann::json& controller, const scenario::LoadOptions& load,
                                     nlohmann::json& errors) {
  const auto problem = [&](std::string pointer, std::string message) {
    errors.push_back({{"pointer", std::move(pointer)}, {"message", std::move(message)}});
  };
  if (!document.contains("robots") || !document["robots"].is_array() || document["robots"].empty()) {
    problem("/controller", "the scenario has no robot to control");
    return {};
  }
  if (!controller.is_object() || !controller.contains("type") || !controller["type"].is_string()) {
    problem("/controller", "a controller is an object with a \"type\" (idle, goal, social, dwa, orca, social_force or teleop)");
    return {};
  }
  document["robots"][0]["controller"] = controller;
  scenario::LoadResult loaded = scenario::load_scenario(document, load);
  // Problems in the replaced controller are the caller's; the scenario itself was valid before.
  const std::string controller_pointer = "/robots/0/controller";
  for (const core::ValidationError& error : loaded.errors) {
    if (error.pointer.starts_with(controller_pointer)) {
      problem("/controller" + error.pointer.substr(controller_pointer.size()), error.message);
    } else {
      problem("/scenario" + error.pointer, error.message);
    }
  }
  return loaded;
}

RunRequest replay_request(const nlohmann::json& document, const scenario::LoadOptions& load, const nlohmann::json& config, std::uint64_t seed) {
  RunRequest request;
  request.document = document;
  request.load = load;
  request.seeds = {seed};
  // The controller the run's robot had, whole: runs stored before effective controllers were kept
  // replaced the scenario's controller with the one asked for.
  for (const char* key : {"effective_controller", "controller"}) {
    if (config.contains(key) && !config[key].is_null()) {
      request.controller = config[key];
      request.controller_whole = true;
      break;
    }
  }
  if (config.contains("max_time") && config["max_time"].is_number()) request.max_time = config["max_time"].get<double>();
  for (const nlohmann::json& asked : config.value("requests", nlohmann::json::array())) {
    request.requests.emplace_back(asked["time"].get<double>(), asked.value("routine", asked.value("task", "")));
  }
  return request;
}

void throw_if_problems(const nlohmann::json& errors) {
  if (errors.empty()) return;
  const std::string first = errors[0]["message"];
  throw core::Error(core::ErrorCode::bad_request, errors.size() == 1 ? first : first + " (and " + std::to_string(errors.size() - 1) + " more)",
                    {{"errors", errors}, {"pointer", errors[0]["pointer"]}});
}

RunSpec make_run_spec(const RunRequest& request, const nlohmann::json& found) {
  using nlohmann::json;
  json errors = found;
  // A field the reader found wrong (or a part of it) is not reported again from what it left.
  const auto reported = [&found](const std::string& pointer) {
    return std::any_of(found.begin(), found.end(), [&](const json& error) {
      const std::string other = error.value("pointer", "");
      return other == pointer || other.starts_with(pointer + "/") || pointer.starts_with(other + "/");
    });
  };
  const auto problem = [&](std::string pointer, std::string message) {
    if (reported(pointer)) return;
    errors.push_back({{"pointer", std::move(pointer)}, {"message", std::move(message)}});
  };

  if (request.seeds.empty()) problem("/seeds", "a run needs at least one seed");
  if (request.seeds.size() > kMaxSeedsPerRun) problem("/seeds", "at most " + std::to_string(kMaxSeedsPerRun) + " seeds per run");
  if (std::set<std::uint64_t>(request.seeds.begin(), request.seeds.end()).size() != request.seeds.size()) {
    problem("/seeds", "every seed may appear only once");
  }
  if (request.max_time && !(*request.max_time > 0.0)) problem("/max_time", "max_time must be a number of seconds > 0");
  for (std::size_t i = 0; i < request.gates.size(); ++i) {
    try {
      metrics::parse_gate(request.gates[i]);
    } catch (const core::Error& e) {
      problem("/gates/" + std::to_string(i), e.what());
    }
  }

  std::string controller = "scenario";
  scenario::LoadResult loaded;
  json effective = scenario_controller(request.document);
  if (request.controller) {
    effective = request.controller_whole ? *request.controller : effective_controller(request.document, *request.controller);
    loaded = with_controller(request.document, effective, request.load, errors);
    if (effective.is_object() && effective.contains("type") && effective["type"].is_string()) controller = effective["type"];
  } else {
    loaded = scenario::load_scenario(request.document, request.load);
    for (const core::ValidationError& error : loaded.errors) problem("/scenario" + error.pointer, error.message);
  }
  if (loaded.model && request.max_time && *request.max_time > 0.0) {
    try {
      scenario::check_episode_ticks(*request.max_time, loaded.model->dt, request.load.limits.max_episode_ticks, "max_time");
    } catch (const core::Error& e) {
      problem("/max_time", e.what());
    }
  }
  for (std::size_t i = 0; loaded.model && i < request.requests.size(); ++i) {
    if (loaded.model->find_routine(request.requests[i].second) < 0) {
      problem("/requests/" + std::to_string(i), "the scenario has no task '" + request.requests[i].second + "'");
    }
  }
  if (!request.requests.empty() && loaded.model &&
      std::none_of(loaded.model->agents.begin(), loaded.model->agents.end(),
                   [](const scenario::AgentDef& agent) { return agent.kind == scenario::AgentKind::robot; })) {
    problem("/requests", "the scenario has no robot to make requests");
  }
  throw_if_problems(errors);

  RunSpec spec;
  spec.scenario_id = request.scenario_id;
  spec.model = loaded.model;
  spec.seeds = request.seeds;
  spec.controller = controller;
  spec.max_time = request.max_time;
  spec.requests = request.requests;
  spec.baseline_without_robot = request.baseline_without_robot;
  json requests = json::array();
  for (const auto& [time, routine] : request.requests) requests.push_back({{"time", time}, {"routine", routine}});
  spec.config = {{"scenario", request.scenario_id},
                 {"seeds", request.seeds},
                 {"gates", request.gates},
                 {"controller", request.controller ? *request.controller : json()},
                 {"effective_controller", effective},
                 {"max_time", request.max_time ? json(*request.max_time) : json()},
                 {"requests", requests},
                 {"scenario_sha256", request.scenario_sha256},
                 {"baseline_without_robot", request.baseline_without_robot},
                 {"hrisim_version", core::version()},
                 {"git_commit", core::git_commit()}};
  return spec;
}

}  // namespace hrisim::runs
