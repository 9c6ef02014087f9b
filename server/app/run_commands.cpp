#include "app/run_commands.hpp"

#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>

#include "app/cli.hpp"
#include "app/command_line.hpp"
#include "app/sweep_file.hpp"
#include "core/error.hpp"
#include "core/random.hpp"
#include "core/sha256.hpp"
#include "runs/episode.hpp"
#include "runs/executor.hpp"
#include "runs/merge.hpp"
#include "runs/report.hpp"
#include "runs/shards.hpp"
#include "runs/spec.hpp"
#include "sim/session.hpp"
#include "storage/store.hpp"

namespace hrisim::app {
namespace {

using nlohmann::json;

/// Shows how far a run is: a bar rewritten in place on a terminal, one line per episode otherwise.
class ProgressReport {
 public:
  explicit ProgressReport(std::size_t total) : total_(total), terminal_(isatty(fileno(stderr))), start_(std::chrono::steady_clock::now()) {}

  void episode_done(const storage::EpisodeRecord& episode) {
    std::lock_guard lock(mutex_);
    ++done_;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double rate = elapsed > 0.0 ? static_cast<double>(done_) / elapsed : 0.0;
    if (!terminal_) {
      std::fprintf(stderr, "episode %zu/%zu: seed %llu %s (%s) at %.1f s\n", done_, total_, static_cast<unsigned long long>(episode.seed),
                   episode.status.c_str(), episode.termination_reason.c_str(), episode.sim_time);
      return;
    }
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done_ / total_);
    const double left = rate > 0.0 ? static_cast<double>(total_ - done_) / rate : 0.0;
    std::fprintf(stderr, "\r[%s%s] %zu/%zu episodes, %.2f/s, %.0f s left ", std::string(filled, '#').c_str(),
                 std::string(kWidth - filled, '.').c_str(), done_, total_, rate, left);
    if (done_ == total_) std::fputc('\n', stderr);
  }

 private:
  std::mutex mutex_;
  std::size_t total_, done_ = 0;
  bool terminal_;
  std::chrono::steady_clock::time_point start_;
};

/// A temporary database for a run whose episodes are not to be kept (no --db).
struct ScratchDatabase {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("hrisim-run-" + core::unguessable_id('d') + ".db");
  ~ScratchDatabase() { storage::remove_database(path); }
};

/// The process's environment, where schedulers say which shard a task is.
std::optional<std::string> environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? std::optional<std::string>(value) : std::nullopt;
}

/// --jobs: episodes at once (one per core by default).
unsigned jobs_of(const ParsedArgs& parsed) {
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  if (const auto text = parsed.last("--jobs")) {
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), jobs);
    if (ec != std::errc() || end != text->data() + text->size() || jobs == 0 || jobs > 256) usage_error("--jobs: expected 1 to 256, got '" + *text + "'");
  }
  return jobs;
}

std::vector<std::uint64_t> seeds_of_shard(const std::vector<std::uint64_t>& seeds, const runs::Shard& shard) {
  std::vector<std::uint64_t> part;
  for (const std::size_t position : runs::shard_positions(seeds.size(), shard)) part.push_back(seeds[position]);
  return part;
}

/// --shard, read (with the scheduler's variables for auto), and the --db it needs; none without it.
std::optional<runs::Shard> shard_of(const ParsedArgs& parsed) {
  const auto text = parsed.last("--shard");
  if (!text) return std::nullopt;
  if (!parsed.last("--db")) usage_error("--shard: give --db FILE, the database this shard's episodes are kept in to be merged (hrisim merge)");
  return runs::parse_shard(*text, environment);
}

/// Makes `request` a run of a loaded file: its document, where its maps are, and the stored record it
/// runs from (one per distinct file content).
void set_scenario(runs::RunRequest& request, const LoadedFile& loaded) {
  request.document = loaded.document;
  request.load = loaded.load;
  request.scenario_sha256 = core::sha256_hex(loaded.text);
  request.scenario_id = "f" + request.scenario_sha256.substr(0, 32);
}

