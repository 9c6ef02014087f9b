#include "http/scenarios_api.hpp"

#include <algorithm>
#include <map>

#include "core/bounded_json.hpp"
#include "core/json_schema.hpp"
#include "core/text.hpp"
#include "http/request_helpers.hpp"
#include "render/image_codec.hpp"
#include "render/scene_renderer.hpp"
#include "scenario/source.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"
#include "storage/store.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;

/// The body's format: ?format= when given, else the content type (JSON, or YAML: a HuNavSim agents
/// file), else its content.
scenario::SourceFormat body_format(const Request& request) {
  if (const auto named = query_value(request.query, "format")) {
    const auto format = scenario::source_format(*named);
    if (!format) {
      throw core::Error(core::ErrorCode::bad_request, "format '" + *named + "' is not json, imhus, pedsim or hunav", {{"parameter", "format"}});
    }
    return *format;
  }
  const auto type = request.headers.find("content-type");
  const std::string content_type = type == request.headers.end() ? "" : type->second;
  if (content_type.starts_with("application/json")) return scenario::SourceFormat::json;
  if (content_type.starts_with("application/yaml") || content_type.starts_with("application/x-yaml") || content_type.starts_with("text/yaml")) {
    return scenario::SourceFormat::hunav_yaml;
  }
  return scenario::detect_source_format(request.body);
}

[[noreturn]] void bad_upload(const std::string& pointer, const std::string& message) {
  throw core::Error(core::ErrorCode::bad_request, message, {{"pointer", pointer}});
}

/// The files of a bundle: {path: its text, or {"base64": its bytes}}.
std::map<std::string, std::string> upload_files(const json& files) {
  if (!files.is_object()) bad_upload("/files", "files: an object of {path relative to the scenario: text, or {\"base64\": bytes}}");
  if (files.size() > kMaxUploadFiles) bad_upload("/files", "at most " + std::to_string(kMaxUploadFiles) + " files may come with a scenario");
  std::map<std::string, std::string> result;
  for (const auto& [path, content] : files.items()) {
    const std::string pointer = "/files/" + core::pointer_token(path);
    if (const std::string problem = storage::scenario_file_path_problem(path); !problem.empty()) bad_upload(pointer, problem);
    if (content.is_string()) {
      result.emplace(path, content.get<std::string>());
    } else if (content.is_object() && content.size() == 1 && content.contains("base64") && content["base64"].is_string()) {
      auto bytes = core::base64_decode(content["base64"].get<std::string>());
      if (!bytes) bad_upload(pointer + "/base64", "not base64 (RFC 4648, padded, without line breaks)");
      result.emplace(path, std::move(*bytes));
    } else {
      bad_upload(pointer, "a file is its text, or {\"base64\": its bytes}");
    }
  }
  if (const auto nested = nested_upload_file(result)) {
    bad_upload("/files/" + core::pointer_token(nested->inside), "'" + nested->file + "' cannot be a folder holding '" + nested->inside +
                                                                    "': it is a file of the bundle too (a path names a file or a folder, not both)");
  }
  return result;
}

/// What the body uploads: a scenario alone (JSON or XML, see body_format), or a bundle — a JSON
/// object {"scenario": the native document or any format's text, "files": …} — of a scenario and the
/// files it names.
Upload upload_of(const Request& request) {
  const scenario::SourceFormat format = body_format(request);
  // A bundle whatever ?format= says: it then names the format of the bundle's scenario.
  const std::size_t first = request.body.find_first_not_of(" \t\r\n");
  const bool object = first != std::string::npos && request.body[first] == '{';
  if (format != scenario::SourceFormat::json && !object) return {request.body, format, {}};
  core::check_json_nesting(request.body);
  // Not JSON: the compiler says where.
  const json body = json::parse(request.body, nullptr, false);
  if (!body.is_object() || !body.contains("files")) return {request.body, format, {}};
  for (const auto& [key, unused] : body.items()) {
    if (key != "scenario" && key != "files") bad_upload("/" + core::pointer_token(key), "a bundle has \"scenario\" and \"files\" only, not '" + key + "'");
  }
  if (!body.contains("scenario")) bad_upload("/scenario", "a bundle's scenario is missing");
  Upload upload{"", scenario::SourceFormat::json, upload_files(body["files"])};
  const json& scenario = body["scenario"];
  if (scenario.is_object()) {
    upload.text = core::json_text(scenario, 2);
  } else if (scenario.is_string()) {
    upload.text = scenario.get<std::string>();
    const auto named = query_value(request.query, "format");
    upload.format = named ? body_format(request) : scenario::detect_source_format(upload.text);
  } else {
    bad_upload("/scenario", "a bundle's scenario is the native document (an object) or the text of a scenario file");
  }
  return upload;
}

