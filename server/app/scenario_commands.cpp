#include "app/scenario_commands.hpp"

#include <charconv>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "app/cli.hpp"
#include "app/command_line.hpp"
#include "core/error.hpp"
#include "runs/spec.hpp"
#include "runs/video.hpp"
#include "scenario/former_keys.hpp"
#include "storage/store.hpp"

namespace hrisim::app {

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

namespace {

/// hrisim import --upgrade FILE [--in-place]: the former keys of a scenario renamed, every other byte kept.
int upgrade_command(const ParsedArgs& parsed) {
  const std::string& file = parsed.file;
  const bool in_place = parsed.flags.contains("--in-place");
  const auto text = read_text(file);
  if (!text) {
    std::fprintf(stderr, "%s: cannot read the file\n", file.c_str());
    return 1;
  }
  if (file_format(file, *text, {}) != scenario::SourceFormat::json) {
    usage_error(file + " is not hrisim's JSON: --upgrade renames the former keys of a hrisim scenario (import this file without it)");
  }
  nlohmann::json document;
  try {
    document = scenario::parse_scenario_json(*text);
  } catch (const core::Error& e) {
    std::fprintf(stderr, "%s: %s\n", file.c_str(), e.what());
    return 1;
  }
  if (!document.is_object()) {
    std::fprintf(stderr, "%s: not a scenario: a scenario is a JSON object\n", file.c_str());
    return 1;
  }
  const std::vector<scenario::FormerKey> former = scenario::find_former_keys(document);
  std::vector<core::ValidationError> both;
  for (const scenario::FormerKey& key : former) {
    if (key.current_too) both.push_back(scenario::former_key_issue(key));
  }
  if (!both.empty()) {
    print_errors(file, both);
    std::fprintf(stderr, "%s: not upgraded: the file has a key under both its names\n", file.c_str());
    return 1;
  }
  if (former.empty()) {
    std::fprintf(stderr, "%s: already uses the current keys: nothing to upgrade\n", file.c_str());
    if (!in_place) std::fwrite(text->data(), 1, text->size(), stdout);  // a pipe still gets the scenario
    return 0;
  }
  const std::string upgraded = scenario::rename_former_keys(*text, former);
  for (const scenario::FormerKey& key : former) {
    std::fprintf(stderr, "%s: %s: '%s' renamed '%s'\n", file.c_str(), key.pointer().c_str(), key.former.c_str(), key.current.c_str());
  }
  if (!in_place) {
    std::fwrite(upgraded.data(), 1, upgraded.size(), stdout);
    return 0;
  }
  // Written through the file itself, so that its permissions and links stay as they were.
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << upgraded;
  out.close();
  if (!out) {
    std::fprintf(stderr, "%s: cannot write the file\n", file.c_str());
    return 1;
  }
  std::fprintf(stderr, "%s: upgraded in place (%zu key%s renamed)\n", file.c_str(), former.size(), former.size() == 1 ? "" : "s");
  return 0;
}

}  // namespace

int import_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed = parse_args(args, {"--from", "--dialect", "--scenario", "--map"}, {"--upgrade", "--in-place"},
                                       "usage: hrisim import [--from imhus|pedsim|hunav] [--dialect pedsim_ros|libpedsim] FILE [--scenario NAME] [--map FILE]\n"
                                       "       hrisim import --upgrade FILE [--in-place]");
  if (parsed.flags.contains("--upgrade")) {
    if (!parsed.values.empty()) usage_error("--upgrade renames the former keys of a hrisim scenario: it takes no " + parsed.values.begin()->first);
    return upgrade_command(parsed);
  }
  if (parsed.flags.contains("--in-place")) usage_error("--in-place belongs with --upgrade: an import is written to stdout");
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