/// The file set_scenario() gave a request, as it is stored with its runs.
storage::ScenarioRecord stored_scenario(const runs::RunRequest& request, const LoadedFile& loaded) {
  return {request.scenario_id, loaded.result.model->name, std::string(scenario::to_string(loaded.format)), loaded.text, "", "", "", "", {}};
}

/// The request's spec; a refused one prints each problem as PREFIX POINTER CONTEXT: MESSAGE first.
runs::RunSpec spec_of(const runs::RunRequest& request, const std::string& prefix = "", const std::string& context = "") {
  try {
    return runs::make_run_spec(request);
  } catch (const core::Error& e) {
    for (const auto& error : e.details().value("errors", json::array())) {
      std::fprintf(stderr, "%s%s%s: %s\n", prefix.c_str(), error["pointer"].get<std::string>().c_str(), context.c_str(),
                   error["message"].get<std::string>().c_str());
    }
    throw;
  }
}

/// Makes `spec` (of the shard's seeds) the shard's part of the whole run: the whole run's id, derived
/// from what it is (its name, scenario, seeds, shard count, gates and limits), and in its config the
/// shard, the count and the whole run's seeds. hrisim merge joins the parts.
void make_shard(runs::RunSpec& spec, const runs::RunRequest& request, const std::vector<std::uint64_t>& all_seeds, const runs::Shard& shard) {
  const json identity = {{"name", spec.name},
                         {"scenario", spec.model->name},
                         {"seeds", all_seeds},
                         {"shards", shard.count},
                         {"gates", request.gates},
                         {"max_time", spec.config["max_time"]},
                         {"requests", spec.config["requests"]},
                         {"baseline_without_robot", request.baseline_without_robot}};
  spec.id = runs::shard_run_id(identity);
  spec.config["sharding"] = {{"count", shard.count}, {"index", shard.index}, {"of_seeds", all_seeds}};
}

/// The database at `path`, its folder made, with the runs of killed processes marked interrupted.
std::filesystem::path prepared(const std::filesystem::path& path) {
  if (const auto folder = path.parent_path(); !folder.empty()) std::filesystem::create_directories(folder);
  return path;
}

/// A run this process makes: its spec (with the seeds it runs), the scenario file it came from (kept
/// with it) and what the verdict line calls it.
struct PlannedRun {
  runs::RunSpec spec;
  storage::ScenarioRecord scenario;
  std::string label;
};

/// Runs `planned` into `store` on `jobs` threads → each run's report and label. A shard's run the
/// database has finished already (a task run again) is reported as it is.
std::vector<std::pair<json, std::string>> execute(storage::Store& store, const std::filesystem::path& database, std::vector<PlannedRun> planned,
                                                  unsigned jobs) {
  // Runs of a process that was killed (this command's or a server's) are found out now.
  if (const int interrupted = store.interrupt_abandoned_runs(); interrupted > 0) {
    std::fprintf(stderr, "hrisim: %d run%s whose process ended marked interrupted\n", interrupted, interrupted == 1 ? "" : "s");
  }
  std::size_t total = 0;
  for (const PlannedRun& run : planned) {
    if (run.spec.id.empty()) {
      total += run.spec.seeds.size();
      continue;
    }
    if (const auto existing = store.run(run.spec.id)) {
      if (existing->status != "finished") {
        throw core::Error(core::ErrorCode::conflict, database.string() + " has this shard's run " + existing->id + " " + existing->status +
                                                         ": give the shard a new database, or delete that one");
      }
    } else {
      total += run.spec.seeds.size();
    }
  }
  ProgressReport progress(std::max<std::size_t>(total, 1));
  runs::Executor executor(store, jobs, [&](const std::string&, const storage::EpisodeRecord& episode) { progress.episode_done(episode); });
  std::vector<std::pair<std::string, std::string>> ids;
  for (PlannedRun& run : planned) {
    store.put_scenario_if_missing(run.scenario);
    if (!run.spec.id.empty() && store.run(run.spec.id)) {
      ids.emplace_back(run.spec.id, run.label);
      continue;
    }
    ids.emplace_back(executor.submit(std::move(run.spec)).id, run.label);
  }
  std::vector<std::pair<json, std::string>> reports;
  for (const auto& [id, label] : ids) {
    executor.wait(id);
    reports.emplace_back(runs::run_report(*store.run(id), store.episodes_of_run(id), {}), label);
  }
  return reports;
}