json issues(const std::vector<scenario::SourceIssue>& list) {
  json result = json::array();
  for (const auto& issue : list) result.push_back(issue.to_json());
  return result;
}

/// The scenarios routes over REST, each a named handler (kScenarioRoutes). Everything that may compile
/// a scenario (an upload not in the cache, a new one) runs on the worker pool: compiling a large map
/// or crowd must not hold an I/O thread.
class ScenarioRoutes {
 public:
  explicit ScenarioRoutes(std::shared_ptr<ScenarioCatalogue> catalogue) : catalogue_(std::move(catalogue)) {}

  Response list(const Request& request) const;
  Response document(const Request& request) const;
  Response world(const Request& request) const;
  Response thumbnail(const Request& request) const;
  Response validate(const Request& request) const;
  Response upload(const Request& request) const;
  Response remove(const Request& request) const;

 private:
  std::shared_ptr<ScenarioCatalogue> catalogue_;
};

constexpr NamedRoute<ScenarioRoutes> kScenarioRoutes[] = {
    {"GET", "/api/v1/scenarios", &ScenarioRoutes::list},
    {"GET", "/api/v1/scenarios/{id}", &ScenarioRoutes::document},
    {"GET", "/api/v1/scenarios/{id}/world", &ScenarioRoutes::world},
    {"GET", "/api/v1/scenarios/{id}/thumbnail", &ScenarioRoutes::thumbnail},
    {"POST", "/api/v1/scenarios/validate", &ScenarioRoutes::validate},
    {"POST", "/api/v1/scenarios", &ScenarioRoutes::upload},
    {"DELETE", "/api/v1/scenarios/{id}", &ScenarioRoutes::remove},
};

Response ScenarioRoutes::list(const Request& request) const {
  const int limit = static_cast<int>(integer_query(request, "limit", 1, kMaxPageSize, kDefaultPageSize));
  const std::string cursor = query_value(request.query, "cursor").value_or("");
  return Response::later([catalogue = catalogue_, limit, cursor, caller = request.caller] {
    const auto ids = catalogue->page(cursor, limit + 1, caller);
    json items = json::array();
    for (std::size_t i = 0; i < ids.size() && static_cast<int>(i) < limit; ++i) {
      if (json summary = catalogue->summary(ids[i]); !summary.is_null()) items.push_back(std::move(summary));
    }
    json page{{"items", items}, {"next_cursor", nullptr}};
    if (static_cast<int>(ids.size()) > limit) page["next_cursor"] = ids[static_cast<std::size_t>(limit) - 1];
    return Response::json(200, page);
  });
}

Response ScenarioRoutes::document(const Request& request) const {
  return Response::later([catalogue = catalogue_, id = request.path_params.at("id"), caller = request.caller] {
    const auto entry = catalogue->find(id, caller);
    if (!entry) throw core::Error(core::ErrorCode::not_found, "no scenario '" + id + "'", {{"id", id}});
    return Response::json(200, entry->source.document);
  });
}

