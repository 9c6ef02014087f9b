#include "http/api.hpp"

#include <boost/version.hpp>

#include "core/build_info.hpp"
#include "core/random.hpp"
#include "core/text.hpp"
#include "http/episodes_api.hpp"
#include "http/request_contract.hpp"
#include "http/request_helpers.hpp"
#include "http/runs_api.hpp"
#include "http/scenarios_api.hpp"
#include "http/sessions_api.hpp"
#include "http/static_files.hpp"
#include "http/video_jobs.hpp"
#include "render/image_codec.hpp"
#include "render/offscreen_context.hpp"
#include "robots/description.hpp"
#include "storage/store.hpp"

namespace hrisim::http {
namespace {

/// A built-in robot in a few lines, for lists.
nlohmann::json robot_summary(const robots::RobotDescription& robot) {
  nlohmann::json joints = nlohmann::json::array(), sensors = nlohmann::json::array();
  for (const robots::Joint& joint : robot.joints) {
    if (joint.type != robots::JointType::fixed && !joint.mimic) joints.push_back(joint.name);
  }
  for (const robots::Sensor& sensor : robot.sensors) sensors.push_back({{"name", sensor.name}, {"type", sensor.type}});
  nlohmann::json groups = nlohmann::json::object();
  for (const auto& [group, members] : robot.groups) groups[group] = members;
  return {{"name", robot.name},
          {"description", robot.description},
          {"footprint_radius", robot.footprint_radius},
          {"height", robot.height},
          {"mass", robot.mass},
          {"drive", robot.drive ? nlohmann::json{{"wheel_radius", robot.drive->params.wheel_radius},
                                                 {"wheel_separation", robot.drive->params.wheel_separation},
                                                 {"max_linear_speed", robot.drive->params.max_linear_speed},
                                                 {"max_angular_speed", robot.drive->params.max_angular_speed}}
                                : nlohmann::json()},
          {"actuated_joints", joints},
          {"groups", groups},
          {"gripper", robot.gripper ? nlohmann::json(robot.gripper->joint) : nlohmann::json()},
          {"sensors", sensors}};
}

std::string boost_version() {
  return std::to_string(BOOST_VERSION / 100000) + "." + std::to_string(BOOST_VERSION / 100 % 1000) + "." +
         std::to_string(BOOST_VERSION % 100);
}

/// The service's own routes: its health, its version, the API's description and the built-in robots,
/// each a named handler (kServiceRoutes).
class ServiceRoutes {
 public:
  ServiceRoutes(storage::Store* store, nlohmann::json version) : store_(store), version_(std::move(version)) {}

  Response health(const Request& request) const;
  Response version(const Request& request) const;
  Response description_yaml(const Request& request) const;
  Response description_json(const Request& request) const;
  Response robots(const Request& request) const;
  Response robot(const Request& request) const;

 private:
  storage::Store* store_;
  nlohmann::json version_;
};

constexpr NamedRoute<ServiceRoutes> kServiceRoutes[] = {
    {"GET", "/healthz", &ServiceRoutes::health},
    {"GET", "/api/v1/version", &ServiceRoutes::version},
    {"GET", "/api/v1/openapi.yaml", &ServiceRoutes::description_yaml},
    {"GET", "/api/v1/openapi.json", &ServiceRoutes::description_json},
    {"GET", "/api/v1/robots", &ServiceRoutes::robots},
    {"GET", "/api/v1/robots/{name}", &ServiceRoutes::robot},
};

Response ServiceRoutes::health(const Request&) const {
  try {
    store_->ping();
    return Response::json(200, {{"status", "ok"}, {"database", "ok"}});
  } catch (const core::Error& e) {
    return Response::json(503, {{"status", "unavailable"}, {"database", e.what()}});
  }
}

Response ServiceRoutes::version(const Request&) const { return Response::json(200, version_); }

Response ServiceRoutes::description_yaml(const Request&) const {
  return Response{200, "application/yaml", std::string(api_file("openapi.yaml")), {}, {}};
}

Response ServiceRoutes::description_json(const Request&) const {
  return Response{200, "application/json", std::string(api_file("openapi.json")), {}, {}};
}

Response ServiceRoutes::robots(const Request&) const {
  nlohmann::json items = nlohmann::json::array();
  for (const std::string& name : robots::builtin_robot_names()) items.push_back(robot_summary(*robots::builtin_robot(name)));
  return Response::json(200, {{"items", items}});
}

Response ServiceRoutes::robot(const Request& request) const {
  const std::string& name = request.path_params.at("name");
  const auto robot = robots::builtin_robot(name);
  if (!robot) {
    return Response::error(core::Error(core::ErrorCode::not_found, "no robot named '" + name + "' (known: " + core::join(robots::builtin_robot_names()) + ")",
                                       {{"name", name}}));
  }
  return Response::json(200, {{"summary", robot_summary(*robot)}, {"description", robots::builtin_robot_document(name)}});
}

}  // namespace

nlohmann::json version_info() {
  return {{"name", "hrisim"},
          {"version", core::version()},
          {"git_commit", core::git_commit()},
          {"build_type", core::build_type()},
          {"compiler", core::compiler()},
          {"libraries",
           {{"boost", boost_version()},
            {"eigen", core::eigen_version()},
            {"nlohmann_json", core::json_version()},
            {"opencv", render::opencv_version()},
            {"sqlite", storage::Store::sqlite_version()}}},
          {"opengl",
           {{"version", render::probe_gl().version},
            {"renderer", render::probe_gl().renderer},
            {"vendor", render::probe_gl().vendor}}}};
}

std::shared_ptr<const Router> make_api_router(const ApiContext& context) {
  auto router = std::make_shared<Router>();
  router->follow(RequestContract::embedded());
  storage::Store* store = context.store;

  add_routes(*router, std::make_shared<const ServiceRoutes>(store, version_info()), kServiceRoutes);

  auto tickets = std::make_shared<TicketBook>();
  router->set_guard(make_guard(context.access, tickets));

  auto catalogue = std::make_shared<ScenarioCatalogue>(store, context.scenarios_dir, context.scenario_limits, context.scenario_cache_bytes);
  add_scenario_routes(*router, catalogue);
  add_session_routes(*router, catalogue, context.sessions, tickets, store);
  add_run_routes(*router, catalogue, store, context.executor);
  const std::filesystem::path videos_dir =
      context.videos_dir.empty() ? std::filesystem::temp_directory_path() / ("hrisim-videos-" + core::unguessable_id('v')) : context.videos_dir;
  add_episode_routes(*router, catalogue, store, std::make_shared<VideoJobs>(videos_dir));

  auto files = std::make_shared<StaticFiles>(context.web_root);
  router->set_fallback([files](const Request& request) {
    if (request.path == "/api" || request.path.starts_with("/api/")) {
      return Response::error(core::Error(core::ErrorCode::not_found, "no API endpoint at " + request.path,
                                         {{"path", request.path}}));
    }
    return files->serve(request);
  });
  return router;
}

}  // namespace hrisim::http
