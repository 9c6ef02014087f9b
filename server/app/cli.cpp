#include "app/cli.hpp"

#include <charconv>
#include <limits>
#include <map>

#include "core/error.hpp"

namespace hrisim::app {
namespace {

struct Flag {
  const char* name;
  const char* env;
  const char* help;
  std::function<void(ServeOptions&, const std::string&)> apply;
};

std::uint64_t parse_unsigned(const std::string& where, const std::string& text, std::uint64_t min,
                             std::uint64_t max) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < min || value > max) {
    throw core::Error(core::ErrorCode::bad_request,
                      where + ": expected a whole number from " + std::to_string(min) + " to " + std::to_string(max) +
                          ", got '" + text + "'",
                      {{"option", where}, {"value", text}});
  }
  return value;
}

/// A comma-separated list, each item checked by `check`.
std::vector<std::string> comma_list(const std::string& text, const std::function<void(const std::string&)>& check) {
  std::vector<std::string> items;
  std::string_view rest(text);
  while (!rest.empty()) {
    const auto comma = rest.find(',');
    items.emplace_back(rest.substr(0, comma));
    check(items.back());
    rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
  }
  return items;
}

/// Rewords an error of a token as an error of the option it came from, without the token itself.
template <class Read>
auto token_option(const std::string& option, Read read) {
  try {
    return read();
  } catch (const core::Error& e) {
    throw core::Error(core::ErrorCode::bad_request, option + ": " + e.what(), {{"option", option}});
  }
}