Response ScenarioRoutes::world(const Request& request) const {
  return Response::later([catalogue = catalogue_, id = request.path_params.at("id"), caller = request.caller] {
    const auto entry = catalogue->find(id, caller);
    if (!entry) throw core::Error(core::ErrorCode::not_found, "no scenario '" + id + "'", {{"id", id}});
    if (!entry->source.model) throw core::Error(core::ErrorCode::conflict, "scenario '" + id + "' does not load", {{"id", id}});
    nlohmann::json world = scenario::world_geometry(*entry->source.model);
    world["id"] = id;
    return Response::json(200, world);
  });
}

Response ScenarioRoutes::thumbnail(const Request& request) const {
  const std::string& id = request.path_params.at("id");
  const auto entry = catalogue_->find(id, request.caller);
  if (!entry) throw core::Error(core::ErrorCode::not_found, "no scenario '" + id + "'", {{"id", id}});
  if (!entry->source.model) throw core::Error(core::ErrorCode::conflict, "scenario '" + id + "' does not load", {{"id", id}});
  // A size given alone keeps the default's 4:3.
  const auto asked_width = static_cast<int>(integer_query(request, "width", 16, kMaxThumbnailSize, 0));
  const auto asked_height = static_cast<int>(integer_query(request, "height", 16, kMaxThumbnailSize, 0));
  const int width = asked_width ? asked_width : asked_height ? std::clamp(asked_height * kThumbnailWidth / kThumbnailHeight, 16, kMaxThumbnailSize) : kThumbnailWidth;
  const int height = asked_height ? asked_height : asked_width ? std::clamp(asked_width * kThumbnailHeight / kThumbnailWidth, 16, kMaxThumbnailSize) : kThumbnailHeight;
  // The scenario at its start (seed 0) from above, drawn on the worker pool.
  return Response::later([model = entry->source.model, width, height] {
    const sim::Session session(model, 0);
    const sim::CameraInfo camera = sim::camera_of(session, "overview", width, height);
    Response image{200, "image/png", render::encode_png(render::render_on_this_thread(sim::scene_for(session, camera), camera.camera).colour), {}, {}};
    image.headers.emplace_back("Cache-Control", "max-age=3600");
    return image;
  });
}

Response ScenarioRoutes::validate(const Request& request) const {
  return Response::later([catalogue = catalogue_, request] {
    const auto compiled = catalogue->check(upload_of(request));
    json reply{{"valid", compiled.errors.empty()},
               {"format", scenario::to_string(compiled.format)},
               {"errors", issues(compiled.errors)},
               {"warnings", issues(compiled.warnings)}};
    if (compiled.model) reply["summary"] = scenario::summarize(*compiled.model);
    return Response::json(200, reply);
  });
}

Response ScenarioRoutes::upload(const Request& request) const {
  return Response::later([catalogue = catalogue_, request] {
    scenario::CompiledSource compiled;
    const auto added = catalogue->add(upload_of(request), request.caller.owner, compiled);
    if (added.id.empty()) {
      throw core::Error(core::ErrorCode::bad_request, "the scenario is not valid: nothing was stored",
                        {{"format", scenario::to_string(compiled.format)}, {"errors", issues(compiled.errors)}});
    }
    const json warnings = issues(compiled.warnings);
    // The same content again: the upload it duplicates, 200 rather than 201.
    Response response = Response::json(added.existed ? 200 : 201,
                                       {{"summary", catalogue->summary(added.id)}, {"warnings", warnings}, {"existed", added.existed}});
    response.headers.emplace_back("Location", "/api/v1/scenarios/" + added.id);
    return response;
  });
}

Response ScenarioRoutes::remove(const Request& request) const {
  const std::string& id = request.path_params.at("id");
  return Response::json(200, {{"id", id}, {"outcome", catalogue_->remove(id, request.caller) ? "deleted" : "unlisted"}});
}

}  // namespace

void add_scenario_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue) {
  add_routes(router, std::make_shared<const ScenarioRoutes>(std::move(catalogue)), kScenarioRoutes);
}

}  // namespace hrisim::http
