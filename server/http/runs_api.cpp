#include "http/runs_api.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <cmath>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/text.hpp"
#include "http/episodes_api.hpp"
#include "http/request_helpers.hpp"
#include "http/session_limits.hpp"
#include "metrics/definitions.hpp"
#include "metrics/gates.hpp"
#include "runs/labels.hpp"
#include "runs/executor.hpp"
#include "runs/merge.hpp"
#include "runs/report.hpp"
#include "runs/spec.hpp"
#include "storage/store.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;

/// Most runs one list request returns.
constexpr int kMaxRunsPerPage = 100;
/// Most runs one comparison takes.
constexpr std::size_t kMaxComparedRuns = 10;

/// The problems found in a run request so far: {pointer, message} each (runs::throw_if_problems).
class Problems {
 public:
  void add(const std::string& pointer, const std::string& message) { list_.push_back({{"pointer", pointer}, {"message", message}}); }
  json& list() { return list_; }

 private:
  json list_ = json::array();
};

struct RunLabels {
  std::string name;
  std::vector<std::string> tags;
  std::string notes;
};

/// The name, tags and notes the body gives (the others kept as `labels` has them), problems noted:
/// the contract has checked their types and counts; their sizes are in bytes (runs::label_problems).
void read_labels(const json& body, RunLabels& labels, Problems& problems) {
  labels.name = body.value("name", labels.name);
  labels.notes = body.value("notes", labels.notes);
  labels.tags = body.value("tags", labels.tags);
  for (const json& problem : runs::label_problems(labels.name, labels.tags, labels.notes)) problems.add(problem["pointer"], problem["message"]);
}

/// The seeds a run request lists, or `count` of them from `first_seed`.
std::vector<std::uint64_t> seeds_of(const json& body, Problems& problems) {
  if (body.contains("seeds")) return body["seeds"].get<std::vector<std::uint64_t>>();
  const std::int64_t count = body["count"], first = body.value("first_seed", std::int64_t{0});
  if (first > kMaxSeed - count + 1) {
    problems.add("/first_seed", "first_seed + count - 1 must be at most " + std::to_string(kMaxSeed));
    return {};
  }
  std::vector<std::uint64_t> seeds;
  for (std::int64_t i = 0; i < count; ++i) seeds.push_back(static_cast<std::uint64_t>(first + i));
  return seeds;
}

/// The run the body asks for, every problem of its fields in `problems` (the scenario must be there).
runs::RunRequest run_request(const json& body, ScenarioCatalogue& catalogue, const Caller& caller, Problems& problems) {
  const std::string id = body["scenario"];
  const auto entry = catalogue.find(id, caller);
  if (!entry || !entry->source.model) {
    throw core::Error(core::ErrorCode::not_found, "no scenario '" + id + "'", {{"pointer", "/scenario"}, {"id", id}});
  }
  runs::RunRequest request;
  request.scenario_id = id;
  request.document = entry->source.document;
  request.load = catalogue.options(*entry).load;
  request.scenario_sha256 = entry->content_sha256();
  request.seeds = seeds_of(body, problems);
  if (body.contains("controller") && !body["controller"].is_null()) request.controller = body["controller"];
  request.baseline_without_robot = body.value("baseline_without_robot", false);
  if (body.contains("max_time")) request.max_time = body["max_time"].get<double>();
  request.gates = body.value("gates", std::vector<std::string>{});
  const json requests = body.value("requests", json::array());
  for (std::size_t i = 0; i < requests.size(); ++i) {
    // "task" is the routine's former name, still accepted for one version.
    const json& item = requests[i];
    if (item.contains("routine") == item.contains("task")) {
      problems.add("/requests/" + std::to_string(i), "a request is {\"time\": seconds >= 0, \"routine\": name}");
      continue;
    }
    request.requests.emplace_back(item["time"].get<double>(), item.value("routine", item.value("task", "")));
  }
  return request;
}

/// The stored scenario a run of catalogue entry `id` refers to: an upload is stored already; a bundled
/// scenario is stored as a snapshot named by its content, so the run keeps exactly what it ran.
std::string stored_scenario_id(storage::Store& store, const std::string& id, const ScenarioCatalogue::Entry& entry,
                               const std::string& sha256) {
  if (entry.origin == "uploaded") return id;
  const std::string snapshot = "b" + sha256.substr(0, 32);
  store.put_scenario_if_missing({snapshot, entry.source.model->name, "json", core::json_text(entry.source.document, 2), "", "", "", "", {}});
  return snapshot;
}