/// Prints the reports — one as itself, several as {"runs": [...]} — with each verdict's reasons and a
/// verdict line on stderr, and writes JUnit XML of a single run when asked → 0 when every verdict
/// passes, else 1. `scratch`: the runs were not kept (their ids are left out).
int print_reports(const std::vector<std::pair<json, std::string>>& reports, bool scratch, const std::optional<std::string>& junit_path) {
  if (junit_path) {
    if (reports.size() != 1) usage_error("--junit: one run's report only; this command made " + std::to_string(reports.size()));
    std::ofstream junit(*junit_path);
    if (!junit) usage_error("--junit: cannot write " + *junit_path);
    junit << runs::junit_xml(reports.front().first);
  }
  json printed = json::array();
  bool all_passed = true;
  for (const auto& [report, label] : reports) {
    printed.push_back(report);
    if (scratch) printed.back().erase("id");  // the run was not kept
    const bool passed = report["verdict"]["passed"];
    all_passed = all_passed && passed;
    for (const auto& reason : report["verdict"]["reasons"]) std::fprintf(stderr, "%s\n", reason.get<std::string>().c_str());
    const json sharding = report["config"].value("sharding", json());
    const std::string part = sharding.contains("index") ? " (shard " + std::to_string(sharding["index"].get<int>()) + "/" +
                                                              std::to_string(sharding["count"].get<int>()) + " of run " + report["id"].get<std::string>() + ")"
                                                        : "";
    std::fprintf(stderr, "%s: %zu episodes%s, verdict %s\n", label.c_str(), report["episodes"].size(), part.c_str(), passed ? "PASSED" : "FAILED");
  }
  std::printf("%s\n", (printed.size() == 1 ? printed.front() : json{{"runs", printed}}).dump(2).c_str());
  return all_passed ? 0 : 1;
}

/// Runs `planned` into --db (a scratch file without it) and prints their reports → the exit status.
int run_and_report(const ParsedArgs& parsed, std::vector<PlannedRun> planned, unsigned jobs) {
  std::optional<ScratchDatabase> scratch;
  const std::filesystem::path database = parsed.last("--db") ? std::filesystem::path(*parsed.last("--db")) : scratch.emplace().path;
  storage::Store store(prepared(database));
  return print_reports(execute(store, database, std::move(planned), jobs), scratch.has_value(), parsed.last("--junit"));
}

}  // namespace

