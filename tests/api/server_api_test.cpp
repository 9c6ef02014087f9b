// API tests against the real `hrisim serve` binary on a loopback port with a temporary database.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "test_server.hpp"

namespace hrisim::testing {
namespace {

nlohmann::json json_of(const HttpReply& reply) { return nlohmann::json::parse(reply.body); }

class ServerApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new TestServer(); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static TestServer* server_;
};
TestServer* ServerApi::server_ = nullptr;

TEST_F(ServerApi, HealthReportsServerAndDatabase) {
  const HttpReply reply = http(port(), "GET", "/healthz");
  EXPECT_EQ(reply.status, 200);
  EXPECT_EQ(reply.headers.at("content-type"), "application/json");
  EXPECT_EQ(json_of(reply)["status"], "ok");
  EXPECT_EQ(json_of(reply)["database"], "ok");
  EXPECT_TRUE(std::filesystem::exists(server_->database())) << "the database file is created at start";
}

TEST_F(ServerApi, VersionNamesBuildAndLibraries) {
  const nlohmann::json version = json_of(http(port(), "GET", "/api/v1/version"));
  EXPECT_EQ(version["name"], "hrisim");
  EXPECT_FALSE(version["version"].get<std::string>().empty());
  EXPECT_FALSE(version["git_commit"].get<std::string>().empty());
  EXPECT_TRUE(version["compiler"].is_string());
  for (const char* library : {"boost", "eigen", "nlohmann_json", "sqlite"}) {
    ASSERT_TRUE(version["libraries"].contains(library)) << library;
    EXPECT_NE(version["libraries"][library].get<std::string>().find('.'), std::string::npos) << library;
  }
}

TEST_F(ServerApi, OpenApiDescriptionIsServed) {
  const HttpReply reply = http(port(), "GET", "/api/v1/openapi.yaml");
  EXPECT_EQ(reply.status, 200);
  EXPECT_EQ(reply.headers.at("content-type"), "application/yaml");
  EXPECT_NE(reply.body.find("openapi: 3"), std::string::npos);
  EXPECT_NE(reply.body.find("/healthz"), std::string::npos);
  // The same description as JSON, for tools that do not read YAML.
  const HttpReply json_reply = http(port(), "GET", "/api/v1/openapi.json");
  EXPECT_EQ(json_reply.status, 200);
  EXPECT_EQ(json_reply.headers.at("content-type"), "application/json");
  const nlohmann::json description = json_of(json_reply);
  EXPECT_TRUE(description["openapi"].get<std::string>().starts_with("3.1"));
  EXPECT_TRUE(description["paths"].contains("/api/v1/runs"));
  EXPECT_TRUE(description["paths"].contains("/healthz"));
}

TEST_F(ServerApi, BuiltInRobotsAreListedAndDescribed) {
  const nlohmann::json list = json_of(http(port(), "GET", "/api/v1/robots"));
  ASSERT_EQ(list["items"].size(), 3u);
  EXPECT_EQ(list["items"][1]["name"], "hsr");
  EXPECT_EQ(list["items"][1]["footprint_radius"], 0.215);
  EXPECT_EQ(list["items"][1]["drive"]["wheel_separation"], 0.266);
  EXPECT_EQ(list["items"][1]["groups"]["arm"].size(), 6u);
  EXPECT_TRUE(list["items"][2]["drive"].is_null()) << "ROMAN stands on a fixed stand";
  const HttpReply hsr = http(port(), "GET", "/api/v1/robots/hsr");
  EXPECT_EQ(hsr.status, 200);
  EXPECT_EQ(json_of(hsr)["description"]["drive"]["wheel_radius"], 0.04);
  const HttpReply unknown = http(port(), "GET", "/api/v1/robots/r2d2");
  EXPECT_EQ(unknown.status, 404);
  EXPECT_EQ(json_of(unknown)["error"]["code"], "not_found");
  EXPECT_EQ(json_of(unknown)["error"]["details"]["name"], "r2d2");
}

TEST_F(ServerApi, StaticPageWithContentType) {
  const HttpReply page = http(port(), "GET", "/");
  EXPECT_EQ(page.status, 200);
  EXPECT_EQ(page.headers.at("content-type"), "text/html; charset=utf-8");
  EXPECT_NE(page.body.find("hrisim"), std::string::npos);
  const HttpReply style = http(port(), "GET", "/style.css");
  EXPECT_EQ(style.status, 200);
  EXPECT_EQ(style.headers.at("content-type"), "text/css; charset=utf-8");
}

TEST_F(ServerApi, HeadHasLengthButNoBody) {
  const HttpReply get = http(port(), "GET", "/");
  const HttpReply head = http(port(), "HEAD", "/");
  EXPECT_EQ(head.status, 200);
  EXPECT_EQ(head.headers.at("content-length"), std::to_string(get.body.size()));
  EXPECT_TRUE(head.body.empty());
}

TEST_F(ServerApi, UnknownPathsAreJson404) {
  for (const char* path : {"/api/v1/nope", "/nope.html", "/api"}) {
    const HttpReply reply = http(port(), "GET", path);
    EXPECT_EQ(reply.status, 404) << path;
    EXPECT_EQ(json_of(reply)["error"]["code"], "not_found") << path;
    EXPECT_FALSE(json_of(reply)["error"]["message"].get<std::string>().empty());
  }
}

TEST_F(ServerApi, WrongMethodIs405WithAllow) {
  const HttpReply reply = http(port(), "POST", "/healthz", "{}");
  EXPECT_EQ(reply.status, 405);
  EXPECT_EQ(reply.headers.at("allow"), "GET");
  EXPECT_EQ(json_of(reply)["error"]["code"], "method_not_allowed");
}

TEST_F(ServerApi, OversizedBodyIs413BeforeItIsRead) {
  RawConnection connection(port());
  const std::size_t announced = 5u * 1024 * 1024;
  connection.send("POST /api/v1/version HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: " +
                  std::to_string(announced) + "\r\n\r\n" + std::string(64 * 1024, 'x'));
  const HttpReply reply = connection.read_reply();
  EXPECT_EQ(reply.status, 413);
  EXPECT_EQ(json_of(reply)["error"]["code"], "payload_too_large");
  EXPECT_EQ(json_of(reply)["error"]["details"]["limit_bytes"], 4 * 1024 * 1024);
}

TEST_F(ServerApi, OversizedHeadersAre431) {
  const HttpReply reply = http(port(), "GET", "/healthz", "", "X-Padding: " + std::string(10 * 1024, 'a') + "\r\n");
  EXPECT_EQ(reply.status, 431);
  EXPECT_EQ(json_of(reply)["error"]["code"], "headers_too_large");
}

TEST_F(ServerApi, PathTraversalIsRefused) {
  for (const char* target : {"/../CMakeLists.txt", "/%2e%2e/CMakeLists.txt", "/..%2fCMakeLists.txt",
                             "/static/../../README.md"}) {
    const HttpReply reply = http(port(), "GET", target);
    EXPECT_EQ(reply.status, 400) << target;
    EXPECT_EQ(reply.body.find("cmake_minimum_required"), std::string::npos) << target;
    EXPECT_EQ(json_of(reply)["error"]["code"], "bad_request") << target;
  }
}

TEST_F(ServerApi, ExpectContinueGetsAnInterimReply) {
  RawConnection connection(port());
  connection.send("POST /api/v1/version HTTP/1.1\r\nHost: 127.0.0.1\r\nExpect: 100-continue\r\nContent-Length: 2\r\n\r\n");
  EXPECT_EQ(connection.read_reply().status, 100);
  connection.send("{}");
  EXPECT_EQ(connection.read_reply().status, 405);
}

TEST_F(ServerApi, MalformedRequestIs400) {
  RawConnection connection(port());
  connection.send("THIS IS NOT HTTP\r\n\r\n");
  const HttpReply reply = connection.read_reply();
  EXPECT_EQ(reply.status, 400);
  EXPECT_EQ(json_of(reply)["error"]["code"], "bad_request");
}

TEST_F(ServerApi, KeepAliveServesSeveralRequests) {
  RawConnection connection(port());
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(connection.send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
    EXPECT_EQ(connection.read_reply().status, 200);
  }
}

TEST(ServerLimits, SlowClientIsClosed) {
  TestServer server({"--read-timeout", "2"});
  RawConnection connection(server.port(), std::chrono::milliseconds(200));
  const std::string request = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  // One byte per second: the whole request would need over 40 s; the server gives it 2.
  bool closed = false;
  for (std::size_t i = 0; i < request.size() && !closed; ++i) {
    if (!connection.send(request.substr(i, 1))) {
      closed = true;
      break;
    }
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (!closed && std::chrono::steady_clock::now() < until) {
      try {
        closed = connection.closed_by_peer();
      } catch (...) {
      }
    }
  }
  EXPECT_TRUE(closed) << "the trickling client was never disconnected";
}

TEST(ServerLimits, ConnectionsBeyondTheMaximumGet503) {
  TestServer server({"--max-connections", "2"});
  RawConnection first(server.port()), second(server.port());
  // Make sure both are admitted before the third arrives, and both busy: each sends a request's header
  // and then its body slowly (a connection waiting for a header would give its place up).
  first.send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  second.send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  ASSERT_EQ(first.read_reply().status, 200);
  ASSERT_EQ(second.read_reply().status, 200);
  for (RawConnection* busy : {&first, &second}) busy->send("POST /api/v1/scenarios/validate HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{");
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  RawConnection third(server.port());
  const HttpReply reply = third.read_reply();
  EXPECT_EQ(reply.status, 503);
  EXPECT_EQ(json_of(reply)["error"]["code"], "unavailable");
}

TEST(ServerLifecycle, SigtermClosesIdleConnectionsAndTheDatabaseCleanly) {
  TestServer server;
  RawConnection idle(server.port());
  idle.send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  ASSERT_EQ(idle.read_reply().status, 200);  // kept alive, now idle
  // Without the graceful close of idle connections this would wait for the 30 s read timeout.
  EXPECT_EQ(server.terminate(std::chrono::seconds(10)), 0);
  EXPECT_NE(server.output().find("hrisim stopped"), std::string::npos);
  EXPECT_TRUE(idle.closed_by_peer());
  // A clean close checkpoints the write-ahead log and removes it.
  EXPECT_FALSE(std::filesystem::exists(server.database().string() + "-wal"));
}

TEST(ServerAuth, TokenGuardsTheApiButNotHealthVersionOrTheUi) {
  TestServer server({"--token", "s3cret-token-0123456789"});
  const std::uint16_t port = server.port();
  EXPECT_EQ(http(port, "GET", "/healthz").status, 200);
  EXPECT_EQ(http(port, "GET", "/api/v1/version").status, 200);
  EXPECT_EQ(http(port, "GET", "/").status, 200);
  const HttpReply missing = http(port, "GET", "/api/v1/robots");
  EXPECT_EQ(missing.status, 401);
  EXPECT_EQ(json_of(missing)["error"]["code"], "unauthorized");
  EXPECT_EQ(missing.headers.at("www-authenticate"), "Bearer realm=\"hrisim\"");
  EXPECT_EQ(http(port, "GET", "/api/v1/robots", "", "Authorization: Bearer wrong-token-0123456789\r\n").status, 401);
  EXPECT_EQ(http(port, "GET", "/api/v1/robots", "", "Authorization: Bearer s3cret-token-0123456789\r\n").status, 200);
  EXPECT_EQ(http(port, "POST", "/api/v1/scenarios", "{}", "Authorization: Bearer s3cret\r\n").status, 401)
      << "a prefix of the token is not the token";
}

TEST(ServerLifecycle, BadFlagExitsWithMessage) {
  const CommandResult result = run_command(std::string(HRISIM_BINARY) + " serve --port 70000");
  EXPECT_EQ(result.exit_status, 2);
  EXPECT_NE(result.output.find("--port"), std::string::npos) << result.output;
}

TEST(ServerLifecycle, PortInUseIsReported) {
  TestServer first;
  const CommandResult result = run_command(
      std::string(HRISIM_BINARY) + " serve --port " + std::to_string(first.port()) + " --db " +
      (first.dir() / "other.db").string() + " --scenarios " + HRISIM_SOURCE_DIR + "/scenarios --web " +
      HRISIM_SOURCE_DIR + "/web");
  EXPECT_NE(result.exit_status, 0);
  EXPECT_NE(result.output.find("cannot listen"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace hrisim::testing