/// The run as `caller` may see it: another owner's is absent (404), as an unknown one.
storage::RunRecord find_run(storage::Store& store, const std::string& id, const Caller& caller) {
  auto run = store.run(id);
  if (!run || !visible_to(caller, run->owner)) throw core::Error(core::ErrorCode::not_found, "no run '" + id + "'", {{"id", id}});
  return *run;
}

json report_of(storage::Store& store, runs::Executor& executor, const storage::RunRecord& run) {
  return runs::run_report(run, store.episodes_of_run(run.id), executor.live(run.id));
}

/// A run's episodes as CSV: one row each, its facts then every metric (empty for no value).
std::string episodes_csv(const std::vector<storage::EpisodeRecord>& episodes) {
  std::ostringstream csv;
  csv.precision(17);
  csv << "episode,seed,controller,status,termination,ticks,sim_time";
  for (const metrics::Definition& definition : metrics::definitions()) csv << ',' << definition.key;
  csv << '\n';
  for (const storage::EpisodeRecord& episode : episodes) {
    csv << episode.id << ',' << episode.seed << ',' << episode.controller << ',' << episode.status << ',' << episode.termination_reason << ','
        << episode.ticks << ',' << episode.sim_time;
    for (const metrics::Definition& definition : metrics::definitions()) {
      csv << ',';
      const auto found = std::find_if(episode.metrics.begin(), episode.metrics.end(),
                                      [&](const storage::MetricValue& metric) { return metric.key == definition.key; });
      if (found != episode.metrics.end() && found->value) csv << *found->value;
    }
    csv << '\n';
  }
  return csv.str();
}

/// A query parameter's comma-separated values; none when absent.
std::vector<std::string> list_parameter(const Request& request, const std::string& key) {
  std::vector<std::string> values;
  std::istringstream list(query_value(request.query, key).value_or(""));
  for (std::string value; std::getline(list, value, ',');) {
    if (!value.empty()) values.push_back(value);
  }
  return values;
}

/// "metric.statistic" checked against the metric definitions (a gate's left side).
std::pair<std::string, std::string> metric_statistic(const std::string& text, const std::string& parameter) {
  try {
    const metrics::Gate gate = metrics::parse_gate(text + " == 0");
    return {gate.metric, gate.statistic};
  } catch (const core::Error& e) {
    throw core::Error(core::ErrorCode::bad_request, parameter + ": " + e.what(), {{"parameter", parameter}});
  }
}

/// The list a GET /api/v1/runs asks for: status, scenario, text, tag, sorting by a metric (cursor
/// "@offset" then) or newest first (cursor: the last run's id), and filters in a gate's form.
storage::RunQuery run_query(const Request& request, storage::Store& store) {
  storage::RunQuery query;
  query.limit = static_cast<int>(integer_query(request, "limit", 1, kMaxRunsPerPage, 20));
  query.status = query_value(request.query, "status").value_or("");
  query.scenario_id = query_value(request.query, "scenario").value_or("");
  query.text = query_value(request.query, "q").value_or("");
  query.tag = query_value(request.query, "tag").value_or("");
  query.owner = request.caller.sees_all ? std::nullopt : std::optional(request.caller.owner);
  static const std::set<std::string> kStatuses{"", "queued", "running", "finished", "failed", "cancelled", "interrupted"};
  if (!kStatuses.contains(query.status)) {
    throw core::Error(core::ErrorCode::bad_request,
                      "status must be one of queued, running, finished, failed, cancelled, interrupted", {{"parameter", "status"}});
  }
  if (const auto sort = query_value(request.query, "sort"); sort && *sort != "created") query.sort = metric_statistic(*sort, "sort");
  const std::string order = query_value(request.query, "order").value_or("desc");
  if (order != "asc" && order != "desc") throw core::Error(core::ErrorCode::bad_request, "order: asc or desc", {{"parameter", "order"}});
  query.descending = order == "desc";
  for (const std::string& where : list_parameter(request, "where")) {
    try {
      const metrics::Gate gate = metrics::parse_gate(where);
      query.filters.push_back({gate.metric, gate.statistic, gate.op, gate.threshold});
    } catch (const core::Error& e) {
      throw core::Error(core::ErrorCode::bad_request, std::string("where: ") + e.what(), {{"parameter", "where"}});
    }
  }
  const std::string cursor = query_value(request.query, "cursor").value_or("");
  if (query.sort) {
    char* end = nullptr;
    const long long offset = cursor.starts_with('@') ? std::strtoll(cursor.c_str() + 1, &end, 10) : 0;
    if (!cursor.empty() && (!cursor.starts_with('@') || end == cursor.c_str() + 1 || *end != '\0' || offset < 0)) {
      throw core::Error(core::ErrorCode::bad_request, "cursor: the next_cursor of the previous page of this sorted list", {{"parameter", "cursor"}});
    }
    query.offset = offset;
  } else {
    if (!cursor.empty() && !store.run(cursor)) throw core::Error(core::ErrorCode::bad_request, "cursor: no run '" + cursor + "'", {{"parameter", "cursor"}});
    query.after_id = cursor;
  }
  return query;
}

