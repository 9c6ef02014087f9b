#include "app/cli.hpp"

#include <gtest/gtest.h>

#include <map>

#include "core/error.hpp"

namespace hrisim::app {
namespace {

EnvLookup env_of(std::map<std::string, std::string> values) {
  return [values](const std::string& name) -> std::optional<std::string> {
    const auto found = values.find(name);
    return found == values.end() ? std::nullopt : std::optional<std::string>(found->second);
  };
}

TEST(ServeOptions, Defaults) {
  const ServeOptions options = parse_serve_options({}, env_of({}));
  EXPECT_EQ(options.server.host, "127.0.0.1");
  EXPECT_EQ(options.server.port, 8080);
  EXPECT_EQ(options.database, "var/hrisim.db");
  EXPECT_EQ(options.scenarios, "scenarios");
  EXPECT_EQ(options.web_root, "web");
  EXPECT_EQ(options.server.header_limit, 8u * 1024);
  EXPECT_EQ(options.server.body_limit, 4u * 1024 * 1024);
  EXPECT_EQ(options.server.read_timeout, std::chrono::seconds(30));
  EXPECT_EQ(options.server.header_timeout, std::chrono::seconds(10));
}

TEST(ServeOptions, FlagsBeatEnvironmentWhichBeatsDefaults) {
  const ServeOptions options = parse_serve_options(
      {"--port", "9000", "--db=/tmp/x.db"},
      env_of({{"HRISIM_PORT", "7000"}, {"HRISIM_HOST", "0.0.0.0"}, {"HRISIM_TOKEN", "0123456789abcdef"}}));
  EXPECT_EQ(options.server.port, 9000);
  EXPECT_EQ(options.server.host, "0.0.0.0");
  EXPECT_EQ(options.database, "/tmp/x.db");
}

TEST(ServeOptions, LimitsAreSettable) {
  const ServeOptions options = parse_serve_options(
      {"--header-limit", "16384", "--body-limit", "1024", "--read-timeout", "2", "--max-connections", "3"},
      env_of({{"HRISIM_HEADER_TIMEOUT", "4"}}));
  EXPECT_EQ(options.server.header_limit, 16384u);
  EXPECT_EQ(options.server.body_limit, 1024u);
  EXPECT_EQ(options.server.read_timeout, std::chrono::seconds(2));
  EXPECT_EQ(options.server.max_connections, 3u);
  EXPECT_EQ(options.server.header_timeout, std::chrono::seconds(4));
}

void expect_error_mentions(const std::vector<std::string>& args, const std::map<std::string, std::string>& env,
                           const std::string& needle) {
  try {
    parse_serve_options(args, env_of(env));
    FAIL() << "expected an error mentioning " << needle;
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::bad_request);
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(ServeOptions, BadValuesSayWhichOptionAndWhy) {
  expect_error_mentions({"--port", "70000"}, {}, "--port");
  expect_error_mentions({"--port", "80x"}, {}, "'80x'");
  expect_error_mentions({"--read-timeout", "0"}, {}, "--read-timeout");
  expect_error_mentions({"--header-timeout", "0"}, {}, "--header-timeout");
  expect_error_mentions({}, {{"HRISIM_PORT", "-1"}}, "HRISIM_PORT");
  expect_error_mentions({"--colour", "red"}, {}, "--colour");
  expect_error_mentions({"--db"}, {}, "needs a value");
  expect_error_mentions({"serve"}, {}, "unexpected argument");
}

TEST(ServeOptions, BeyondLoopbackOnlyWithATokenOrWhenToldSo) {
  expect_error_mentions({"--host", "0.0.0.0"}, {}, "without a token");
  EXPECT_EQ(parse_serve_options({"--host", "0.0.0.0", "--token", "0123456789abcdef"}, env_of({})).access.tokens.at(0).secret, "0123456789abcdef");
  EXPECT_TRUE(parse_serve_options({"--host", "0.0.0.0", "--allow-unauthenticated"}, env_of({})).allow_unauthenticated);
  EXPECT_TRUE(parse_serve_options({"--host", "10.0.0.5"}, env_of({{"HRISIM_ALLOW_UNAUTHENTICATED", "1"}})).allow_unauthenticated);
  for (const char* loopback : {"127.0.0.1", "127.0.1.1", "::1", "localhost"}) {
    EXPECT_NO_THROW(parse_serve_options({"--host", loopback}, env_of({}))) << loopback;
  }
  expect_error_mentions({"--token", "short"}, {}, "--token: a token's secret needs at least 16");
  expect_error_mentions({"--token", "alice:0123456789abcdef:owner"}, {}, "role is user, read or admin");
  expect_error_mentions({"--token", "a b:0123456789abcdef"}, {}, "a token's name");
  const ServeOptions named = parse_serve_options({"--token", "alice:0123456789abcdef", "--token", "dash:fedcba9876543210:read"}, env_of({}));
  ASSERT_EQ(named.access.tokens.size(), 2u) << "--token repeats";
  EXPECT_EQ(named.access.tokens[0].name, "alice");
  EXPECT_EQ(named.access.tokens[0].role, http::Role::user);
  EXPECT_EQ(named.access.tokens[1].role, http::Role::read);
  expect_error_mentions({}, {{"HRISIM_TOKEN", "short"}}, "HRISIM_TOKEN");
}

TEST(ServeOptions, UsageListsEveryVariable) {
  const std::string usage = serve_usage();
  for (const char* variable : {"HRISIM_HOST", "HRISIM_PORT", "HRISIM_DB", "HRISIM_SCENARIOS", "HRISIM_WEB_ROOT", "HRISIM_TOKEN",
                               "HRISIM_TOKENS", "HRISIM_ALLOWED_HOSTS", "HRISIM_MAX_CONNECTIONS_PER_CLIENT", "HRISIM_MAX_QUEUED_ANSWERS",
                               "HRISIM_MAX_PEOPLE", "HRISIM_MAX_GRID_CELLS", "HRISIM_MAX_EPISODE_TICKS", "HRISIM_SCENARIO_CACHE_MB",
                               "HRISIM_ALLOW_UNAUTHENTICATED"}) {
    EXPECT_NE(usage.find(variable), std::string::npos) << variable;
  }
}

}  // namespace
}  // namespace hrisim::app
