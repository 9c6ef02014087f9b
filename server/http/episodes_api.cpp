#include "http/episodes_api.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "episode/episode.hpp"
#include "http/range_header.hpp"
#include "http/request_helpers.hpp"
#include "http/session_views.hpp"
#include "http/video_jobs.hpp"
#include "metrics/definitions.hpp"
#include "runs/episode.hpp"
#include "runs/report.hpp"
#include "runs/video.hpp"
#include "sim/camera_scene.hpp"
#include "storage/store.hpp"

namespace hrisim::http {

using nlohmann::json;

storage::EpisodeRecord find_episode(storage::Store& store, const std::string& id, const Caller& caller, const std::string& pointer) {
  auto episode = store.episode(id);
  const auto run = episode && episode->run_id ? store.run(*episode->run_id) : std::nullopt;
  if (!episode || !visible_to(caller, run ? run->owner : "")) {
    json details = {{"id", id}};
    if (!pointer.empty()) details["pointer"] = pointer;
    throw core::Error(core::ErrorCode::not_found, "no episode '" + id + "'", details);
  }
  return std::move(*episode);
}

json episode_json(const storage::EpisodeRecord& episode) {
  json metrics = json::object();
  for (const storage::MetricValue& metric : episode.metrics) metrics[metric.key] = runs::metric_json(metric);
  return {{"id", episode.id},
          {"run_id", episode.run_id ? json(*episode.run_id) : json()},
          {"scenario", episode.scenario_id},
          {"seed", episode.seed},
          {"controller", episode.controller},
          {"status", episode.status},
          {"termination", episode.termination_reason},
          {"ticks", episode.ticks},
          {"sim_time", episode.sim_time},
          {"created_at", episode.created_at},
          {"state_hash", episode.state_hash.empty() ? json() : json(episode.state_hash)},
          {"metrics", metrics}};
}

EpisodeReplay replay_of_episode(storage::Store& store, ScenarioCatalogue& catalogue, const std::string& id, const Caller& caller,
                                const std::string& pointer) {
  EpisodeReplay replay;
  replay.episode = find_episode(store, id, caller, pointer);
  const auto run = replay.episode.run_id ? store.run(*replay.episode.run_id) : std::nullopt;
  const auto entry = catalogue.find(replay.episode.scenario_id);
  if (!entry || !entry->source.model) {
    json details = {{"id", id}};
    if (!pointer.empty()) details["pointer"] = pointer;
    throw core::Error(core::ErrorCode::conflict, "episode " + id + "'s scenario '" + replay.episode.scenario_id + "' no longer loads", details);
  }
  replay.config = run ? run->config : json::object();
  replay.request = runs::replay_request(entry->source.document, catalogue.options(*entry).load, replay.config, replay.episode.seed);
  replay.spec = runs::make_run_spec(replay.request);
  replay.scenario_sha256 = entry->content_sha256();
  return replay;
}

namespace {

/// The job `id` as `caller` may see it: one filming another owner's episode is absent (404).
std::string visible_video(const VideoJobs& videos, storage::Store& store, const std::string& id, const Caller& caller) {
  const auto episode = videos.episode_of(id);
  if (!episode) throw core::Error(core::ErrorCode::not_found, "no video '" + id + "'", {{"id", id}});
  try {
    find_episode(store, *episode, caller);
  } catch (const core::Error&) {
    throw core::Error(core::ErrorCode::not_found, "no video '" + id + "'", {{"id", id}});
  }
  return id;
}

/// How a video is filmed, from a POST body the request contract has checked.
VideoRequest video_request(const json& body) {
  VideoRequest request;
  request.options.camera = body.value("camera", request.options.camera);
  request.options.fps = body.value("fps", runs::kDefaultVideoFps);
  request.options.width = body.value("width", 0);
  request.options.height = body.value("height", 0);
  request.format = body.value("format", "mp4");
  return request;
}

/// The video's bytes, or only the one range a Range header asks for (206; 416, without a body, when it
/// lies outside; RFC 9110: read_range_header), read from the file as asked: a player seeking in a long
/// video does not read it all each time.
Response file_answer(const VideoJobs::File& file, const Request& request) {
  std::error_code missing;
  const std::uint64_t size = std::filesystem::file_size(file.path, missing);
  std::ifstream in(file.path, std::ios::binary);
  if (missing || !in) throw core::Error(core::ErrorCode::not_found, "the video's file is gone");
  const auto header = request.headers.find("range");
  const AskedRange asked = header == request.headers.end() ? AskedRange{} : read_range_header(header->second, size);
  if (asked.kind == AskedRange::Kind::unsatisfiable) return Response{416, "", "", {{"Content-Range", "bytes */" + std::to_string(size)}}, {}};
  const bool part = asked.kind == AskedRange::Kind::part;
  const std::uint64_t first = part ? asked.first : 0, length = part ? asked.last - asked.first + 1 : size;
  std::string bytes(length, '\0');
  in.seekg(static_cast<std::streamoff>(first));
  in.read(bytes.data(), static_cast<std::streamsize>(length));
  if (!in) throw core::Error(core::ErrorCode::not_found, "the video's file is gone");
  Response response = download(std::move(bytes), file.content_type, file.name);
  response.headers.emplace_back("Accept-Ranges", "bytes");
  if (part) {
    response.status = 206;
    response.headers.emplace_back("Content-Range", "bytes " + std::to_string(asked.first) + "-" + std::to_string(asked.last) + "/" + std::to_string(size));
  }
  return response;
}

/// The stored episodes' routes and their videos' over REST, each a named handler (kEpisodeRoutes).
/// Bodies reach them checked against api/openapi.yaml (Router::follow).
class EpisodeRoutes {
 public:
  EpisodeRoutes(std::shared_ptr<ScenarioCatalogue> catalogue, storage::Store* store, std::shared_ptr<VideoJobs> videos)
      : catalogue_(std::move(catalogue)), store_(store), videos_(std::move(videos)) {}