/// Stores the summary of every ended run that has none yet, so that lists sort and filter them all.
void summarize_ended_runs(storage::Store& store, runs::Executor& executor) {
  for (const storage::RunRecord& run : store.ended_runs_without_summary()) {
    store.set_run_summary(run.id, report_of(store, executor, run)["aggregates"]);
  }
}

/// Distinct run configurations (scenario content, controller, time limit, requests) one import may
/// hold: each is compiled against its scenario, which costs what compiling the scenario costs, so an
/// import of many small runs could otherwise ask for thousands of compiles. Results of shards and of
/// a few controllers hold a handful.
constexpr std::size_t kMaxImportedConfigurations = 64;

/// An imported run's config compiled against its scenario as POST /api/v1/runs compiles a request
/// (controller, time limit, requests): a run that could not have been asked for here is refused.
void check_imported_config(ScenarioCatalogue& catalogue, const storage::ScenarioRecord& scenario, const storage::RunRecord& run) {
  const auto format = scenario::source_format(scenario.format);
  if (!format) throw core::Error(core::ErrorCode::bad_request, "its scenario has a format hrisim does not read");
  catalogue.check(Upload{scenario.source, *format, scenario.files}, [&run](const scenario::CompiledSource& compiled, const scenario::SourceOptions& options) {
    if (!compiled.model) {
      const std::string first = compiled.errors.empty() ? "" : ": " + compiled.errors.front().message;
      throw core::Error(core::ErrorCode::bad_request, "its scenario does not load here" + first);
    }
    runs::RunRequest request = runs::replay_request(compiled.document, options.load, run.config, 0);
    request.seeds = run.config.value("seeds", std::vector<std::uint64_t>{});
    (void)runs::make_run_spec(request);
  });
}

/// The runs routes over REST, each a named handler (kRunRoutes). Bodies reach them checked against
/// api/openapi.yaml (Router::follow).
class RunRoutes {
 public:
  RunRoutes(std::shared_ptr<ScenarioCatalogue> catalogue, storage::Store* store, runs::Executor* executor)
      : catalogue_(std::move(catalogue)), store_(store), executor_(executor) {}

  Response metrics(const Request& request) const;
  Response submit(const Request& request) const;
  Response list(const Request& request) const;
  Response label(const Request& request) const;
  Response compare(const Request& request) const;
  Response report(const Request& request) const;
  Response cancel(const Request& request) const;
  Response episodes(const Request& request) const;
  Response import_runs(const Request& request) const;
  Response junit(const Request& request) const;

 private:
  std::shared_ptr<ScenarioCatalogue> catalogue_;
  storage::Store* store_;
  runs::Executor* executor_;
};

constexpr NamedRoute<RunRoutes> kRunRoutes[] = {
    {"GET", "/api/v1/metrics", &RunRoutes::metrics},
    {"POST", "/api/v1/runs", &RunRoutes::submit},
    {"GET", "/api/v1/runs", &RunRoutes::list},
    {"PATCH", "/api/v1/runs/{id}", &RunRoutes::label},
    {"GET", "/api/v1/runs/compare", &RunRoutes::compare},
    {"GET", "/api/v1/runs/{id}", &RunRoutes::report},
    {"POST", "/api/v1/runs/{id}/cancel", &RunRoutes::cancel},
    {"GET", "/api/v1/runs/{id}/episodes", &RunRoutes::episodes},
    {"POST", "/api/v1/runs/import", &RunRoutes::import_runs},
    {"GET", "/api/v1/runs/{id}/junit", &RunRoutes::junit},
};

