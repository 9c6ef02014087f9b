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

/// Shortest bearer token accepted: guessing 16 random characters is out of reach.
constexpr std::size_t kMinimumTokenLength = 16;

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
      {"max-connections", "HRISIM_MAX_CONNECTIONS", "open connections beyond which clients get 503 (default 256)",
       [](ServeOptions& o, const std::string& v) {
         o.server.max_connections = parse_unsigned("--max-connections", v, 1, 1'000'000);
       }},
      {"header-limit", "HRISIM_HEADER_LIMIT", "largest request header in bytes, else 431 (default 8192)",
       [](ServeOptions& o, const std::string& v) {
         o.server.header_limit = parse_unsigned("--header-limit", v, 1024, 1 << 20);
       }},
      {"body-limit", "HRISIM_BODY_LIMIT", "largest request body in bytes, else 413 (default 4194304)",
       [](ServeOptions& o, const std::string& v) {
         o.server.body_limit = parse_unsigned("--body-limit", v, 0, std::uint64_t{1} << 32);
       }},
      {"read-timeout", "HRISIM_READ_TIMEOUT", "seconds a request may take to arrive, else closed (default 30)",
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
      {"run-jobs", "HRISIM_RUN_JOBS", "episodes of runs computed at once, 0 for one per core (default 0)",
       [](ServeOptions& o, const std::string& v) { o.run_jobs = static_cast<unsigned>(parse_unsigned("--run-jobs", v, 0, 256)); }},
      {"allowed-origins", "HRISIM_ALLOWED_ORIGINS",
       "comma-separated browser origins (e.g. https://lab.example:8443) that may open WebSockets besides the server's own (default none)",
       [](ServeOptions& o, const std::string& v) {
         o.allowed_origins.clear();
         std::string_view rest(v);
         while (!rest.empty()) {
           const auto comma = rest.find(',');
           const std::string_view origin = rest.substr(0, comma);
           if (!origin.starts_with("http://") && !origin.starts_with("https://")) {
             throw core::Error(core::ErrorCode::bad_request, "--allowed-origins: an origin is scheme://host[:port], got '" + std::string(origin) + "'",
                               {{"option", "--allowed-origins"}});
           }
           o.allowed_origins.emplace_back(origin);
           rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
         }
       }},
      {"token", "HRISIM_TOKEN", "bearer token every /api/ route but version then requires (default none)",
       [](ServeOptions& o, const std::string& v) {
         if (v.size() < kMinimumTokenLength) {
           throw core::Error(core::ErrorCode::bad_request, "--token: at least " + std::to_string(kMinimumTokenLength) + " characters",
                             {{"option", "--token"}});
         }
         o.token = v;
       }},
  };
  return kFlags;
}

}  // namespace

ServeOptions parse_serve_options(const std::vector<std::string>& args, const EnvLookup& env) {
  ServeOptions options;
  std::map<std::string, std::string> given;
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
    given[name] = value;
  }
  for (const Flag& flag : flags()) {
    if (const auto found = given.find(flag.name); found != given.end()) {
      flag.apply(options, found->second);
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
  if (options.token.empty() && !options.allow_unauthenticated && !is_loopback(options.server.host)) {
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
    text.append(std::max<std::size_t>(2, 22 - std::string(flag.name).size()), ' ');
    text += std::string(flag.help) + "  [" + flag.env + "]\n";
  }
  text += "  --allow-unauthenticated      listen beyond loopback without a token  [HRISIM_ALLOW_UNAUTHENTICATED=1]\n";
  return text;
}

}  // namespace hrisim::app
