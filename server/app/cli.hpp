#pragma once
// Command-line options of `hrisim serve`: flags, then HRISIM_* environment variables, then defaults.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "http/access.hpp"
#include "http/scenario_catalogue.hpp"
#include "http/server.hpp"
#include "http/session_limits.hpp"
#include "scenario/load.hpp"

namespace hrisim::app {

inline constexpr const char* kDefaultDatabase = "var/hrisim.db";
inline constexpr const char* kDefaultScenarios = "scenarios";
inline constexpr const char* kDefaultWebRoot = "web";

struct ServeOptions {
  http::ServerOptions server;
  std::filesystem::path database = kDefaultDatabase;
  std::uint64_t max_database_bytes = 0;  ///< 0: as large as the disk allows
  std::filesystem::path scenarios = kDefaultScenarios;
  std::filesystem::path web_root = kDefaultWebRoot;
  live::SessionLimits sessions;
  unsigned run_jobs = 0;               ///< episodes of runs at once, 0 for one per core
  http::AccessPolicy access;           ///< tokens (from --token and --tokens), allowed origins and hosts
  scenario::ScenarioLimits scenario_limits;
  std::size_t scenario_cache_bytes = http::kDefaultScenarioCacheBytes;
  std::size_t max_recording_bytes = http::kDefaultMaxRecordingBytes;  ///< every session's and run's recording together
  bool allow_unauthenticated = false;  ///< listen beyond loopback without a token
  /// Databases of runs (hrisim merge's, a shard's, another machine's) merged into `database` at start.
  std::vector<std::filesystem::path> imports;
};

/// Whether a host address only accepts connections from this machine.
bool is_loopback(const std::string& host);

/// Reads an environment variable; empty optional when unset.
using EnvLookup = std::function<std::optional<std::string>(const std::string&)>;

/// Parses the arguments after `serve`. Throws core::Error(bad_request) naming the flag or variable
/// and what is wrong with its value.
ServeOptions parse_serve_options(const std::vector<std::string>& args, const EnvLookup& env);

/// Help text of `hrisim serve`, listing every flag with its variable and default.
std::string serve_usage();

}  // namespace hrisim::app