Response RunRoutes::metrics(const Request&) const {
  json items = json::array();
  for (const metrics::Definition& d : metrics::definitions()) {
    items.push_back({{"key", d.key},
                     {"unit", d.unit},
                     {"category", d.category},
                     {"better", metrics::to_string(d.better)},
                     {"description", d.description},
                     {"convention", d.convention}});
  }
  json series = json::array();
  for (const metrics::SeriesDefinition& d : metrics::series_definitions()) {
    series.push_back({{"name", d.name}, {"unit", d.unit}, {"description", d.description}});
  }
  return Response::json(200, {{"items", items}, {"series", series}});
}

Response RunRoutes::submit(const Request& request) const {
  const json& body = request.checked_body;
  Problems problems;
  const runs::RunRequest asked = run_request(body, *catalogue_, request.caller, problems);
  RunLabels labels;
  read_labels(body, labels, problems);
  runs::RunSpec spec = runs::make_run_spec(asked, problems.list());
  spec.owner = request.caller.owner;
  spec.name = labels.name;
  spec.tags = labels.tags;
  spec.notes = labels.notes;
  spec.scenario_id = stored_scenario_id(*store_, asked.scenario_id, *catalogue_->find(asked.scenario_id), asked.scenario_sha256);
  const storage::RunRecord run = executor_->submit(std::move(spec));
  Response response = Response::json(201, report_of(*store_, *executor_, find_run(*store_, run.id, request.caller)));
  response.headers.emplace_back("Location", "/api/v1/runs/" + run.id);
  return response;
}

Response RunRoutes::list(const Request& request) const {
  const storage::RunQuery query = run_query(request, *store_);
  if (query.sort || !query.filters.empty()) summarize_ended_runs(*store_, *executor_);
  std::vector<std::pair<std::string, std::string>> columns;
  for (const std::string& name : list_parameter(request, "metrics")) columns.push_back(metric_statistic(name, "metrics"));
  json items = json::array();
  const auto page = store_->runs(query);
  for (const storage::RunRecord& run : page) {
    const json report = report_of(*store_, *executor_, run);
    json item{{"id", report["id"]},
              {"name", report["name"]},
              {"tags", report["tags"]},
              {"scenario", report["scenario"]},
              {"controller", report["controller"]},
              {"status", report["status"]},
              {"created_at", report["created_at"]},
              {"finished_at", report["finished_at"]},
              {"progress", report["progress"]},
              {"success_rate", report["rates"]["success_rate"]},
              {"verdict", {{"passed", report["verdict"]["passed"]},
                           {"complete", report["verdict"]["complete"]},
                           {"reasons", report["verdict"]["reasons"]}}}};
    json values = json::object();
    for (const auto& [metric, statistic] : columns) values[metric + "." + statistic] = report["aggregates"][metric][statistic];
    item["metrics"] = std::move(values);
    items.push_back(std::move(item));
  }
  json reply{{"items", items}};
  const bool full = static_cast<int>(page.size()) == query.limit;
  reply["next_cursor"] = !full ? json() : query.sort ? json("@" + std::to_string(query.offset + query.limit)) : json(page.back().id);
  return Response::json(200, reply);
}

Response RunRoutes::label(const Request& request) const {
  const storage::RunRecord run = find_run(*store_, request.path_params.at("id"), request.caller);
  RunLabels labels{run.name, run.tags, run.notes};
  Problems problems;
  read_labels(request.checked_body, labels, problems);
  runs::throw_if_problems(problems.list());
  store_->set_run_labels(run.id, labels.name, labels.tags, labels.notes);
  return Response::json(200, report_of(*store_, *executor_, find_run(*store_, run.id, request.caller)));
}

