#include "app/scenario_commands.hpp"

#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "core/error.hpp"
#include "core/random.hpp"
#include "core/sha256.hpp"
#include "app/cli.hpp"
#include "scenario/import.hpp"
#include "scenario/load.hpp"
#include "runs/episode.hpp"
#include "runs/executor.hpp"
#include "runs/report.hpp"
#include "runs/spec.hpp"
#include "runs/video.hpp"
#include "scenario/source.hpp"
#include "sim/session.hpp"
#include "storage/store.hpp"

namespace hrisim::app {
namespace {

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
    if (arg == "--help" || arg == "-h") {
      std::printf("%s\n", usage.c_str());
      std::exit(0);
    }
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

/// How a file of another simulator is turned into a scenario.
struct SourceOptions {
  std::string format;  ///< "imhus", "pedsim", "hunav", or empty to tell by the file
  std::string dialect;  ///< Pedsim: "pedsim_ros", "libpedsim", or empty for the root element's
  std::string scenario;
  std::optional<std::filesystem::path> map;
};

SourceOptions source_options(const ParsedArgs& parsed) {
  SourceOptions source;
  source.format = parsed.last("--from").value_or("");
  if (!source.format.empty() && source.format != "imhus" && source.format != "pedsim" && source.format != "hunav") {
    usage_error("--from: expected imhus, pedsim or hunav, got '" + source.format + "'");
  }
  source.dialect = parsed.last("--dialect").value_or("");
  if (!source.dialect.empty() && source.dialect != "pedsim_ros" && source.dialect != "libpedsim") {
    usage_error("--dialect: expected pedsim_ros or libpedsim, got '" + source.dialect + "'");
  }
  source.scenario = parsed.last("--scenario").value_or("");
  if (const auto map = parsed.last("--map")) source.map = *map;
  return source;
}

/// A file's format: --from's, else its extension's (.json, .xml: IMHuS or Pedsim by the content,
/// .yaml/.yml: HuNavSim), else its content's.
scenario::SourceFormat file_format(const std::string& file, std::string_view text, const SourceOptions& source) {
  if (!source.format.empty()) return *scenario::source_format(source.format);
  const std::string extension = std::filesystem::path(file).extension().string();
  if (extension == ".json") return scenario::SourceFormat::json;
  if (extension == ".yaml" || extension == ".yml") return scenario::SourceFormat::hunav_yaml;
  if (extension == ".xml") return scenario::detect_xml_format(text) == "pedsim" ? scenario::SourceFormat::pedsim_xml : scenario::SourceFormat::imhus_xml;
  return scenario::detect_source_format(text);
}

void print_messages(const std::string& file, const char* kind, const std::vector<scenario::ImportMessage>& messages) {
  for (const auto& message : messages) {
    std::fprintf(stderr, "%s:%s %s%s\n", file.c_str(), message.line > 0 ? (std::to_string(message.line) + ":").c_str() : "",
                 kind, message.message.c_str());
  }
}

std::optional<std::string> read_text(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Imports an IMHuS or Pedsim XML file or a HuNavSim agents file; prints its warnings, and its errors
/// when there are any.
std::optional<scenario::ImportResult> import_file(const std::string& file, const std::string& text, scenario::SourceFormat format,
                                                  const SourceOptions& source) {
  scenario::ImportOptions options{source.scenario, source.map, {std::filesystem::path(file).parent_path(), bundled_scenarios_dir()},
                                  std::filesystem::path(file).filename().string(), {}, source.dialect};
  options.limits.confine_files = false;  // a user's own files, on their own machine
  scenario::ImportResult result = format == scenario::SourceFormat::imhus_xml    ? scenario::import_imhus(text, options)
                                  : format == scenario::SourceFormat::pedsim_xml ? scenario::import_pedsim(text, options)
                                                                                 : scenario::import_hunav(text, options);
  print_messages(file, "warning: ", result.warnings);
  if (!result.errors.empty()) {
    print_messages(file, "", result.errors);
    return std::nullopt;
  }
  return result;
}

/// A scenario file compiled: its text and format, native document, and the model (or the errors).
struct LoadedFile {
  std::string text;
  scenario::SourceFormat format = scenario::SourceFormat::json;
  nlohmann::json document;
  scenario::LoadOptions load;  ///< where its maps are found
  scenario::LoadResult result;
  std::optional<scenario::ImportResult> imported;  ///< an imported file's import, for the lines its parts came from
};

LoadedFile load(const std::string& file, const SourceOptions& source = {}) {
  LoadedFile loaded;
  loaded.load = {{std::filesystem::path(file).parent_path(), bundled_scenarios_dir()}, {}};
  loaded.load.limits.confine_files = false;  // a user's own files, on their own machine
  auto text = read_text(file);
  if (!text) {
    loaded.result.errors = {{"", "cannot read the file"}};
    return loaded;
  }
  loaded.text = std::move(*text);
  loaded.format = file_format(file, loaded.text, source);
  if (loaded.format == scenario::SourceFormat::json) {
    loaded.result = scenario::load_scenario_text(loaded.text, loaded.load);
    if (loaded.result.model) loaded.document = nlohmann::json::parse(loaded.text);
    return loaded;
  }
  const auto imported = import_file(file, loaded.text, loaded.format, source);
  if (!imported) {
    loaded.result.errors = {{"", "the file could not be imported"}};
    return loaded;
  }
  loaded.document = imported->scenario;
  loaded.result = scenario::load_scenario(loaded.document, loaded.load);
  loaded.imported = imported;
  return loaded;
}

/// Errors as `FILE: POINTER: message`; for an imported file `FILE:LINE: POINTER: message`, at the XML
/// line the part at fault came from.
void print_errors(const std::string& file, const std::vector<core::ValidationError>& errors, const char* kind = "",
                  const scenario::ImportResult* imported = nullptr) {
  for (const auto& error : errors) {
    const int line = imported ? scenario::origin_line(*imported, error.pointer) : 0;
    std::fprintf(stderr, "%s:%s %s: %s%s\n", file.c_str(), line > 0 ? (std::to_string(line) + ":").c_str() : "",
                 error.pointer.empty() ? "(document)" : error.pointer.c_str(), kind, error.message.c_str());
  }
}

void print_errors(const std::string& file, const LoadedFile& loaded) {
  print_errors(file, loaded.result.errors, "", loaded.imported ? &*loaded.imported : nullptr);
}

}  // namespace

std::string bundled_scenarios_dir() {
  const char* configured = std::getenv("HRISIM_SCENARIOS");
  return configured ? configured : "scenarios";
}

int validate_command(const std::vector<std::string>& args) {
  const std::string usage = "usage: hrisim validate FILE... [--from imhus|pedsim|hunav] [--dialect pedsim_ros|libpedsim] [--scenario NAME] [--map FILE]";
  if (args.empty()) usage_error(usage);
  // Files and the import options that apply to all of them.
  std::vector<std::string> files, options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--from" || args[i] == "--dialect" || args[i] == "--scenario" || args[i] == "--map") {
      options.push_back(args[i]);
      if (i + 1 < args.size()) options.push_back(args[++i]);
    } else if (args[i] == "--help" || args[i] == "-h" || args[i].starts_with("--")) {
      options.push_back(args[i]);
    } else {
      files.push_back(args[i]);
    }
  }
  options.push_back(files.empty() ? std::string() : files.front());
  const SourceOptions source = source_options(parse_args(options, {"--from", "--dialect", "--scenario", "--map"}, {}, usage));
  int status = 0;
  for (const std::string& file : files) {
    const LoadedFile loaded = load(file, source);
    const scenario::LoadResult& result = loaded.result;
    print_errors(file, result.warnings, "warning: ", loaded.imported ? &*loaded.imported : nullptr);
    if (!result.model) {
      print_errors(file, loaded);
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
    if (last < first || last - first >= runs::kMaxSeedsPerRun) {
      usage_error("--seeds: A-B needs A <= B and at most " + std::to_string(runs::kMaxSeedsPerRun) + " seeds, got '" + text + "'");
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
  ~ScratchDatabase() {
    std::error_code ignored;
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix, ignored);
  }
};

}  // namespace

int run_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(
      args, {"--seed", "--seeds", "--db", "--max-time", "--request", "--from", "--dialect", "--scenario", "--map", "--trajectory", "--gate", "--junit", "--controller", "--jobs"},
      {"--events", "--baseline-without-robot"},
      "usage: hrisim run FILE [--seed N | --seeds A-B|A,B,C] [--gate EXPR ...] [--junit FILE.xml] [--db FILE] [--jobs N] "
      "[--controller JSON] [--baseline-without-robot] [--max-time S] [--events] [--request TIME:ROUTINE ...] [--from imhus|pedsim|hunav] [--scenario NAME] [--map FILE] "
      "[--trajectory FILE.csv]");
  const std::string& file = parsed.file;
  std::uint64_t single_seed = 0;
  if (const auto text = parsed.last("--seed")) {
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), single_seed);
    if (ec != std::errc() || end != text->data() + text->size()) usage_error("--seed: expected a whole number, got '" + *text + "'");
  }
  // A batch is a stored run with a report and a verdict; one plain episode prints its own summary.
  const bool batch = parsed.last("--seeds") || parsed.last("--db") || parsed.values.contains("--gate") || parsed.last("--junit");
  if (parsed.last("--seeds") && parsed.last("--seed")) usage_error("--seed and --seeds: give one of them");
  const std::vector<std::uint64_t> seeds = parsed.last("--seeds") ? parse_seeds(*parsed.last("--seeds")) : std::vector<std::uint64_t>{single_seed};

  runs::RunRequest request;
  request.seeds = seeds;
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
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  if (const auto text = parsed.last("--jobs")) {
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), jobs);
    if (ec != std::errc() || end != text->data() + text->size() || jobs == 0 || jobs > 256) usage_error("--jobs: expected 1 to 256, got '" + *text + "'");
  }

  const LoadedFile loaded = load(file, source_options(parsed));
  print_errors(file, loaded.result.warnings, "warning: ", loaded.imported ? &*loaded.imported : nullptr);
  if (!loaded.result.model) {
    print_errors(file, loaded);
    return 2;
  }
  request.document = loaded.document;
  request.load = loaded.load;
  request.scenario_sha256 = core::sha256_hex(loaded.text);
  request.scenario_id = "f" + request.scenario_sha256.substr(0, 32);  // one stored record per distinct file content
  const runs::RunSpec spec = [&] {
    try {
      return runs::make_run_spec(request);
    } catch (const core::Error& e) {
      for (const auto& error : e.details().value("errors", nlohmann::json::array())) {
        std::fprintf(stderr, "%s: %s\n", error["pointer"].get<std::string>().c_str(), error["message"].get<std::string>().c_str());
      }
      throw;
    }
  }();

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

  // With --db the run and its episodes are kept, each episode in one transaction as it ends.
  std::optional<ScratchDatabase> scratch;
  std::filesystem::path database;
  if (const auto path = parsed.last("--db")) {
    database = *path;
    if (const auto folder = database.parent_path(); !folder.empty()) std::filesystem::create_directories(folder);
  } else {
    database = scratch.emplace().path;
  }
  storage::Store store(database);
  // Runs of a process that was killed (this command's or a server's) are found out now.
  if (const int interrupted = store.interrupt_abandoned_runs(); interrupted > 0) {
    std::fprintf(stderr, "hrisim: %d run%s whose process ended marked interrupted\n", interrupted, interrupted == 1 ? "" : "s");
  }
  runs::RunSpec stored_spec = spec;
  if (!store.scenario(stored_spec.scenario_id)) {
    store.put_scenario({stored_spec.scenario_id, spec.model->name, std::string(scenario::to_string(loaded.format)), loaded.text, "", "", "", "", {}});
  }
  ProgressReport progress(seeds.size());
  runs::Executor executor(store, jobs, [&](const std::string&, const storage::EpisodeRecord& episode) { progress.episode_done(episode); });
  const storage::RunRecord run = executor.submit(std::move(stored_spec));
  executor.wait(run.id);
  const nlohmann::json report = runs::run_report(*store.run(run.id), store.episodes_of_run(run.id), {});
  if (const auto path = parsed.last("--junit")) {
    std::ofstream junit(*path);
    if (!junit) usage_error("--junit: cannot write " + *path);
    junit << runs::junit_xml(report);
  }
  nlohmann::json printed = report;
  if (scratch) printed.erase("id");  // the run was not kept
  std::printf("%s\n", printed.dump(2).c_str());
  const bool passed = report["verdict"]["passed"];
  for (const auto& reason : report["verdict"]["reasons"]) std::fprintf(stderr, "%s\n", reason.get<std::string>().c_str());
  std::fprintf(stderr, "%s: %zu episodes, verdict %s\n", spec.model->name.c_str(), seeds.size(), passed ? "PASSED" : "FAILED");
  return passed ? 0 : 1;
}

