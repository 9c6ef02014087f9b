#include "app/scenario_commands.hpp"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/sha256.hpp"
#include "scenario/import.hpp"
#include "scenario/load.hpp"
#include "scenario/source.hpp"
#include "sim/session.hpp"
#include "storage/store.hpp"

namespace hrisim::app {
namespace {

/// Samples per second written by `hrisim run --trajectory`.
constexpr double kTrajectoryRate = 10.0;
/// Most seeds one `hrisim run --seeds A-B` runs.
constexpr std::uint64_t kMaxSeedsPerRun = 100000;

[[noreturn]] void usage_error(const std::string& message) {
  throw core::Error(core::ErrorCode::bad_request, message);
}

double parse_seconds(const std::string& option, const std::string& text) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !(value >= 0.0)) {
    usage_error(option + ": expected a number of seconds >= 0, got '" + text + "'");
  }
  return value;
}

/// Arguments of a command: one file and options, each option with its values in order.
struct ParsedArgs {
  std::string file;
  std::map<std::string, std::vector<std::string>> values;  ///< options that take a value
  std::set<std::string> flags;                              ///< options without one
  std::optional<std::string> last(const std::string& option) const {
    const auto found = values.find(option);
    return found == values.end() ? std::nullopt : std::optional(found->second.back());
  }
};

ParsedArgs parse_args(const std::vector<std::string>& args, const std::set<std::string>& valued,
                      const std::set<std::string>& flags, const std::string& usage) {
  ParsedArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (valued.contains(arg)) {
      if (i + 1 >= args.size()) usage_error(arg + " needs a value");
      parsed.values[arg].push_back(args[++i]);
    } else if (flags.contains(arg)) {
      parsed.flags.insert(arg);
    } else if (arg.starts_with("--")) {
      usage_error("unknown option " + arg);
    } else if (parsed.file.empty()) {
      parsed.file = arg;
    } else {
      usage_error("unexpected argument '" + arg + "'");
    }
  }
  if (parsed.file.empty()) usage_error(usage);
  return parsed;
}

/// How an XML file is turned into a scenario.
struct SourceOptions {
  std::string format;  ///< "imhus", "pedsim", or empty to detect
  std::string scenario;
  std::optional<std::filesystem::path> map;
};

SourceOptions source_options(const ParsedArgs& parsed) {
  SourceOptions source;
  source.format = parsed.last("--from").value_or("");
  source.scenario = parsed.last("--scenario").value_or("");
  if (const auto map = parsed.last("--map")) source.map = *map;
  return source;
}

void print_messages(const std::string& file, const char* kind, const std::vector<scenario::ImportMessage>& messages) {
  for (const auto& message : messages) {
    std::fprintf(stderr, "%s:%s %s%s\n", file.c_str(), message.line > 0 ? (std::to_string(message.line) + ":").c_str() : "",
                 kind, message.message.c_str());
  }
}

/// Imports an IMHuS or Pedsim XML file; prints its warnings, and its errors when there are any.
std::optional<scenario::ImportResult> import_file(const std::string& file, const SourceOptions& source) {
  std::ifstream in(file, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "%s: cannot read the file\n", file.c_str());
    return std::nullopt;
  }
  std::ostringstream text;
  text << in.rdbuf();
  const std::string format = source.format.empty() ? scenario::detect_xml_format(text.str()) : source.format;
  if (format != "imhus" && format != "pedsim") usage_error("--from: expected imhus or pedsim, got '" + format + "'");
  scenario::ImportOptions options{source.scenario, source.map, {bundled_scenarios_dir()},
                                  std::filesystem::path(file).filename().string()};
  scenario::ImportResult result = format == "imhus" ? scenario::import_imhus(text.str(), options)
                                                    : scenario::import_pedsim(text.str(), options);
  print_messages(file, "warning: ", result.warnings);
  if (!result.errors.empty()) {
    print_messages(file, "", result.errors);
    return std::nullopt;
  }
  return result;
}

scenario::LoadResult load(const std::string& file, const SourceOptions& source = {}) {
  if (std::filesystem::path(file).extension() != ".xml") return scenario::load_scenario_file(file, {{bundled_scenarios_dir()}});
  const auto imported = import_file(file, source);
  if (!imported) return {nullptr, {{"", "the XML file could not be imported"}}, {}};
  // Relative map paths in the imported scenario resolve next to the XML file, then in the bundle.
  const scenario::LoadOptions options{{std::filesystem::path(file).parent_path(), bundled_scenarios_dir()}};
  return scenario::load_scenario(nlohmann::json::parse(imported->scenario.dump()), options);
}