const std::vector<Flag>& flags() {
  static const std::vector<Flag> kFlags = {
      {"host", "HRISIM_HOST", "IP address to listen on (default 127.0.0.1)",
       [](ServeOptions& o, const std::string& v) { o.server.host = v; }},
      {"port", "HRISIM_PORT", "TCP port, 0 for any free one (default 8080)",
       [](ServeOptions& o, const std::string& v) {
         o.server.port = static_cast<std::uint16_t>(parse_unsigned("--port", v, 0, 65535));
       }},
      {"db", "HRISIM_DB", "SQLite database file (default var/hrisim.db)",
       [](ServeOptions& o, const std::string& v) { o.database = v; }},
      {"scenarios", "HRISIM_SCENARIOS", "folder of bundled scenarios (default scenarios)",
       [](ServeOptions& o, const std::string& v) { o.scenarios = v; }},
      {"web", "HRISIM_WEB_ROOT", "folder of the browser UI (default web)",
       [](ServeOptions& o, const std::string& v) { o.web_root = v; }},
      {"threads", "HRISIM_THREADS", "I/O threads, 0 for one per core (default 0)",
       [](ServeOptions& o, const std::string& v) {
         o.server.threads = static_cast<unsigned>(parse_unsigned("--threads", v, 0, 256));
       }},
      {"max-connections", "HRISIM_MAX_CONNECTIONS", "open connections, WebSockets included, beyond which clients get 503 (default 256)",
       [](ServeOptions& o, const std::string& v) {
         o.server.max_connections = parse_unsigned("--max-connections", v, 1, 1'000'000);
       }},
      {"max-connections-per-client", "HRISIM_MAX_CONNECTIONS_PER_CLIENT",
       "open connections, WebSockets included, one client address may hold (default 64)",
       [](ServeOptions& o, const std::string& v) {
         o.server.max_connections_per_client = parse_unsigned("--max-connections-per-client", v, 1, 1'000'000);
       }},
      {"max-queued-answers", "HRISIM_MAX_QUEUED_ANSWERS", "WebSocket answers a client may leave unread before it is closed with 1008 (default 64)",
       [](ServeOptions& o, const std::string& v) { o.server.max_queued_answers = parse_unsigned("--max-queued-answers", v, 1, 1'000'000); }},
      {"max-queued-answer-bytes", "HRISIM_MAX_QUEUED_ANSWER_BYTES",
       "bytes of WebSocket answers a client may leave unread before it is closed with 1008 (default 67108864)",
       [](ServeOptions& o, const std::string& v) {
         o.server.max_queued_answer_bytes = parse_unsigned("--max-queued-answer-bytes", v, 1024, std::uint64_t{1} << 40);
       }},
      {"max-people", "HRISIM_MAX_PEOPLE", "humans and robots one scenario may hold (default 2000)",
       [](ServeOptions& o, const std::string& v) { o.scenario_limits.max_people = static_cast<int>(parse_unsigned("--max-people", v, 1, 1'000'000)); }},
      {"max-grid-cells", "HRISIM_MAX_GRID_CELLS", "cells of a scenario's grid map (default 16000000)",
       [](ServeOptions& o, const std::string& v) {
         o.scenario_limits.max_grid_cells = static_cast<std::int64_t>(parse_unsigned("--max-grid-cells", v, 1, std::uint64_t{1} << 40));
       }},
      {"max-episode-ticks", "HRISIM_MAX_EPISODE_TICKS",
       "ticks a session or a run's episode may last: its time limit (or max_time) over dt (default 216000)",
       [](ServeOptions& o, const std::string& v) {
         o.scenario_limits.max_episode_ticks = static_cast<std::int64_t>(parse_unsigned("--max-episode-ticks", v, 1, std::uint64_t{1} << 40));
       }},
      {"max-database-mb", "HRISIM_MAX_DATABASE_MB", "MiB the database file may grow to, 0 for as much as the disk holds (default 0)",
       [](ServeOptions& o, const std::string& v) { o.max_database_bytes = parse_unsigned("--max-database-mb", v, 0, 1 << 30) << 20; }},
      {"scenario-cache-mb", "HRISIM_SCENARIO_CACHE_MB", "MiB of compiled uploaded scenarios kept in memory (default 256)",
       [](ServeOptions& o, const std::string& v) { o.scenario_cache_bytes = parse_unsigned("--scenario-cache-mb", v, 1, 1 << 20) << 20; }},
      {"max-recording-mb", "HRISIM_MAX_RECORDING_MB",
       "MiB the recordings of all live sessions and of the runs' episodes in flight may hold together (default 1024)",
       [](ServeOptions& o, const std::string& v) { o.max_recording_bytes = parse_unsigned("--max-recording-mb", v, 1, 1 << 24) << 20; }},
      {"header-limit", "HRISIM_HEADER_LIMIT", "largest request header in bytes, else 431 (default 8192)",
       [](ServeOptions& o, const std::string& v) {
         o.server.header_limit = parse_unsigned("--header-limit", v, 1024, 1 << 20);
       }},
      {"body-limit", "HRISIM_BODY_LIMIT", "largest request body in bytes, else 413 (default 4194304)",
       [](ServeOptions& o, const std::string& v) {
         o.server.body_limit = parse_unsigned("--body-limit", v, 0, std::uint64_t{1} << 32);
       }},
      {"header-timeout", "HRISIM_HEADER_TIMEOUT", "seconds a request's header may take to arrive, else closed (default 10)",
       [](ServeOptions& o, const std::string& v) {
         o.server.header_timeout = std::chrono::seconds(parse_unsigned("--header-timeout", v, 1, 3600));
       }},
      {"read-timeout", "HRISIM_READ_TIMEOUT", "seconds a request's body may take to arrive after its header, else closed (default 30)",
       [](ServeOptions& o, const std::string& v) {
         o.server.read_timeout = std::chrono::seconds(parse_unsigned("--read-timeout", v, 1, 3600));
       }},
      {"log-requests", "HRISIM_LOG_REQUESTS", "1 to log each request to stderr, 0 not to (default 1)",
       [](ServeOptions& o, const std::string& v) { o.server.log_requests = parse_unsigned("--log-requests", v, 0, 1); }},
      {"max-sessions", "HRISIM_MAX_SESSIONS", "live sessions beyond which creating one gets 503 (default 8)",
       [](ServeOptions& o, const std::string& v) { o.sessions.max_sessions = static_cast<int>(parse_unsigned("--max-sessions", v, 1, 10000)); }},
      {"session-idle-timeout", "HRISIM_SESSION_IDLE_TIMEOUT", "seconds an unused session lives (default 600)",
       [](ServeOptions& o, const std::string& v) {
         o.sessions.idle_timeout = std::chrono::seconds(parse_unsigned("--session-idle-timeout", v, 1, 7 * 24 * 3600));
       }},
      {"workers", "HRISIM_WORKERS", "threads that step sessions, 0 for one per core (default 0)",
       [](ServeOptions& o, const std::string& v) { o.server.workers = static_cast<unsigned>(parse_unsigned("--workers", v, 0, 256)); }},
      {"crowd-threads", "HRISIM_CROWD_THREADS",
       "threads computing a live session's crowd of 256 people or more, the same trajectory on any number (default 1)",
       [](ServeOptions& o, const std::string& v) { o.sessions.crowd_threads = static_cast<unsigned>(parse_unsigned("--crowd-threads", v, 1, 64)); }},
      {"run-jobs", "HRISIM_RUN_JOBS", "episodes of runs computed at once, 0 for one per core (default 0)",
       [](ServeOptions& o, const std::string& v) { o.run_jobs = static_cast<unsigned>(parse_unsigned("--run-jobs", v, 0, 256)); }},
      {"allowed-origins", "HRISIM_ALLOWED_ORIGINS",
       "comma-separated browser origins (e.g. https://lab.example:8443) that may open WebSockets besides the server's own (default none)",
       [](ServeOptions& o, const std::string& v) {
         o.access.allowed_origins = comma_list(v, [](const std::string& origin) {
           if (!origin.starts_with("http://") && !origin.starts_with("https://")) {
             throw core::Error(core::ErrorCode::bad_request, "--allowed-origins: an origin is scheme://host[:port], got '" + origin + "'",
                               {{"option", "--allowed-origins"}});
           }
         });
       }},
      {"allowed-hosts", "HRISIM_ALLOWED_HOSTS",
       "comma-separated host names requests may name in Host besides IP addresses and localhost, * for any (default none)",
       [](ServeOptions& o, const std::string& v) {
         o.access.allowed_hosts = comma_list(v, [](const std::string& host) {
           if (host.empty() || host.find_first_of(" /:") != std::string::npos) {
             throw core::Error(core::ErrorCode::bad_request, "--allowed-hosts: a host name without port, got '" + host + "'", {{"option", "--allowed-hosts"}});
           }
         });
       }},
      {"token", "HRISIM_TOKEN",
       "a bearer token /api/ routes (but version) then require: SECRET (an admin without owner), or NAME:SECRET[:user|read|admin]; may be repeated",
       [](ServeOptions& o, const std::string& v) { o.access.tokens.push_back(token_option("--token", [&] { return http::parse_token(v); })); }},
      {"import", "HRISIM_IMPORT",
       "a database of runs (hrisim merge's, or a shard's) merged into --db at start, so its runs show in the browser; may be repeated",
       [](ServeOptions& o, const std::string& v) { o.imports.emplace_back(v); }},
      {"tokens", "HRISIM_TOKENS", "a file of tokens, one NAME:SECRET[:user|read|admin] per line (default none)",
       [](ServeOptions& o, const std::string& v) {
         for (http::Token& token : token_option("--tokens", [&] { return http::read_token_file(v); })) o.access.tokens.push_back(std::move(token));
       }},
  };
  return kFlags;
}

}  // namespace

