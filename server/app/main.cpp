// hrisim — simulation service for testing robots among people. Entry point and subcommands.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "app/cli.hpp"
#include "app/run_commands.hpp"
#include "runs/merge.hpp"
#include "app/scenario_commands.hpp"
#include "app/trajectory_commands.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/memory_budget.hpp"
#include "http/api.hpp"
#include "http/scenario_catalogue.hpp"
#include "metrics/definitions.hpp"
#include "runs/executor.hpp"
#include "storage/store.hpp"

namespace {

constexpr const char* kUsage =
    "usage: hrisim <command> [options]\n\n"
    "commands:\n"
    "  serve     start the HTTP/WebSocket server and browser UI (hrisim serve --help)\n"
    "  validate  check scenario files: hrisim validate FILE... [--from imhus|pedsim|hunav] [--dialect D] [--scenario NAME] [--map FILE]\n"
    "  run       run a scenario headless: one episode prints its summary; a run of several\n"
    "            seeds prints its report and exits 1 when a gate fails:\n"
    "            hrisim run FILE [--seed N | --seeds A-B|A,B,C] [--gate EXPR ...] [--junit FILE.xml]\n"
    "                       [--db FILE] [--jobs N] [--controller JSON] [--max-time S] [--events]\n"
    "                       [--request TIME:ROUTINE ...] [--from imhus|pedsim|hunav] [--dialect pedsim_ros|libpedsim]\n"
    "                       [--scenario NAME] [--map FILE]\n"
    "                       [--trajectory FILE.csv] [--name NAME] [--shard K/N|auto|auto/N]\n"
    "            (FILE: native JSON, IMHuS or Pedsim XML; --shard runs the K-th of N parts into --db)\n"
    "  sweep     run every scenario x controller of a sweep file (JSON) over its seeds, or a shard of it:\n"
    "            hrisim sweep SWEEP.json [--db FILE] [--jobs N] [--shard K/N|auto|auto/N]\n"
    "  merge     merge shards' databases into one and print the runs' reports:\n"
    "            hrisim merge SHARD.db... --into RESULTS.db [--junit FILE.xml]\n"
    "  import    convert IMHuS or Pedsim XML to the native JSON on stdout:\n"
    "            hrisim import [--from imhus|pedsim|hunav] [--dialect pedsim_ros|libpedsim] FILE [--scenario NAME] [--map FILE]\n"
    "            or rename the former keys of a hrisim scenario (on stdout, or into the file):\n"
    "            hrisim import --upgrade FILE [--in-place]\n"
    "  render    replay a stored episode to a video:\n"
    "            hrisim render EPISODE --out FILE.mp4|.webm|.avi [--db FILE] [--camera overview|follow|ROBOT.SENSOR]\n"
    "                          [--fps 25] [--width W] [--height H]\n"
    "  trajectories  predict recorded pedestrians (ETH/UCY's four columns) by constant velocity, ORCA\n"
    "            and social force; prints ADE and FDE: hrisim trajectories FILE [--json]\n"
    "  metrics   print the metrics reference (docs/metrics.md) as Markdown\n"
    "  version   print build and library versions as JSON\n"
    "  help      print this text\n";

int serve(const std::vector<std::string>& args) {
  for (const std::string& arg : args) {
    if (arg == "--help" || arg == "-h") {
      std::fputs(hrisim::app::serve_usage().c_str(), stdout);
      return 0;
    }
  }
  const hrisim::app::ServeOptions options =
      hrisim::app::parse_serve_options(args, [](const std::string& name) -> std::optional<std::string> {
        const char* value = std::getenv(name.c_str());
        return value ? std::optional<std::string>(value) : std::nullopt;
      });
  if (!std::filesystem::is_directory(options.scenarios)) {
    throw hrisim::core::Error(hrisim::core::ErrorCode::bad_request,
                              "scenario folder " + options.scenarios.string() + " does not exist");
  }
  if (!std::filesystem::is_directory(options.web_root)) {
    throw hrisim::core::Error(hrisim::core::ErrorCode::bad_request,
                              "web folder " + options.web_root.string() + " does not exist");
  }

  hrisim::storage::Store store(options.database);
  if (options.max_database_bytes > 0) store.limit_size(options.max_database_bytes);
  // Runs that were under way when the last server stopped lost their episodes in flight.
  if (const int interrupted = store.interrupt_abandoned_runs(); interrupted > 0) {
    std::fprintf(stderr, "hrisim: %d run%s whose process ended marked interrupted\n", interrupted, interrupted == 1 ? "" : "s");
  }
  // What a killed server left in the temporary folder: imports' copies and uploads' files.
  const int abandoned = hrisim::storage::ForeignDatabase::remove_abandoned_copies() +
                        hrisim::core::remove_folders_of_ended_processes(hrisim::http::kFilesFolderPrefix);
  if (abandoned > 0) std::fprintf(stderr, "hrisim: removed %d temporary folder%s of ended processes\n", abandoned, abandoned == 1 ? "" : "s");
  for (const std::filesystem::path& file : options.imports) {
    if (!std::filesystem::is_regular_file(file)) throw hrisim::core::Error(hrisim::core::ErrorCode::bad_request, "--import: no database " + file.string());
    hrisim::storage::ForeignDatabase source = hrisim::storage::ForeignDatabase::from_file(file, file.string());
    for (const hrisim::runs::MergedRun& merged : hrisim::runs::merge_database(store, source, options.database.string())) {
      std::printf("hrisim: imported run %s from %s: %d episode%s added, %d already here\n", merged.id.c_str(), file.c_str(), merged.added,
                   merged.added == 1 ? "" : "s", merged.present);
    }
  }
  // One budget for every recording: live sessions and the runs' episodes in flight.
  hrisim::core::MemoryBudget recording_memory(options.max_recording_bytes);
  hrisim::runs::Executor executor(store, options.run_jobs ? options.run_jobs : std::max(1u, std::thread::hardware_concurrency()), nullptr,
                                  &recording_memory);
  hrisim::live::SessionLimits session_limits = options.sessions;
  session_limits.recording_memory = &recording_memory;
  if (options.access.tokens.empty() && !hrisim::app::is_loopback(options.server.host)) {
    std::fprintf(stderr, "hrisim: warning: listening on %s without a token: anyone who can reach it controls the simulator\n",
                 options.server.host.c_str());
  }
  const auto router = hrisim::http::make_api_router({&store, options.web_root, options.scenarios, options.access, session_limits, &executor,
                                                     options.scenario_limits, options.scenario_cache_bytes, {}});
  hrisim::http::Server server(options.server, router);
  std::printf("hrisim %s listening on http://%s:%u (database %s, schema version %d)\n",
              hrisim::http::version_info()["version"].get<std::string>().c_str(), options.server.host.c_str(),
              static_cast<unsigned>(server.port()), options.database.c_str(), store.schema_version());
  std::fflush(stdout);
  server.run();
  std::printf("hrisim stopped\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + (argc > 1 ? 2 : argc), argv + argc);
  const std::string command = argc > 1 ? argv[1] : "help";
  try {
    if (command == "serve") return serve(args);
    if (command == "validate") return hrisim::app::validate_command(args);
    if (command == "run") return hrisim::app::run_command(args);
    if (command == "sweep") return hrisim::app::sweep_command(args);
    if (command == "merge") return hrisim::app::merge_command(args);
    if (command == "import") return hrisim::app::import_command(args);
    if (command == "render") return hrisim::app::render_command(args);
    if (command == "trajectories") return hrisim::app::trajectories_command(args);
    if (command == "metrics") {
      std::fputs(hrisim::metrics::reference_markdown().c_str(), stdout);
      return 0;
    }
    if (command == "version" || command == "--version") {
      std::printf("%s\n", hrisim::http::version_info().dump(2).c_str());
      return 0;
    }
    if (command == "help" || command == "--help" || command == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    std::fprintf(stderr, "hrisim: unknown command '%s'\n\n%s", command.c_str(), kUsage);
    return 2;
  } catch (const hrisim::core::Error& e) {
    std::fprintf(stderr, "hrisim: %s\n", e.what());
    return e.code() == hrisim::core::ErrorCode::bad_request ? 2 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrisim: %s\n", e.what());
    return 1;
  }
}