void print_errors(const std::string& file, const std::vector<core::ValidationError>& errors, const char* kind = "") {
  for (const auto& error : errors) {
    std::fprintf(stderr, "%s: %s: %s%s\n", file.c_str(), error.pointer.empty() ? "(document)" : error.pointer.c_str(),
                 kind, error.message.c_str());
  }
}

}  // namespace

std::string bundled_scenarios_dir() {
  const char* configured = std::getenv("HRISIM_SCENARIOS");
  return configured ? configured : "scenarios";
}

int validate_command(const std::vector<std::string>& args) {
  if (args.empty()) usage_error("usage: hrisim validate FILE...");
  int status = 0;
  for (const std::string& file : args) {
    const scenario::LoadResult result = load(file);
    print_errors(file, result.warnings, "warning: ");
    if (!result.model) {
      print_errors(file, result.errors);
      std::fprintf(stderr, "%s: %zu error%s\n", file.c_str(), result.errors.size(), result.errors.size() == 1 ? "" : "s");
      status = 1;
      continue;
    }
    std::size_t humans = 0;
    for (const auto& agent : result.model->agents) humans += agent.kind == scenario::AgentKind::human;
    std::printf("%s: ok (%zu humans, %zu robots, %zu steps)\n", file.c_str(), humans,
                result.model->agents.size() - humans, result.model->steps.size());
  }
  return status;
}