int run_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(
      args, {"--seed", "--seeds", "--db", "--max-time", "--request", "--from", "--dialect", "--scenario", "--map", "--trajectory", "--gate", "--junit", "--controller", "--jobs",
             "--shard", "--name"},
      {"--events", "--baseline-without-robot"},
      "usage: hrisim run FILE [--seed N | --seeds A-B|A,B,C] [--gate EXPR ...] [--junit FILE.xml] [--db FILE] [--jobs N] [--name NAME] "
      "[--shard K/N|auto|auto/N] "
      "[--controller JSON] [--baseline-without-robot] [--max-time S] [--events] [--request TIME:ROUTINE ...] [--from imhus|pedsim|hunav] [--scenario NAME] [--map FILE] "
      "[--trajectory FILE.csv]");
  const std::string& file = parsed.file;
  std::uint64_t single_seed = 0;
  if (const auto text = parsed.last("--seed")) {
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), single_seed);
    if (ec != std::errc() || end != text->data() + text->size()) usage_error("--seed: expected a whole number, got '" + *text + "'");
  }
  // A batch is a stored run with a report and a verdict; one plain episode prints its own summary.
  const bool batch = parsed.last("--seeds") || parsed.last("--db") || parsed.values.contains("--gate") || parsed.last("--junit") || parsed.last("--shard");
  const std::optional<runs::Shard> shard = shard_of(parsed);
  if (parsed.last("--seeds") && parsed.last("--seed")) usage_error("--seed and --seeds: give one of them");
  const std::vector<std::uint64_t> seeds = parsed.last("--seeds") ? parse_seeds(*parsed.last("--seeds")) : std::vector<std::uint64_t>{single_seed};

  runs::RunRequest request;
  request.seeds = shard ? seeds_of_shard(seeds, *shard) : seeds;
  if (const auto text = parsed.last("--max-time")) request.max_time = parse_seconds("--max-time", *text);
  if (parsed.values.contains("--request")) {
    for (const std::string& text : parsed.values.at("--request")) {
      const auto colon = text.find(':');
      if (colon == std::string::npos) usage_error("--request: expected TIME:ROUTINE, got '" + text + "'");
      request.requests.emplace_back(parse_seconds("--request", text.substr(0, colon)), text.substr(colon + 1));
    }
  }
  if (parsed.values.contains("--gate")) request.gates = parsed.values.at("--gate");
  request.baseline_without_robot = parsed.flags.contains("--baseline-without-robot");
  if (const auto text = parsed.last("--controller")) {
    try {
      request.controller = nlohmann::json::parse(*text);
    } catch (const nlohmann::json::parse_error&) {
      usage_error("--controller: expected a JSON object such as '{\"type\":\"social\",\"goal\":{\"location\":\"exit\"}}', got '" + *text + "'");
    }
  }
  const unsigned jobs = jobs_of(parsed);

  const LoadedFile loaded = load(file, source_options(parsed));
  print_errors(file, loaded.result.warnings, "warning: ", loaded.imported ? &*loaded.imported : nullptr);
  if (!loaded.result.model) {
    print_errors(file, loaded);
    return 2;
  }
  set_scenario(request, loaded);
  runs::RunSpec spec = spec_of(request);

  if (!batch) {
    std::ofstream trajectory;
    runs::EpisodeOptions options;
    options.max_time = spec.max_time;
    options.requests = spec.requests;
    options.baseline_without_robot = spec.baseline_without_robot;
    if (const auto path = parsed.last("--trajectory")) {
      trajectory.open(*path);
      if (!trajectory) usage_error("--trajectory: cannot write " + *path);
      trajectory << "time,tick,agent,x,y,theta,vx,vy\n";
      trajectory.precision(17);
      const std::int64_t stride = runs::trajectory_stride(spec.model->dt);
      options.observe = [&trajectory, stride](const sim::Session& session) {
        if (session.state().tick % stride != 0) return;
        for (const sim::AgentId id : session.agent_ids()) {
          const int index = session.index_of(id);
          const sim::AgentState& agent = session.state().agents[index];
          trajectory << session.time() << ',' << session.state().tick << ',' << session.model().agents[index].id << ',' << agent.position.x()
                     << ',' << agent.position.y() << ',' << agent.heading << ',' << agent.velocity.x() << ',' << agent.velocity.y() << '\n';
        }
      };
    }
    runs::EpisodeResult episode = runs::run_episode(spec.model, single_seed, options);
    if (parsed.flags.contains("--events")) {
      nlohmann::json log = nlohmann::json::array();
      for (const storage::EventRecord& event : episode.record.events) {
        log.push_back({{"tick", event.tick}, {"time", event.time}, {"kind", event.kind}, {"subject", event.subject}, {"data", event.data}});
      }
      episode.summary["event_log"] = log;
    }
    std::printf("%s\n", episode.summary.dump(2).c_str());
    return 0;
  }
  if (parsed.last("--trajectory") || parsed.flags.contains("--events")) {
    usage_error("--trajectory and --events are for one episode; a run stores every episode's (give --db)");
  }

  spec.name = parsed.last("--name").value_or("");
  if (shard) make_shard(spec, request, seeds, *shard);

  // With --db the run and its episodes are kept, each episode in one transaction as it ends.
  const std::string label = spec.name.empty() ? spec.model->name : spec.name;
  std::vector<PlannedRun> planned;
  planned.push_back({std::move(spec), stored_scenario(request, loaded), label});
  return run_and_report(parsed, std::move(planned), jobs);
}