int render_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(args, {"--db", "--camera", "--out", "--fps", "--width", "--height", "--scenarios"}, {},
                                       "usage: hrisim render EPISODE --out FILE.mp4|FILE.webm|FILE.avi [--db FILE] [--camera overview] [--fps 25] "
                                       "[--width W] [--height H] [--scenarios DIR]");
  const auto out = parsed.last("--out");
  if (!out) usage_error("--out: the video file to write (.mp4, .webm or .avi) is required");
  const std::string camera_name = parsed.last("--camera").value_or(runs::kDefaultVideoCamera);
  const auto whole = [&](const char* option, int low, int high, int fallback) {
    const auto text = parsed.last(option);
    if (!text) return fallback;
    int value = 0;
    const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
    if (ec != std::errc() || end != text->data() + text->size() || value < low || value > high) {
      usage_error(std::string(option) + ": expected " + std::to_string(low) + " to " + std::to_string(high) + ", got '" + *text + "'");
    }
    return value;
  };
  const int fps = whole("--fps", 1, runs::kMaxVideoFps, runs::kDefaultVideoFps);
  const int width = whole("--width", 16, 4096, 0), height = whole("--height", 16, 4096, 0);

  const std::filesystem::path database = parsed.last("--db").value_or(kDefaultDatabase);
  if (!std::filesystem::exists(database)) usage_error("--db: no database " + database.string());
  storage::Store store(database);
  const auto episode = store.episode(parsed.file);
  if (!episode) throw core::Error(core::ErrorCode::not_found, "no episode '" + parsed.file + "' in " + database.string());
  const auto stored = store.scenario(episode->scenario_id);
  if (!stored) throw core::Error(core::ErrorCode::not_found, "the scenario of episode " + parsed.file + " is not stored");
  const nlohmann::json config = episode->run_id ? store.run(*episode->run_id).value_or(storage::RunRecord{}).config : nlohmann::json::object();

  // The episode again, exactly: same scenario, seed, controller, time limit and requests.
  scenario::SourceOptions source;
  source.load.map_search_path = {parsed.last("--scenarios").value_or(bundled_scenarios_dir())};
  const scenario::CompiledSource compiled = scenario::compile_source(stored->source, scenario::source_format(stored->format).value_or(scenario::SourceFormat::json), source);
  if (!compiled.model) throw core::Error(core::ErrorCode::internal, "the stored scenario of episode " + parsed.file + " no longer loads");
  const runs::RunSpec spec = runs::make_run_spec(runs::replay_request(compiled.document, source.load, config, episode->seed));

  const runs::VideoResult video = runs::render_episode_video(spec, *episode, *out, {camera_name, fps, width, height});
  if (!video.matches_stored_episode) {
    std::fprintf(stderr,
                 "hrisim: warning: the replay ended at tick %lld (%s, state %s), the stored episode at %lld (%s, state %s): another hrisim "
                 "version ran it\n",
                 static_cast<long long>(video.replay.ticks), video.replay.termination_reason.c_str(), video.replay.state_hash.c_str(),
                 static_cast<long long>(episode->ticks), episode->termination_reason.c_str(), episode->state_hash.c_str());
  }
  const nlohmann::json summary = {{"episode", parsed.file}, {"out", *out},         {"camera", camera_name},
                                  {"codec", video.codec},   {"frames", video.frames}, {"fps", video.fps},
                                  {"ticks", video.replay.ticks}, {"matches_stored_episode", video.matches_stored_episode}};
  std::printf("%s\n", summary.dump(2).c_str());
  return 0;
}