namespace {

/// Seeds of `--seeds`: "A-B" (inclusive) or "A,B,C".
std::vector<std::uint64_t> parse_seeds(const std::string& text) {
  auto number = [&](std::string_view part) {
    std::uint64_t value = 0;
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (ec != std::errc() || end != part.data() + part.size()) usage_error("--seeds: expected A-B or A,B,C of whole numbers, got '" + text + "'");
    return value;
  };
  std::vector<std::uint64_t> seeds;
  if (text.empty()) usage_error("--seeds: expected A-B or A,B,C of whole numbers, got nothing");
  if (const auto dash = text.find('-'); dash != std::string::npos) {
    const std::uint64_t first = number(std::string_view(text).substr(0, dash)), last = number(std::string_view(text).substr(dash + 1));
    if (last < first || last - first >= kMaxSeedsPerRun) {
      usage_error("--seeds: A-B needs A <= B and at most " + std::to_string(kMaxSeedsPerRun) + " seeds, got '" + text + "'");
    }
    for (std::uint64_t seed = first; seed <= last; ++seed) seeds.push_back(seed);
  } else {
    std::string_view rest(text);
    while (!rest.empty()) {
      const auto comma = rest.find(',');
      seeds.push_back(number(rest.substr(0, comma)));
      rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    }
  }
  return seeds;
}

struct RunOptions {
  std::optional<double> max_time;
  bool with_events = false;
  std::vector<std::pair<double, std::string>> requests;
  std::ofstream* trajectory_csv = nullptr;  ///< every agent at kTrajectoryRate, when given
};

struct Episode {
  nlohmann::json summary;
  std::vector<storage::EventRecord> events;
  std::vector<storage::TrajectorySample> trajectory;  ///< every agent at kTrajectoryRate
};

/// Runs one episode of the model with this seed to its end (or max_time).
Episode run_episode(const std::shared_ptr<const scenario::Model>& shared, std::uint64_t seed, const RunOptions& options) {
  const scenario::Model& model = *shared;
  sim::Session session(shared, seed);
  for (const auto& [time, task_name] : options.requests) {
    const int task = model.find_task(task_name);
    if (task < 0) usage_error("--request: the scenario has no task '" + task_name + "'");
    int robot = -1;
    for (std::size_t a = 0; a < model.agents.size() && robot < 0; ++a) {
      if (model.agents[a].kind == scenario::AgentKind::robot) robot = static_cast<int>(a);
    }
    if (robot < 0) usage_error("--request: the scenario has no robot to make the request");
    session.schedule_request(time, session.agent_id(model.agents[robot].id), task);
  }
  Episode episode;
  const std::int64_t sample_every = std::max<std::int64_t>(1, std::llround(1.0 / (kTrajectoryRate * model.dt)));
  std::int64_t last_sampled = -1;
  auto record = [&](const sim::Session& running) {
    const sim::State& state = running.state();
    if (state.tick % sample_every != 0 || state.tick == last_sampled) return;  // the end may be observed twice
    last_sampled = state.tick;
    for (const sim::AgentId id : running.agent_ids()) {
      const int index = running.index_of(id);
      const sim::AgentState& agent = state.agents[index];
      episode.trajectory.push_back({model.agents[index].id, state.tick, agent.position.x(), agent.position.y(), agent.heading});
      if (options.trajectory_csv) {
        *options.trajectory_csv << running.time() << ',' << state.tick << ',' << model.agents[index].id << ',' << agent.position.x() << ','
                                << agent.position.y() << ',' << agent.heading << ',' << agent.velocity.x() << ',' << agent.velocity.y() << '\n';
      }
    }
  };
  record(session);
  session.run(options.max_time, record);

  const sim::State& state = session.state();
  nlohmann::json steps = nlohmann::json::array();
  for (std::size_t s = 0; s < model.steps.size(); ++s) {
    const sim::StepRecord& step = state.steps[s];
    nlohmann::json entry{{"name", model.steps[s].name}};
    entry["started"] = step.started_tick < 0 ? nlohmann::json() : nlohmann::json(step.started_tick * model.dt);
    entry["finished"] = step.finished_tick < 0 ? nlohmann::json() : nlohmann::json(step.finished_tick * model.dt);
    entry["duration"] = step.finished_tick < 0 ? nlohmann::json() : nlohmann::json((step.finished_tick - step.started_tick) * model.dt);
    steps.push_back(entry);
  }
  nlohmann::json agents = nlohmann::json::array();
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    const sim::AgentState& agent = state.agents[a];
    agents.push_back({{"id", model.agents[a].id},
                      {"x", agent.position.x()},
                      {"y", agent.position.y()},
                      {"theta", agent.heading},
                      {"busy", !agent.program.empty()}});
  }
  std::map<std::string, int> counts;
  for (const sim::Event& event : state.events) {
    ++counts[event.kind];
    episode.events.push_back({event.tick, event.time, event.kind, event.subject, event.data});
  }
  const bool in_step = state.step < static_cast<int>(model.steps.size());
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(session.state_hash()));
  episode.summary = {
      {"scenario", model.name},
      {"seed", seed},
      {"dt", model.dt},
      {"ticks", state.tick},
      {"sim_time", session.time()},
      {"completed", state.termination == "scenario_end"},
      {"termination", state.termination},
      {"step", in_step ? nlohmann::json{{"index", state.step}, {"name", model.steps[state.step].name}} : nlohmann::json()},
      {"steps", steps},
      {"events", counts},
      {"agents", agents},
      {"state_hash", hash}};
  if (options.with_events) {
    nlohmann::json log = nlohmann::json::array();
    for (const sim::Event& event : state.events) {
      log.push_back({{"tick", event.tick}, {"time", event.time}, {"kind", event.kind}, {"subject", event.subject}, {"data", event.data}});
    }
    episode.summary["event_log"] = log;
  }
  return episode;
}

}  // namespace