Response RunRoutes::compare(const Request& request) const {
  if (query_value(request.query, "runs")) {
    const std::vector<std::string> ids = list_parameter(request, "runs");
    if (ids.size() < 2 || ids.size() > kMaxComparedRuns) {
      throw core::Error(core::ErrorCode::bad_request, "runs: from 2 to " + std::to_string(kMaxComparedRuns) + " run ids, comma-separated, the baseline first",
                        {{"parameter", "runs"}});
    }
    const std::string correction = query_value(request.query, "correction").value_or("holm");
    if (correction != "holm" && correction != "none") {
      throw core::Error(core::ErrorCode::bad_request, "correction: holm or none", {{"parameter", "correction"}});
    }
    std::vector<storage::RunRecord> records;
    std::vector<std::vector<storage::EpisodeRecord>> episodes;
    for (const std::string& id : ids) {
      if (std::any_of(records.begin(), records.end(), [&](const storage::RunRecord& run) { return run.id == id; })) {
        throw core::Error(core::ErrorCode::bad_request, "runs: run '" + id + "' is named twice", {{"parameter", "runs"}});
      }
      records.push_back(find_run(*store_, id, request.caller));
      episodes.push_back(store_->episodes_of_run(id));
    }
    std::vector<runs::RunWithEpisodes> compared;
    for (std::size_t i = 0; i < records.size(); ++i) compared.push_back({&records[i], &episodes[i]});
    return Response::json(200, runs::compare_many_runs(compared, correction == "holm"));
  }
  const auto a = query_value(request.query, "a"), b = query_value(request.query, "b");
  if (!a || a->empty() || !b || b->empty()) {
    throw core::Error(core::ErrorCode::bad_request, "give the two runs as ?a=ID&b=ID", {{"parameter", a && !a->empty() ? "b" : "a"}});
  }
  const storage::RunRecord run_a = find_run(*store_, *a, request.caller), run_b = find_run(*store_, *b, request.caller);
  return Response::json(200, runs::compare_runs(run_a, store_->episodes_of_run(run_a.id), run_b, store_->episodes_of_run(run_b.id)));
}

Response RunRoutes::report(const Request& request) const {
  return Response::json(200, report_of(*store_, *executor_, find_run(*store_, request.path_params.at("id"), request.caller)));
}

Response RunRoutes::cancel(const Request& request) const {
  const storage::RunRecord run = find_run(*store_, request.path_params.at("id"), request.caller);
  if (!executor_->cancel(run.id)) {
    throw core::Error(core::ErrorCode::conflict, "run '" + run.id + "' is " + run.status + " and cannot be cancelled",
                      {{"id", run.id}, {"status", run.status}});
  }
  return Response::json(202, report_of(*store_, *executor_, find_run(*store_, run.id, request.caller)));
}

Response RunRoutes::episodes(const Request& request) const {
  const std::string format = json_or_csv_format(request);
  const storage::RunRecord run = find_run(*store_, request.path_params.at("id"), request.caller);
  const std::vector<storage::EpisodeRecord> episodes = store_->episodes_of_run(run.id);
  if (format == "csv") return download(episodes_csv(episodes), kCsvContentType, run.id + "-episodes.csv");
  json items = json::array();
  for (const storage::EpisodeRecord& episode : episodes) items.push_back(episode_json(episode));
  return Response::json(200, {{"items", items}});
}

Response RunRoutes::import_runs(const Request& request) const {
  // Checking, copying and merging the database: work for the pool.
  return Response::later([catalogue = catalogue_, store = store_, body = request.body, owner = request.caller.owner] {
    storage::ForeignDatabase source = storage::ForeignDatabase::from_bytes(body, "the uploaded database");
    json runs = json::array();
    std::set<std::string> compiled;  // the configurations checked already, each compiled once
    const runs::RunCheck as_asked = [&catalogue, &compiled](const storage::ScenarioRecord& scenario, const storage::RunRecord& run) {
      const json& config = run.config;
      std::string configuration = scenario.sha256;
      for (const char* key : {"effective_controller", "controller", "max_time", "requests"}) configuration += '\0' + config.value(key, json()).dump();
      if (compiled.contains(configuration)) return;
      if (compiled.size() == kMaxImportedConfigurations) {
        throw core::Error(core::ErrorCode::bad_request, "more than " + std::to_string(kMaxImportedConfigurations) +
                                                            " distinct run configurations (scenario, controller, max_time, requests) in one import: "
                                                            "import the database in parts, or with hrisim serve --import");
      }
      check_imported_config(*catalogue, scenario, run);
      compiled.insert(std::move(configuration));
    };
    for (const runs::MergedRun& merged : runs::merge_database(*store, source, "this server's", owner, as_asked)) {
      runs.push_back({{"id", merged.id}, {"source_id", merged.source_id}, {"added", merged.added}, {"present", merged.present}});
    }
    return Response::json(200, {{"runs", runs}});
  });
}

Response RunRoutes::junit(const Request& request) const {
  const json report = report_of(*store_, *executor_, find_run(*store_, request.path_params.at("id"), request.caller));
  return Response{200, "application/xml", runs::junit_xml(report), {}, {}};
}

}  // namespace

void add_run_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, storage::Store* store, runs::Executor* executor) {
  add_routes(router, std::make_shared<const RunRoutes>(std::move(catalogue), store, executor), kRunRoutes);
}

}  // namespace hrisim::http