int sweep_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(args, {"--db", "--jobs", "--shard", "--junit"}, {},
                                       "usage: hrisim sweep SWEEP.json [--db FILE] [--jobs N] [--shard K/N|auto|auto/N]");
  if (parsed.last("--junit")) usage_error("--junit: a sweep has several runs; merge them, or give hrisim run one run's");
  const Sweep sweep = read_sweep(parsed.file);
  const std::optional<runs::Shard> shard = shard_of(parsed);
  const unsigned jobs = jobs_of(parsed);

  std::vector<PlannedRun> planned;
  for (std::size_t s = 0; s < sweep.scenarios.size(); ++s) {
    const std::string& file = sweep.scenarios[s];
    const LoadedFile loaded = load(file);
    if (!loaded.result.model) {
      print_errors(file, loaded);
      usage_error(parsed.file + ": /scenarios/" + std::to_string(s) + ": " + file + " is not a valid scenario");
    }
    for (std::size_t c = 0; c < sweep.controllers.size(); ++c) {
      runs::RunRequest request;
      set_scenario(request, loaded);
      request.seeds = shard ? seeds_of_shard(sweep.seeds, *shard) : sweep.seeds;
      if (!sweep.controllers[c].is_null()) request.controller = sweep.controllers[c];
      request.gates = sweep.gates;
      request.max_time = sweep.max_time;
      request.requests = sweep.requests;
      request.baseline_without_robot = sweep.baseline_without_robot;
      runs::RunSpec spec = spec_of(request, parsed.file + ": ", " (scenario " + file + ", controller " + std::to_string(c) + ")");
      const std::string controller = sweep.controllers[c].is_null() ? "own controller" : sweep.controllers[c].value("type", "controller " + std::to_string(c));
      spec.name = sweep.name + " · " + loaded.result.model->name + " · " + controller;
      if (shard) make_shard(spec, request, sweep.seeds, *shard);
      const std::string label = spec.name;
      planned.push_back({std::move(spec), stored_scenario(request, loaded), label});
    }
  }
  return run_and_report(parsed, std::move(planned), jobs);
}

int merge_command(const std::vector<std::string>& args) {
  const std::string usage = "usage: hrisim merge SHARD.db... --into RESULTS.db [--junit FILE.xml]";
  const ParsedArgs parsed = parse_args(args, {"--into", "--junit"}, {}, usage, true);
  const auto into = parsed.last("--into");
  if (!into) usage_error("--into: the database to merge into is required\n" + usage);
  for (const std::string& file : parsed.files) {
    if (!std::filesystem::is_regular_file(file)) usage_error(file + ": no such database");
    std::error_code ignored;
    if (std::filesystem::equivalent(file, *into, ignored)) usage_error(file + " is the database merged into (--into)");
  }
  storage::Store target(prepared(*into));
  storage::ForeignDatabase::remove_abandoned_copies();  // of merges that were killed
  std::vector<std::string> runs_merged;
  for (const std::string& file : parsed.files) {
    storage::ForeignDatabase source = storage::ForeignDatabase::from_file(file, file);
    for (const runs::MergedRun& merged : runs::merge_database(target, source, *into)) {
      std::fprintf(stderr, "%s: run %s: %d episode%s added, %d already in %s\n", file.c_str(), merged.id.c_str(), merged.added,
                   merged.added == 1 ? "" : "s", merged.present, into->c_str());
      if (std::find(runs_merged.begin(), runs_merged.end(), merged.id) == runs_merged.end()) runs_merged.push_back(merged.id);
    }
  }
  std::vector<std::pair<json, std::string>> reports;
  for (const std::string& id : runs_merged) {
    const storage::RunRecord run = *target.run(id);
    reports.emplace_back(runs::run_report(run, target.episodes_of_run(id), {}), run.name.empty() ? run.id : run.name);
  }
  return print_reports(reports, false, parsed.last("--junit"));
}

}  // namespace hrisim::app