int run_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(
      args, {"--seed", "--seeds", "--db", "--max-time", "--request", "--scenario", "--map", "--trajectory"}, {"--events"},
      "usage: hrisim run FILE [--seed N | --seeds A-B|A,B,C] [--db FILE] [--max-time S] [--events] [--request TIME:TASK ...] "
      "[--scenario NAME] [--map FILE] [--trajectory FILE.csv]");
  const std::string& file = parsed.file;
  std::vector<std::uint64_t> seeds{0};
  if (const auto text = parsed.last("--seed")) {
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), seeds[0]);
    if (ec != std::errc() || end != text->data() + text->size()) usage_error("--seed: expected a whole number, got '" + *text + "'");
  }
  const bool batch = parsed.last("--seeds").has_value();
  if (batch) {
    if (parsed.last("--seed")) usage_error("--seed and --seeds: give one of them");
    seeds = parse_seeds(*parsed.last("--seeds"));
  }
  RunOptions options;
  if (const auto text = parsed.last("--max-time")) options.max_time = parse_seconds("--max-time", *text);
  options.with_events = parsed.flags.contains("--events");
  if (parsed.values.contains("--request")) {
    for (const std::string& text : parsed.values.at("--request")) {
      const auto colon = text.find(':');
      if (colon == std::string::npos) usage_error("--request: expected TIME:TASK, got '" + text + "'");
      options.requests.emplace_back(parse_seconds("--request", text.substr(0, colon)), text.substr(colon + 1));
    }
  }
  const SourceOptions source = source_options(parsed);

  const scenario::LoadResult loaded = load(file, source);
  print_errors(file, loaded.warnings, "warning: ");
  if (!loaded.model) {
    print_errors(file, loaded.errors);
    return 1;
  }
  std::ofstream trajectory;
  if (const auto path = parsed.last("--trajectory")) {
    trajectory.open(*path);
    if (!trajectory) usage_error("--trajectory: cannot write " + *path);
    trajectory << "time,tick,agent,x,y,theta,vx,vy\n";
    trajectory.precision(17);
    options.trajectory_csv = &trajectory;
  }
  // With --db the run and its episodes are stored, each episode in one transaction as it ends.
  std::optional<storage::Store> store;
  storage::RunRecord run;
  std::string scenario_id;
  if (const auto path = parsed.last("--db")) {
    if (const auto folder = std::filesystem::path(*path).parent_path(); !folder.empty()) std::filesystem::create_directories(folder);
    store.emplace(*path);
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const std::string sha = core::sha256_hex(text.str());
    scenario_id = "f" + sha.substr(0, 32);  // one record per distinct file content
    if (!store->scenario(scenario_id)) {
      const auto format = std::filesystem::path(file).extension() == ".xml"
                              ? std::string(scenario::to_string(scenario::detect_source_format(text.str())))
                              : std::string("json");
      store->put_scenario({scenario_id, loaded.model->name, format, text.str(), "", ""});
    }
    run = store->put_run({core::unguessable_id('r'), scenario_id, "builtin", {{"seeds", seeds}, {"max_time", options.max_time ? nlohmann::json(*options.max_time) : nlohmann::json()}},
                          "running", "", std::nullopt});
  }
  nlohmann::json episodes = nlohmann::json::array();
  int completed = 0;
  for (const std::uint64_t seed : seeds) {
    Episode episode = run_episode(loaded.model, seed, options);
    completed += episode.summary["completed"].get<bool>();
    if (store) {
      storage::EpisodeRecord record;
      record.id = core::unguessable_id('e');
      record.run_id = run.id;
      record.scenario_id = scenario_id;
      record.seed = seed;
      record.controller = "builtin";
      record.status = "finished";
      record.termination_reason = episode.summary["termination"];
      record.ticks = episode.summary["ticks"];
      record.sim_time = episode.summary["sim_time"];
      record.events = std::move(episode.events);
      record.trajectory = std::move(episode.trajectory);
      store->write_episode(record);
      episode.summary["episode_id"] = record.id;
    }
    if (batch) std::fprintf(stderr, "seed %llu: %s at %.1f s\n", static_cast<unsigned long long>(seed),
                            episode.summary["termination"].get<std::string>().c_str(), episode.summary["sim_time"].get<double>());
    episodes.push_back(std::move(episode.summary));
  }
  if (store) store->set_run_status(run.id, "finished");
  if (!batch) {
    if (store) episodes[0]["run_id"] = run.id;
    std::printf("%s\n", episodes[0].dump(2).c_str());
    return 0;
  }
  nlohmann::json summary{{"scenario", loaded.model->name}, {"episodes", episodes}, {"completed", completed}, {"of", seeds.size()}};
  if (store) summary["run_id"] = run.id;
  std::printf("%s\n", summary.dump(2).c_str());
  return 0;
}

int import_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(args, {"--from", "--scenario", "--map"}, {},
                                       "usage: hrisim import [--from imhus|pedsim] FILE [--scenario NAME] [--map FILE]");
  const std::string& file = parsed.file;
  const SourceOptions source = source_options(parsed);
  const auto imported = import_file(file, source);
  if (!imported) return 1;
  std::printf("%s\n", imported->scenario.dump(2).c_str());
  return 0;
}

}  // namespace hrisim::app