  Response episode(const Request& request) const;
  Response series(const Request& request) const;
  Response trajectory(const Request& request) const;
  Response film(const Request& request) const;
  Response cameras(const Request& request) const;
  Response video(const Request& request) const;
  Response video_file(const Request& request) const;
  Response delete_video(const Request& request) const;

 private:
  std::shared_ptr<ScenarioCatalogue> catalogue_;
  storage::Store* store_;
  std::shared_ptr<VideoJobs> videos_;
};

constexpr NamedRoute<EpisodeRoutes> kEpisodeRoutes[] = {
    {"GET", "/api/v1/episodes/{id}", &EpisodeRoutes::episode},
    {"GET", "/api/v1/episodes/{id}/series", &EpisodeRoutes::series},
    {"GET", "/api/v1/episodes/{id}/trajectory", &EpisodeRoutes::trajectory},
    {"POST", "/api/v1/episodes/{id}/videos", &EpisodeRoutes::film},
    {"GET", "/api/v1/episodes/{id}/cameras", &EpisodeRoutes::cameras},
    {"GET", "/api/v1/videos/{id}", &EpisodeRoutes::video},
    {"GET", "/api/v1/videos/{id}/file", &EpisodeRoutes::video_file},
    {"DELETE", "/api/v1/videos/{id}", &EpisodeRoutes::delete_video},
};

Response EpisodeRoutes::episode(const Request& request) const {
  const storage::EpisodeRecord episode = find_episode(*store_, request.path_params.at("id"), request.caller);
  json reply = episode_json(episode);
  json events = json::array();
  for (const storage::EventRecord& event : episode.events) {
    events.push_back({{"tick", event.tick}, {"time", event.time}, {"kind", event.kind}, {"subject", event.subject}, {"data", event.data}});
  }
  reply["events"] = events;
  // METRICS.md's step_durations: how long each choreography step took, from its step_finished event.
  json step_durations = json::array();
  for (const storage::EventRecord& event : episode.events) {
    if (event.kind == sim::events::StepFinished::kind) step_durations.push_back({{"step", event.subject}, {"duration", event.data.value("duration", 0.0)}});
  }
  reply["step_durations"] = step_durations;
  json null_reasons = json::object();
  for (const storage::MetricValue& metric : episode.metrics) {
    if (metric.null_reason) null_reasons[metric.key] = *metric.null_reason;
  }
  reply["null_reasons"] = null_reasons;
  return Response::json(200, reply);
}

Response EpisodeRoutes::series(const Request& request) const {
  const std::string format = json_or_csv_format(request);
  const std::string name = query_value(request.query, "name").value_or("");
  const auto& known = metrics::series_definitions();
  const auto definition = std::find_if(known.begin(), known.end(), [&](const metrics::SeriesDefinition& d) { return d.name == name; });
  if (!name.empty() && definition == known.end()) {
    throw core::Error(core::ErrorCode::bad_request, "name: no series '" + name + "' (GET /api/v1/metrics lists them)", {{"parameter", "name"}});
  }
  if (format == "csv" && name.empty()) throw core::Error(core::ErrorCode::bad_request, "format=csv needs a series name", {{"parameter", "name"}});
  const storage::EpisodeRecord episode = find_episode(*store_, request.path_params.at("id"), request.caller);
  const double dt = episode.ticks > 0 ? episode.sim_time / static_cast<double>(episode.ticks) : 0.0;
  const std::vector<storage::SeriesRecord> stored = store_->series(episode.id, name);
  if (format == "csv") {
    std::ostringstream csv;
    csv.precision(17);
    csv << "tick,time," << name << '\n';
    for (const storage::SeriesRecord& series : stored) {
      for (std::size_t i = 0; i < series.values.size(); ++i) {
        const std::int64_t tick = series.first_tick + static_cast<std::int64_t>(i) * series.stride;
        csv << tick << ',' << static_cast<double>(tick) * dt << ',';
        if (series.values[i]) csv << *series.values[i];
        csv << '\n';
      }
    }
    return download(csv.str(), kCsvContentType, episode.id + "-" + name + ".csv");
  }
  json items = json::array();
  for (const storage::SeriesRecord& series : stored) {
    json ticks = json::array(), values = json::array();
    for (std::size_t i = 0; i < series.values.size(); ++i) {
      ticks.push_back(series.first_tick + static_cast<std::int64_t>(i) * series.stride);
      values.push_back(series.values[i] ? json(*series.values[i]) : json());
    }
    const auto unit = std::find_if(known.begin(), known.end(), [&](const metrics::SeriesDefinition& d) { return d.name == series.name; });
    items.push_back({{"name", series.name},
                     {"unit", unit == known.end() ? "" : std::string(unit->unit)},
                     {"dt", dt * static_cast<double>(series.stride)},
                     {"ticks", ticks},
                     {"values", values}});
  }
  return Response::json(200, {{"episode", episode.id}, {"items", items}});
}

Response EpisodeRoutes::trajectory(const Request& request) const {
  const std::string format = json_or_csv_format(request);
  const storage::EpisodeRecord episode = find_episode(*store_, request.path_params.at("id"), request.caller);
  const double dt = episode.ticks > 0 ? episode.sim_time / static_cast<double>(episode.ticks) : 0.0;
  if (format == "csv") {
    std::ostringstream csv;
    csv.precision(17);
    csv << "agent,tick,time,x,y,theta\n";
    for (const storage::TrajectorySample& s : episode.trajectory) {
      csv << s.agent_id << ',' << s.tick << ',' << static_cast<double>(s.tick) * dt << ',' << s.x << ',' << s.y << ',' << s.theta << '\n';
    }
    return download(csv.str(), kCsvContentType, episode.id + ".csv");
  }
  json agents = json::object();
  for (const storage::TrajectorySample& s : episode.trajectory) {
    agents[s.agent_id].push_back({{"tick", s.tick}, {"time", static_cast<double>(s.tick) * dt}, {"x", s.x}, {"y", s.y}, {"theta", s.theta}});
  }
  return Response::json(200, {{"episode", episode.id}, {"rate", runs::kTrajectoryRate}, {"agents", agents}});
}

Response EpisodeRoutes::film(const Request& request) const {
  VideoRequest asked = video_request(request.checked_body);
  // Compiling the scenario and finding the camera's size build a world: work for the pool.
  return Response::later([catalogue = catalogue_, store = store_, videos = videos_, asked = std::move(asked), id = request.path_params.at("id"),
                          caller = request.caller]() mutable {
    EpisodeReplay replay = replay_of_episode(*store, *catalogue, id, caller);
    asked.size = runs::video_size(replay.spec, replay.episode.seed, asked.options);
    if (asked.size.width > kMaxVideoSide || asked.size.height > kMaxVideoSide) {
      throw core::Error(core::ErrorCode::bad_request,
                        "the camera's frames are " + std::to_string(asked.size.width) + " × " + std::to_string(asked.size.height) +
                            ": give a width or height that keeps both at most " + std::to_string(kMaxVideoSide),
                        {{"pointer", "/width"}});
    }
    asked.episode = std::move(replay.episode);
    asked.spec = std::move(replay.spec);
    bool created = false;
    const json job = videos->submit(std::move(asked), created);
    Response response = Response::json(created ? 202 : 200, job);
    response.headers.emplace_back("Location", "/api/v1/videos/" + job["id"].get<std::string>());
    return response;
  });
}

Response EpisodeRoutes::cameras(const Request& request) const {
  return Response::later([catalogue = catalogue_, store = store_, id = request.path_params.at("id"), caller = request.caller] {
    const EpisodeReplay replay = replay_of_episode(*store, *catalogue, id, caller);
    const episode::Episode first(replay.spec.model, replay.episode.seed);
    json cameras = json::array();
    for (const sim::CameraInfo& info : sim::cameras_of(first.session())) cameras.push_back(camera_json(info));
    return Response::json(200, {{"episode", id}, {"cameras", cameras}});
  });
}

Response EpisodeRoutes::video(const Request& request) const {
  const std::string id = visible_video(*videos_, *store_, request.path_params.at("id"), request.caller);
  const auto status = videos_->status(id);
  if (!status) throw core::Error(core::ErrorCode::not_found, "no video '" + id + "'", {{"id", id}});
  return Response::json(200, *status);
}

Response EpisodeRoutes::video_file(const Request& request) const {
  const std::string id = visible_video(*videos_, *store_, request.path_params.at("id"), request.caller);
  return file_answer(videos_->file(id), request);
}

Response EpisodeRoutes::delete_video(const Request& request) const {
  const std::string id = visible_video(*videos_, *store_, request.path_params.at("id"), request.caller);
  if (!videos_->remove(id)) throw core::Error(core::ErrorCode::not_found, "no video '" + id + "'", {{"id", id}});
  return Response{204, "application/json", "", {}, {}};
}

}  // namespace

void add_episode_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, storage::Store* store, std::shared_ptr<VideoJobs> videos) {
  add_routes(router, std::make_shared<const EpisodeRoutes>(std::move(catalogue), store, std::move(videos)), kEpisodeRoutes);
}

}  // namespace hrisim::http