int import_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(args, {"--from", "--dialect", "--scenario", "--map"}, {},
                                       "usage: hrisim import [--from imhus|pedsim|hunav] [--dialect pedsim_ros|libpedsim] FILE [--scenario NAME] [--map FILE]");
  const std::string& file = parsed.file;
  const SourceOptions source = source_options(parsed);
  const auto text = read_text(file);
  if (!text) {
    std::fprintf(stderr, "%s: cannot read the file\n", file.c_str());
    return 1;
  }
  const scenario::SourceFormat format = file_format(file, *text, source);
  if (format == scenario::SourceFormat::json) usage_error(file + " is hrisim's own JSON: there is nothing to import (an IMHuS or Pedsim XML file, or a HuNavSim agents YAML, is)");
  const auto imported = import_file(file, *text, format, source);
  if (!imported) return 1;
  std::printf("%s\n", imported->scenario.dump(2).c_str());
  // The scenario written must also be one hrisim runs: what validation finds is an error of the import.
  scenario::LoadOptions load_options{{std::filesystem::path(file).parent_path(), bundled_scenarios_dir()}, {}};
  load_options.limits.confine_files = false;
  const scenario::LoadResult checked = scenario::load_scenario(nlohmann::json::parse(imported->scenario.dump()), load_options);
  print_errors(file, checked.warnings, "warning: ", &*imported);
  if (checked.model) return 0;
  print_errors(file, checked.errors, "", &*imported);
  std::fprintf(stderr, "%s: the imported scenario does not validate (%zu error%s)\n", file.c_str(), checked.errors.size(),
               checked.errors.size() == 1 ? "" : "s");
  return 1;
}

}  // namespace hrisim::app