ServeOptions parse_serve_options(const std::vector<std::string>& args, const EnvLookup& env) {
  ServeOptions options;
  std::map<std::string, std::vector<std::string>> given;  ///< every value of a flag, in order (--token repeats)
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (!arg.starts_with("--")) {
      throw core::Error(core::ErrorCode::bad_request, "unexpected argument '" + arg + "'", {{"argument", arg}});
    }
    std::string name = arg.substr(2), value;
    if (name == "allow-unauthenticated") {  // a switch: no value
      options.allow_unauthenticated = true;
      continue;
    }
    if (const auto eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1);
      name.resize(eq);
    } else if (i + 1 < args.size()) {
      value = args[++i];
    } else {
      throw core::Error(core::ErrorCode::bad_request, "option --" + name + " needs a value", {{"option", name}});
    }
    given[name].push_back(value);
  }
  for (const Flag& flag : flags()) {
    if (const auto found = given.find(flag.name); found != given.end()) {
      for (const std::string& value : found->second) flag.apply(options, value);
      given.erase(found);
    } else if (const auto value = env(flag.env)) {
      try {
        flag.apply(options, *value);
      } catch (const core::Error& e) {
        throw core::Error(core::ErrorCode::bad_request, std::string("environment variable ") + flag.env + ": " + e.what(),
                          {{"variable", flag.env}, {"value", *value}});
      }
    }
  }
  if (!given.empty()) {
    throw core::Error(core::ErrorCode::bad_request, "unknown option --" + given.begin()->first,
                      {{"option", given.begin()->first}});
  }
  if (const auto value = env("HRISIM_ALLOW_UNAUTHENTICATED")) options.allow_unauthenticated |= *value == "1";
  if (options.access.tokens.empty() && !options.allow_unauthenticated && !is_loopback(options.server.host)) {
    throw core::Error(core::ErrorCode::bad_request,
                      "refusing to listen on " + options.server.host +
                          " without a token: give --token (or HRISIM_TOKEN), or --allow-unauthenticated to serve anyone who can reach it",
                      {{"option", "--host"}});
  }
  return options;
}

bool is_loopback(const std::string& host) { return host == "localhost" || host == "::1" || host.starts_with("127."); }

std::string serve_usage() {
  std::string text = "usage: hrisim serve [options]\n\noptions (each also read from the variable named):\n";
  for (const Flag& flag : flags()) {
    text += "  --" + std::string(flag.name) + " VALUE";
    const std::size_t name_width = std::string(flag.name).size();
    text.append(name_width < 28 ? 30 - name_width : 2, ' ');
    text += std::string(flag.help) + "  [" + flag.env + "]\n";
  }
  text += "  --allow-unauthenticated            listen beyond loopback without a token  [HRISIM_ALLOW_UNAUTHENTICATED=1]\n";
  return text;
}

}  // namespace hrisim::app
