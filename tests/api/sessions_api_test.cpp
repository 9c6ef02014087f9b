// Live sessions over REST against the real server: create, status, step (on the worker pool), state,
// delete; determinism across sessions; limits, expiry and bad input.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <thread>

#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

class SessionsApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new TestServer({"--max-sessions", "64"}); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static std::string create(const std::string& scenario, std::int64_t seed) {
    const HttpReply reply = http(port(), "POST", "/api/v1/sessions", json{{"scenario", scenario}, {"seed", seed}}.dump());
    EXPECT_EQ(reply.status, 201) << reply.body;
    return json_of(reply)["id"];
  }
  static TestServer* server_;
};
TestServer* SessionsApi::server_ = nullptr;

TEST_F(SessionsApi, CreateStepReadAndDelete) {
  const HttpReply created = http(port(), "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 3})");
  ASSERT_EQ(created.status, 201) << created.body;
  const json status = json_of(created);
  const std::string id = status["id"];
  EXPECT_EQ(id.size(), 33u) << "s and 128 random bits in hex";
  EXPECT_EQ(created.headers.at("location"), "/api/v1/sessions/" + id);
  EXPECT_EQ(status["tick"], 0);
  EXPECT_EQ(status["status"], "running");
  EXPECT_EQ(status["current_step"]["name"], "gather");
  EXPECT_EQ(status["step"], status["current_step"]);  // the former name, for one version
  const json stepped = json_of(http(port(), "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 60})"));
  EXPECT_EQ(stepped["tick"], 60);
  EXPECT_NEAR(stepped["time"].get<double>(), 1.0, 1e-12);
  EXPECT_FALSE(stepped["terminated"].get<bool>());
  EXPECT_TRUE(std::any_of(stepped["events"].begin(), stepped["events"].end(), [](const json& e) { return e["kind"] == "step_started"; }));
  const json state = json_of(http(port(), "GET", "/api/v1/sessions/" + id + "/state?events_since=30"));
  ASSERT_EQ(state["agents"].size(), 7u);
  EXPECT_EQ(state["agents"][6]["id"], "robot");
  EXPECT_EQ(state["agents"][6]["kind"], "robot");
  for (const json& event : state["events"]) EXPECT_GE(event["tick"].get<int>(), 30);
  EXPECT_EQ(http(port(), "DELETE", "/api/v1/sessions/" + id).status, 204);
  EXPECT_EQ(http(port(), "GET", "/api/v1/sessions/" + id).status, 404);
  EXPECT_EQ(http(port(), "DELETE", "/api/v1/sessions/" + id).status, 404);
}

// The state says who queues where: a line's name and the place in it (null while walking to its end).
TEST_F(SessionsApi, TheStateShowsWhoQueuesWhere) {
  const json scenario = json::parse(R"({"name": "counter", "world": {"bounds": {"min": [0, 0], "max": [10, 10]}},
    "queues": {"counter": {"x": 2, "y": 8, "theta": 1.5708, "service_time": 30}},
    "humans": [{"id": "ana", "start": {"x": 3, "y": 7}}, {"id": "ben", "start": {"x": 9, "y": 1}}],
    "steps": [{"name": "queue", "actions": [{"agent": "ana", "queue": "counter"}, {"agent": "ben", "queue": "counter"}]}]})");
  const HttpReply stored = http(port(), "POST", "/api/v1/scenarios", scenario.dump(), "Content-Type: application/json\r\n");
  ASSERT_EQ(stored.status, 201) << stored.body;
  const std::string scenario_id = json_of(stored)["summary"]["id"];
  const std::string id = json_of(http(port(), "POST", "/api/v1/sessions", json{{"scenario", scenario_id}, {"seed", 1}}.dump()))["id"];
  http(port(), "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 30})");
  const json early = json_of(http(port(), "GET", "/api/v1/sessions/" + id + "/state"));
  EXPECT_EQ(early["agents"][0]["queue"], json::parse(R"({"name": "counter", "place": 0})")) << "ana is within 2 m of the head at once";
  EXPECT_EQ(early["agents"][1]["queue"], json::parse(R"({"name": "counter", "place": null})")) << "ben walks to the end of the line";
  http(port(), "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 900})");
  const json later = json_of(http(port(), "GET", "/api/v1/sessions/" + id + "/state"));
  EXPECT_EQ(later["agents"][1]["queue"], json::parse(R"({"name": "counter", "place": 1})"));
  EXPECT_EQ(http(port(), "DELETE", "/api/v1/sessions/" + id).status, 204);
}

TEST_F(SessionsApi, SameSeedSameStateAndTheScenarioRunsToItsEnd) {
  const std::string a = create("elevator", 5), b = create("elevator", 5), c = create("elevator", 6);
  for (const std::string& id : {a, b, c}) {
    EXPECT_EQ(http(port(), "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 600})").status, 200);
  }
  const auto hash = [&](const std::string& id) { return json_of(http(port(), "GET", "/api/v1/sessions/" + id))["state_hash"]; };
  EXPECT_EQ(hash(a), hash(b));
  EXPECT_NE(hash(a), hash(c));
  const json end = json_of(http(port(), "POST", "/api/v1/sessions/" + a + "/step", R"({"n": 100000})"));
  EXPECT_EQ(end["status"], "finished");
  EXPECT_TRUE(end["terminated"].get<bool>());
  EXPECT_FALSE(end["truncated"].get<bool>());
  EXPECT_EQ(json_of(http(port(), "POST", "/api/v1/sessions/" + a + "/step", "{}"))["tick"], end["tick"]) << "a finished session stays put";
  for (const std::string& id : {a, b, c}) http(port(), "DELETE", "/api/v1/sessions/" + id);
}

TEST_F(SessionsApi, BadInputIsRefusedWithItsPlace) {
  const auto error = [&](const std::string& method, const std::string& target, const std::string& body) {
    const HttpReply reply = http(port(), method, target, body);
    return std::pair{reply.status, json_of(reply)["error"]};
  };
  EXPECT_EQ(error("POST", "/api/v1/sessions", R"({"scenario": "nowhere"})").first, 404);
  EXPECT_EQ(error("POST", "/api/v1/sessions", R"({"scenario": "nowhere"})").second["details"]["pointer"], "/scenario");
  const json neither = error("POST", "/api/v1/sessions", R"({"seed": 1})").second;
  EXPECT_EQ(neither["details"]["pointer"], "") << "the body lacks one of three keys";
  EXPECT_EQ(neither["message"], "the body: expected one of the forms: scenario | episode | snapshot");
  // Every error of a body at once, each with its pointer.
  const json several = error("POST", "/api/v1/sessions", R"({"scenario": "queue", "seed": -1, "mode": "fast", "colour": 1})").second;
  EXPECT_EQ(several["details"]["errors"].size(), 3u) << several;
  EXPECT_NE(several["message"].get<std::string>().find("(and 2 more)"), std::string::npos) << several;
  for (const char* seed : {"-1", "1.5", "\"x\"", "9007199254740992", "null"}) {
    const auto [status, body] = error("POST", "/api/v1/sessions", std::string(R"({"scenario": "queue", "seed": )") + seed + "}");
    EXPECT_EQ(status, 400) << seed;
    EXPECT_EQ(body["details"]["pointer"], "/seed") << seed;
  }
  EXPECT_EQ(error("POST", "/api/v1/sessions", R"({"scenario": "queue", "colour": 1})").second["details"]["pointer"], "/colour");
  const auto [status, body] = error("POST", "/api/v1/sessions", "{\"scenario\":\n \"queue\",,}");
  EXPECT_EQ(status, 400);
  EXPECT_EQ(body["details"]["line"], 2);
  EXPECT_EQ(error("POST", "/api/v1/sessions", "[1, 2]").first, 400);
  const std::string id = create("queue", 1);
  for (const char* n : {"0", "100001", "\"ten\"", "2.5"}) {
    const auto [n_status, n_body] = error("POST", "/api/v1/sessions/" + id + "/step", std::string(R"({"n": )") + n + "}");
    EXPECT_EQ(n_status, 400) << n;
    EXPECT_EQ(n_body["details"]["pointer"], "/n") << n;
  }
  EXPECT_EQ(error("GET", "/api/v1/sessions/" + id + "/state?events_since=-3", "").first, 400);
  EXPECT_EQ(error("POST", "/api/v1/sessions/s0123/step", "{}").first, 404);
  http(port(), "DELETE", "/api/v1/sessions/" + id);
}

TEST(SessionWorkers, LongStepsNeverHoldTheOnlyIoThread) {
  // One I/O thread: if stepping ran on it, nothing else could be answered until it finished.
  TestServer server({"--threads", "1", "--workers", "1"});
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "elevator"})"))["id"];
  const std::string body = R"({"n": 100000})";  // the whole scenario: several hundred milliseconds of work
  RawConnection stepping(server.port(), std::chrono::seconds(60));
  ASSERT_TRUE(stepping.send("POST /api/v1/sessions/" + id + "/step HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                            "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body));
  std::atomic<bool> stepping_done{false};
  std::thread reader([&] {
    EXPECT_EQ(stepping.read_reply().status, 200);
    stepping_done = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the step is under way by now
  EXPECT_EQ(http(server.port(), "GET", "/healthz").status, 200);
  EXPECT_FALSE(stepping_done) << "health was answered only after the step: the step held the I/O thread";
  reader.join();
  EXPECT_EQ(json_of(http(server.port(), "GET", "/api/v1/sessions/" + id))["status"], "finished");
}

// A keep-alive connection's first step moves it to the worker pool (no hand-over per request); it
// goes on serving every kind of request in order, one sent right behind the step included.
TEST(SessionWorkers, AConnectionThatStepsKeepsServingEveryRequestInOrder) {
  TestServer server({"--threads", "1", "--workers", "2"});
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 2})"))["id"];
  RawConnection connection(server.port());
  const auto request = [&](const std::string& method, const std::string& target, const std::string& body) {
    return method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: " +
           std::to_string(body.size()) + "\r\n\r\n" + body;
  };
  const std::string step = request("POST", "/api/v1/sessions/" + id + "/step", R"({"n": 5})");
  // The step and a status request behind it in one write: the second is read after the move.
  ASSERT_TRUE(connection.send(step + request("GET", "/api/v1/sessions/" + id, "")));
  const HttpReply stepped = connection.read_reply();
  ASSERT_EQ(stepped.status, 200) << stepped.body;
  EXPECT_EQ(json_of(stepped)["tick"], 5);
  const HttpReply status = connection.read_reply();
  ASSERT_EQ(status.status, 200) << status.body;
  EXPECT_EQ(json_of(status)["tick"], 5);
  for (int i = 2; i <= 4; ++i) {
    ASSERT_TRUE(connection.send(step));
    EXPECT_EQ(json_of(connection.read_reply())["tick"], 5 * i);
  }
  ASSERT_TRUE(connection.send(request("GET", "/", "")));
  const HttpReply page = connection.read_reply();
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.body.find("<html"), std::string::npos) << "a static file from the same connection";
  ASSERT_TRUE(connection.send(request("POST", "/api/v1/sessions/" + id + "/step", R"({"n": 0})")));
  EXPECT_EQ(connection.read_reply().status, 400) << "an error keeps the connection";
  ASSERT_TRUE(connection.send(step));
  EXPECT_EQ(json_of(connection.read_reply())["tick"], 25);
}

TEST(SessionLimits, BeyondTheMaximumIs503AndIdleSessionsExpire) {
  TestServer server({"--max-sessions", "2", "--session-idle-timeout", "1"});
  const auto post = [&] { return http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "queue"})"); };
  const std::string first = json_of(post())["id"];
  ASSERT_EQ(post().status, 201);
  const HttpReply third = post();
  EXPECT_EQ(third.status, 503);
  EXPECT_EQ(third.headers.at("retry-after"), "10");
  EXPECT_EQ(json_of(third)["error"]["code"], "unavailable");
  std::this_thread::sleep_for(std::chrono::milliseconds(1600));
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/sessions/" + first).status, 404) << "expired after 1 s unused";
  EXPECT_EQ(post().status, 201) << "room again";
}

/// A scenario without steps, people or robot: over at its first tick.
const char* kOverAtOnce = R"({"name": "over", "world": {"bounds": {"min": [0, 0], "max": [4, 4]}}, "steps": []})";

TEST(SessionLimits, FinishedSessionsDoNotCountAndTheLeastRecentlyUsedBeyondTheMaximumGo) {
  TestServer server({"--max-sessions", "2"});
  const std::uint16_t port = server.port();
  const HttpReply upload = http(port, "POST", "/api/v1/scenarios", kOverAtOnce);
  ASSERT_EQ(upload.status, 201) << upload.body;
  const std::string over = json_of(upload)["summary"]["id"];
  const auto create = [&](const std::string& scenario) { return http(port, "POST", "/api/v1/sessions", json{{"scenario", scenario}}.dump()); };
  const auto finished_session = [&] {
    const HttpReply created = create(over);
    EXPECT_EQ(created.status, 201) << created.body;
    const std::string id = json_of(created)["id"];
    EXPECT_EQ(json_of(http(port, "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 1})"))["status"], "finished");
    return id;
  };
  const std::string a = finished_session(), b = finished_session();
  const HttpReply first = create("queue");
  ASSERT_EQ(first.status, 201);
  ASSERT_EQ(create("queue").status, 201) << "two finished sessions leave room for two running ones";
  const HttpReply refused = create("queue");
  ASSERT_EQ(refused.status, 503) << "two running";
  EXPECT_NE(json_of(refused)["error"]["message"].get<std::string>().find("finished ones do not count"), std::string::npos);
  EXPECT_NE(json_of(refused)["error"]["message"].get<std::string>().find("DELETE /api/v1/sessions/{id}"), std::string::npos)
      << "the REST front end says how to end one over REST";
  EXPECT_EQ(json_of(refused)["error"]["details"]["running"], 2);
  ASSERT_EQ(http(port, "DELETE", "/api/v1/sessions/" + json_of(first)["id"].get<std::string>()).status, 204);
  const std::string d = finished_session();
  // Three finished sessions, one more than the maximum kept: creating one ends the least recently used.
  http(port, "GET", "/api/v1/sessions/" + b);
  ASSERT_EQ(create("queue").status, 201);
  EXPECT_EQ(http(port, "GET", "/api/v1/sessions/" + a).status, 404) << "the least recently used finished session went";
  EXPECT_EQ(http(port, "GET", "/api/v1/sessions/" + b).status, 200);
  EXPECT_EQ(http(port, "GET", "/api/v1/sessions/" + d).status, 200);
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

TEST(SessionCommands, HumansAndRobotsTakeCommandsAndABadListChangesNothing) {
  TestServer server;
  const std::uint16_t port = server.port();
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 2})"))["id"];
  const std::string commands = "/api/v1/sessions/" + id + "/commands";
  // The second command is wrong: neither is given.
  const HttpReply refused = http(port, "POST", commands, R"({"commands": [
    {"human": "dev", "command": "walk 8 -3"}, {"robot": "robot", "joints": {"group": "arm", "positions": [0.1]}}]})");
  EXPECT_EQ(refused.status, 400);
  EXPECT_EQ(json_of(refused)["error"]["details"]["pointer"], "/commands/1/joints/positions");
  const HttpReply given = http(port, "POST", commands, R"({"commands": [
    {"human": "dev", "command": "walk 8 -3"},
    {"robot": "robot", "velocity": {"linear": 0.2, "angular": 0.0}},
    {"robot": "robot", "joints": {"group": "head", "positions": [0.5, -0.2]}},
    {"robot": "robot", "gripper": "close"}]})");
  ASSERT_EQ(given.status, 200) << given.body;
  EXPECT_EQ(json_of(given)["applied"], 4);
  const json stepped = json_of(http(port, "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 120})"));
  int commands_seen = 0;
  for (const json& event : stepped["events"]) commands_seen += event["kind"] == "command";
  EXPECT_EQ(commands_seen, 1) << "only the accepted list's human command";
  const json state = json_of(http(port, "GET", "/api/v1/sessions/" + id + "/state"));
  const json& robot = state["agents"][6];
  EXPECT_LT(robot["x"].get<double>(), 2.6 - 0.2) << "driven by its velocity command (west, its heading)";
  const auto bad = [&](const std::string& body) {
    const HttpReply reply = http(port, "POST", commands, body);
    EXPECT_EQ(reply.status, 400) << body;
    return json_of(reply)["error"]["details"]["pointer"].get<std::string>();
  };
  EXPECT_EQ(bad(R"({"commands": [{"human": "zed", "command": "wait 1"}]})"), "/commands/0/human");
  EXPECT_EQ(bad(R"({"commands": [{"human": "dev", "command": "fly 1 2"}]})"), "/commands/0");
  EXPECT_EQ(bad(R"({"commands": [{"robot": "robot", "gripper": "squeeze"}]})"), "/commands/0/gripper");
  EXPECT_EQ(bad(R"({"commands": [{"robot": "robot", "velocity": {"linear": "fast", "angular": 0}}]})"), "/commands/0/velocity/linear");
  EXPECT_EQ(bad(R"({"commands": [{"robot": "robot", "teleport": {}}]})"), "/commands/0/teleport");
  EXPECT_EQ(bad(R"({"commands": [{"robot": "ada", "gripper": "open"}]})"), "/commands/0/robot");
  EXPECT_EQ(bad(R"({"commands": [{"robot": "robot", "request": "fetch_coffee"}]})"), "/commands/0/request");
  EXPECT_EQ(bad(R"({"commands": 3})"), "/commands");
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

TEST(SessionPoses, AgentsAndObjectsArePlacedAndResetStartsAgain) {
  TestServer server;
  const std::uint16_t port = server.port();
  const json scenario = json::parse(R"({"name": "cup", "world": {"bounds": {"min": [0, 0], "max": [6, 6]},
      "obstacles": [{"name": "table", "box": {"x": 4, "y": 4, "length": 1, "width": 1}, "height": 0.75}]},
    "humans": [{"id": "ana", "start": {"x": 1, "y": 1}}],
    "robots": [{"id": "hsr", "model": "hsr", "start": {"x": 1, "y": 4}}],
    "objects": [{"name": "cup", "shape": {"kind": "cylinder", "radius": 0.04, "length": 0.1}, "mass": 0.2,
                 "pose": {"x": 4, "y": 4, "z": 0.8}}],
    "steps": [{"name": "wait", "actions": [{"agent": "ana", "wait": {"duration": 30}}]}]})");
  const std::string scenario_id = json_of(http(port, "POST", "/api/v1/scenarios", scenario.dump()))["summary"]["id"];
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", json{{"scenario", scenario_id}, {"seed", 4}}.dump()))["id"];
  const std::string poses = "/api/v1/sessions/" + id + "/poses";
  const HttpReply moved = http(port, "PUT", poses + "/ana", R"({"x": 2, "y": 1.5, "yaw": 1.5708})", "Content-Type: application/json\r\n");
  ASSERT_EQ(moved.status, 200) << moved.body;
  EXPECT_EQ(json_of(moved)["agents"][0]["x"], 2.0);
  EXPECT_EQ(json_of(moved)["agents"][0]["yaw"], 1.5708);
  ASSERT_EQ(http(port, "PUT", poses + "/cup", R"({"x": 4.2, "y": 3.9, "z": 0.8, "yaw": 0.3})", "Content-Type: application/json\r\n").status, 200);
  http(port, "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 60})");
  const json after = json_of(http(port, "GET", poses));
  EXPECT_NEAR(after["objects"][0]["x"].get<double>(), 4.2, 1e-3);
  EXPECT_NEAR(after["objects"][0]["z"].get<double>(), 0.75 + 0.05, 0.01) << "it settled on the table top";
  EXPECT_NEAR(after["objects"][0]["yaw"].get<double>(), 0.3, 0.01) << "settling turns it a little";
  EXPECT_NEAR(after["agents"][0]["x"].get<double>(), 2.0, 0.05) << "she stays where she was put";
  const auto status = [&](const std::string& body) {
    return http(port, "PUT", poses + "/ana", body, "Content-Type: application/json\r\n").status;
  };
  EXPECT_EQ(status(R"({"x": 4, "y": 4})"), 400) << "on the table";
  EXPECT_EQ(status(R"({"x": 1, "y": 1, "z": 0.5})"), 400) << "people stand on the floor";
  EXPECT_EQ(status(R"({"y": 1})"), 400);
  EXPECT_EQ(http(port, "PUT", poses + "/teapot", R"({"x": 1, "y": 1})", "Content-Type: application/json\r\n").status, 404);
  // Reset: tick 0 and the scenario's own poses again, with a new seed when given.
  const json reset = json_of(http(port, "POST", "/api/v1/sessions/" + id + "/reset", R"({"seed": 9})"));
  EXPECT_EQ(reset["tick"], 0);
  EXPECT_EQ(reset["seed"], 9);
  const json fresh = json_of(http(port, "GET", poses));
  EXPECT_EQ(fresh["agents"][0]["x"], 1.0);
  EXPECT_NEAR(fresh["objects"][0]["x"].get<double>(), 4.0, 1e-9);
}

}  // namespace
}  // namespace hrisim::testing

#include "websocket_client.hpp"

namespace hrisim::testing {
namespace {

TEST(SessionLimits, AnUnwatchedGraceEndsASessionThatLongAfterItsLastWebSocketClosed) {
  TestServer server;
  const std::uint16_t port = server.port();
  const auto create = [&](const json& grace) {
    const HttpReply created = http(port, "POST", "/api/v1/sessions", json{{"scenario", "queue"}, {"unwatched_grace", grace}}.dump());
    EXPECT_EQ(created.status, 201) << created.body;
    return json_of(created);
  };
  const auto listed = [&](const std::string& id) {
    const json list = json_of(http(port, "GET", "/api/v1/sessions"));
    for (const json& item : list["items"]) {
      if (item["id"] == id) return item;
    }
    return json();
  };
  const json watched = create(1), never_watched = create(1), plain = create(nullptr);
  EXPECT_EQ(watched["unwatched_grace"], 1);
  EXPECT_TRUE(plain["unwatched_grace"].is_null());
  const std::string id = watched["id"];
  {
    WebSocketClient socket(port, "/api/v1/sessions/" + id + "/ws");
    ASSERT_EQ(socket.status, 0);
    socket.exchange({{"type", "step"}, {"n", 1}});
    std::this_thread::sleep_for(std::chrono::milliseconds(1600));
    const json item = listed(id);
    ASSERT_FALSE(item.is_null()) << "a session with a WebSocket open stays: " << http(port, "GET", "/api/v1/sessions").body;
    EXPECT_EQ(item["connected_clients"], 1);
    EXPECT_GT(item["unused_for"].get<double>(), 1.0) << "a silent socket does not use it";
  }
  EXPECT_TRUE(listed(never_watched["id"]).is_null()) << "one second after its creation, no WebSocket having opened";
  EXPECT_FALSE(listed(id).is_null()) << "its grace counts from the close";
  EXPECT_FALSE(listed(plain["id"]).is_null());
  std::this_thread::sleep_for(std::chrono::milliseconds(1600));
  EXPECT_TRUE(listed(id).is_null()) << "a second after its last WebSocket closed";
  EXPECT_EQ(http(port, "GET", "/api/v1/sessions/" + id).status, 404);
  EXPECT_FALSE(listed(plain["id"]).is_null()) << "without a grace, only the idle timeout ends it";
  for (const json& wrong : {json(0), json(3601), json("30"), json(1.5)}) {
    const HttpReply refused = http(port, "POST", "/api/v1/sessions", json{{"scenario", "queue"}, {"unwatched_grace", wrong}}.dump());
    EXPECT_EQ(refused.status, 400) << wrong;
    EXPECT_EQ(json_of(refused)["error"]["details"]["pointer"], "/unwatched_grace") << wrong;
  }
}

TEST(SessionWebSocket, LockstepStepsCommandsAndStateInOrder) {
  TestServer server;
  const std::uint16_t port = server.port();
  const auto create = [&] { return json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 8})"))["id"].get<std::string>(); };
  const std::string socket_session = create(), rest_session = create();
  WebSocketClient client(port, "/api/v1/sessions/" + socket_session + "/ws");
  ASSERT_EQ(client.status, 0);
  for (int i = 1; i <= 100; ++i) {
    const json reply = client.exchange({{"type", "step"}, {"n", 1}});
    ASSERT_EQ(reply["type"], "step");
    ASSERT_EQ(reply["tick"], i) << "one step message, one step";
  }
  const json given = client.exchange(json::parse(R"({"type": "commands", "commands": [{"human": "dev", "command": "wait 2"}]})"));
  EXPECT_EQ(given["type"], "commands");
  EXPECT_EQ(given["applied"], 1);
  const json wrong = client.exchange({{"type", "dance"}});
  EXPECT_EQ(wrong["type"], "error");
  EXPECT_EQ(wrong["error"]["details"]["pointer"], "/type");
  EXPECT_EQ(client.exchange({{"type", "step"}, {"n", 0}})["error"]["details"]["pointer"], "/n");
  EXPECT_EQ(client.exchange({{"type", "step"}, {"n", 200}})["tick"], 300) << "the socket stays open after errors";
  const json state = client.exchange({{"type", "state"}, {"events_since", 250}});
  EXPECT_EQ(state["type"], "state");
  EXPECT_EQ(state["agents"].size(), 7u);
  // The same scenario, seed and commands over REST end in the same state.
  http(port, "POST", "/api/v1/sessions/" + rest_session + "/step", R"({"n": 100})");
  http(port, "POST", "/api/v1/sessions/" + rest_session + "/commands", R"({"commands": [{"human": "dev", "command": "wait 2"}]})");
  http(port, "POST", "/api/v1/sessions/" + rest_session + "/step", R"({"n": 200})");
  EXPECT_EQ(json_of(http(port, "GET", "/api/v1/sessions/" + rest_session))["state_hash"], state["state_hash"]);
}

// step_many steps many sessions in one message or request, spread over the worker pool: each ends
// where the same steps one by one end, bit for bit; a bad list is refused at its place and steps none.
TEST(SessionWebSocket, StepManyStepsEverySessionAsItsOwnStepsWould) {
  TestServer server({"--max-sessions", "16", "--workers", "2"});
  const std::uint16_t port = server.port();
  const auto create = [&](std::int64_t seed) {
    return json_of(http(port, "POST", "/api/v1/sessions", json{{"scenario", "approach_human"}, {"seed", seed}}.dump()))["id"].get<std::string>();
  };
  std::vector<std::string> batched, alone;
  for (std::int64_t seed = 1; seed <= 6; ++seed) {
    batched.push_back(create(seed));
    alone.push_back(create(seed));
  }
  const auto action = [](std::size_t env, int step) { return json::array({0.1 * static_cast<double>(env % 3), 0.05 * (step % 4) - 0.1}); };
  WebSocketClient client(port, "/api/v1/sessions/" + batched[0] + "/ws");
  ASSERT_EQ(client.status, 0);
  for (int step = 0; step < 20; ++step) {
    json actions = json::array();
    for (std::size_t env = 0; env < batched.size(); ++env) actions.push_back(action(env, step));
    // The first half over the WebSocket, the second over REST.
    const json message = {{"type", "step_many"}, {"sessions", batched}, {"actions", actions}};
    const json reply = step < 10 ? client.exchange(message) : json_of(http(port, "POST", "/api/v1/sessions/step", json{{"sessions", batched}, {"actions", actions}}.dump()));
    if (step < 10) {
      ASSERT_EQ(reply["type"], "step_many") << reply.dump();
    }
    ASSERT_EQ(reply["results"].size(), batched.size()) << reply.dump();
    for (std::size_t env = 0; env < batched.size(); ++env) {
      const json& result = reply["results"][env];
      ASSERT_EQ(result["id"], batched[env]) << "in the order asked";
      const json own = json_of(http(port, "POST", "/api/v1/sessions/" + alone[env] + "/step", json{{"action", action(env, step)}}.dump()));
      EXPECT_EQ(result["state_hash"], own["state_hash"]) << "env " << env << ", step " << step;
      EXPECT_EQ(result["observation"], own["observation"]);
      EXPECT_EQ(result["reward"], own["reward"]);
    }
  }
  const auto ticks = [&](const std::string& id) { return json_of(http(port, "GET", "/api/v1/sessions/" + id))["tick"].get<std::int64_t>(); };
  const std::int64_t before = ticks(batched[1]);
  // Refused before anything is stepped, at the place of what is wrong.
  const auto refused = [&](const json& body) {
    const HttpReply reply = http(port, "POST", "/api/v1/sessions/step", body.dump());
    EXPECT_GE(reply.status, 400) << body.dump();
    return json_of(reply)["error"]["details"].value("pointer", "");
  };
  EXPECT_EQ(refused({{"sessions", {batched[1], "s-nobody"}}}), "/sessions/1");
  EXPECT_EQ(refused({{"sessions", {batched[1], batched[1]}}}), "/sessions/1");
  EXPECT_EQ(refused({{"sessions", json::array()}}), "/sessions");
  EXPECT_EQ(refused({{"sessions", {batched[1], batched[2]}}, {"actions", {json::array({0.1, 0.0})}}}), "/actions");
  EXPECT_EQ(refused({{"sessions", {batched[1], batched[2]}}, {"actions", {json::array({0.1, 0.0}), json::array({"fast", 0.0})}}}), "/actions/1/0");
  EXPECT_EQ(refused({{"sessions", {batched[1]}}, {"n", 0}}), "/n");
  EXPECT_EQ(ticks(batched[1]), before) << "nothing was stepped";
  const json wrong = client.exchange({{"type", "step_many"}, {"sessions", {batched[1]}}, {"speed", 2}});
  EXPECT_EQ(wrong["type"], "error");
  EXPECT_EQ(wrong["error"]["details"]["pointer"], "/speed");
  // An action the session's space does not take is that session's error; the others step.
  const json mixed = client.exchange({{"type", "step_many"}, {"sessions", {batched[1], batched[2]}}, {"actions", {json::array({0.1}), nullptr}}});
  ASSERT_EQ(mixed["results"].size(), 2u) << mixed.dump();
  EXPECT_TRUE(mixed["results"][0].contains("error")) << mixed.dump();
  EXPECT_EQ(mixed["results"][1]["tick"].get<std::int64_t>(), ticks(batched[2]));
}

TEST(SessionWebSocket, UpgradesAreRefusedForUnknownSessionsAndWithoutTheToken) {
  TestServer server({"--token", "a-token-of-16-chars"});
  const std::uint16_t port = server.port();
  const HttpReply unknown = upgrade(port, "/api/v1/sessions/s00/ws", "Authorization: Bearer a-token-of-16-chars\r\n");
  EXPECT_EQ(unknown.status, 404);
  EXPECT_EQ(json_of(unknown)["error"]["code"], "not_found");
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue"})",
                                      "Authorization: Bearer a-token-of-16-chars\r\n"))["id"];
  EXPECT_EQ(upgrade(port, "/api/v1/sessions/" + id + "/ws").status, 401);
  EXPECT_EQ(upgrade(port, "/api/v1/sessions/" + id + "/nowhere", "Authorization: Bearer a-token-of-16-chars\r\n").status, 404);
  WebSocketClient authorised(port, "/api/v1/sessions/" + id + "/ws", "Bearer a-token-of-16-chars");
  EXPECT_EQ(authorised.status, 0);
  EXPECT_EQ(authorised.exchange({{"type", "step"}})["tick"], 1);
}

TEST(SessionWebSocket, ABrowserOpensItWithAOneTimeTicketFromItsOwnOrigin) {
  TestServer server({"--token", "a-token-of-16-chars", "--allowed-origins", "https://lab.example:8443"});
  const std::uint16_t port = server.port();
  const std::string auth = "Authorization: Bearer a-token-of-16-chars\r\n";
  const auto create = [&] { return json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue"})", auth))["id"].get<std::string>(); };
  const std::string id = create(), other = create();
  EXPECT_EQ(http(port, "POST", "/api/v1/sessions/" + id + "/ws-ticket").status, 401) << "tickets come from authenticated requests only";
  const auto ticket = [&](const std::string& session) {
    const HttpReply reply = http(port, "POST", "/api/v1/sessions/" + session + "/ws-ticket", "", auth);
    EXPECT_EQ(reply.status, 201) << reply.body;
    EXPECT_EQ(json_of(reply)["expires_in"], 30);
    return json_of(reply)["ticket"].get<std::string>();
  };
  const std::string first = ticket(id);
  WebSocketClient with_ticket(port, "/api/v1/sessions/" + id + "/ws?ticket=" + first);
  EXPECT_EQ(with_ticket.status, 0);
  EXPECT_EQ(with_ticket.exchange({{"type", "step"}})["tick"], 1);
  EXPECT_EQ(upgrade(port, "/api/v1/sessions/" + id + "/ws?ticket=" + first).status, 401) << "a ticket opens one socket";
  EXPECT_EQ(upgrade(port, "/api/v1/sessions/" + other + "/ws?ticket=" + ticket(id)).status, 401) << "a ticket is for one session";
  EXPECT_EQ(http(port, "POST", "/api/v1/sessions/s00/ws-ticket", "", auth).status, 404);
  // A page from another site may not drive the session; the server's own pages and listed origins may.
  EXPECT_EQ(upgrade(port, "/api/v1/sessions/" + id + "/ws", auth + "Origin: http://evil.example\r\n").status, 403);
  EXPECT_EQ(upgrade(port, "/api/v1/sessions/" + id + "/ws", auth + "Origin: http://127.0.0.1\r\n").status, 101);
  EXPECT_EQ(upgrade(port, "/api/v1/sessions/" + id + "/ws", auth + "Origin: https://lab.example:8443\r\n").status, 101);
}

TEST(SessionWebSocket, StateFramesArePushedAtTheSubscribedRate) {
  TestServer server;
  const std::uint16_t port = server.port();
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 2})"))["id"];
  WebSocketClient viewer(port, "/api/v1/sessions/" + id + "/ws");
  EXPECT_EQ(viewer.exchange({{"type", "subscribe"}, {"rate", 61}})["error"]["details"]["pointer"], "/rate");
  const json subscribed = viewer.exchange({{"type", "subscribe"}, {"rate", 20}});
  EXPECT_EQ(subscribed["type"], "subscribed");
  EXPECT_EQ(subscribed["rate"], 20.0);
  // Another client steps the session; the viewer sees frames until one shows the last tick, each
  // event in exactly one frame.
  for (int i = 0; i < 3; ++i) http(port, "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 30})");
  std::map<std::string, int> seen;
  json frame;
  do {
    frame = json::parse(viewer.next());
    ASSERT_EQ(frame["type"], "state_frame") << frame.dump();
    EXPECT_EQ(frame["agents"].size(), 7u);
    for (const json& event : frame["events"]) ++seen[event.dump()];
  } while (frame["tick"] != 90);
  EXPECT_EQ(frame["dropped_frames"], 0);
  EXPECT_FALSE(seen.empty());
  for (const auto& [event, count] : seen) EXPECT_EQ(count, 1) << event;
  // Rate 0 stops the frames; answers still come, in order.
  viewer.send({{"type", "subscribe"}, {"rate", 0}});
  json reply;
  do {
    reply = json::parse(viewer.next());
  } while (reply["type"] == "state_frame");
  EXPECT_EQ(reply["type"], "subscribed");
  EXPECT_EQ(viewer.exchange({{"type", "step"}})["tick"], 91);
}

}  // namespace
}  // namespace hrisim::testing

#include <random>

namespace hrisim::testing {
namespace {

/// A thousand generated malformed session requests — creation, steps, commands, poses, state — on a
/// server with one valid session: never a 5xx, every answer JSON, no session created or lost.
TEST(SessionsFuzz, MalformedRequestsBreakNothing) {
  TestServer server;
  const std::uint16_t port = server.port();
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator"})"))["id"];
  std::mt19937_64 random(7);
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(random() % n); };
  const json junk[] = {nullptr, true, -1, 1e308, "x", json::array(), json::object(), 0.5, std::string(300, 'z'), json::array({1, "a"})};
  const auto any = [&] { return junk[pick(std::size(junk))]; };
  for (int i = 0; i < 1000; ++i) {
    std::string method = "POST", target, body;
    switch (i % 6) {
      case 0:
        target = "/api/v1/sessions";
        body = json{{"scenario", i % 3 ? any() : json("elevator")}, {"seed", any()}}.dump();
        break;
      case 1:
        target = "/api/v1/sessions/" + id + (pick(2) ? "/step" : "/reset");
        body = json{{"n", any()}, {"action", any()}, {"options", any()}}.dump();
        break;
      case 2:
        target = "/api/v1/sessions/" + id + "/commands";
        body = json{{"commands", json::array({{{pick(2) ? "human" : "robot", any()}, {"command", any()}, {"velocity", any()}}})}}.dump();
        break;
      case 3:
        method = "PUT";
        target = "/api/v1/sessions/" + id + "/poses/" + (pick(2) ? "ada" : "robot");
        body = json{{"x", any()}, {"y", any()}, {"roll", any()}}.dump();
        break;
      case 4:
        method = "GET";
        target = "/api/v1/sessions/" + id + "/state?events_since=" + std::to_string(static_cast<long long>(random() % 2000) - 1000);
        break;
      case 5:  // cut-off or random bytes
        target = "/api/v1/sessions/" + (pick(2) ? id : "s" + std::to_string(i)) + "/step";
        for (std::size_t k = 0, n = pick(80); k < n; ++k) body += static_cast<char>(random() & 0xFF);
        break;
    }
    const HttpReply reply = http(port, method, target, body);
    ASSERT_LT(reply.status, 500) << i << " " << method << " " << target << " " << body << " → " << reply.body;
    EXPECT_NO_THROW(json_of(reply)) << i;
  }
  EXPECT_EQ(http(port, "GET", "/healthz").status, 200);
  const json sessions = json_of(http(port, "GET", "/api/v1/sessions"));
  ASSERT_GE(sessions["items"].size(), 1u) << "the valid session is still there";
  EXPECT_LE(sessions["items"].size(), 8u) << "never beyond the limit";
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

TEST(SessionSensors, TheRobotsLatestReadingsOverRestAndWebSocket) {
  TestServer server;
  const std::uint16_t port = server.port();
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 1})"))["id"];
  http(port, "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 30})");
  const json sensors = json_of(http(port, "GET", "/api/v1/sessions/" + id + "/robots/robot/sensors"));
  ASSERT_EQ(sensors["lasers"].size(), 1u);
  const json& scan = sensors["lasers"][0];
  EXPECT_EQ(scan["sensor"], "base_scan");
  EXPECT_EQ(scan["ranges"].size(), 1081u);
  EXPECT_GE(scan["tick"].get<int>(), 28) << "40 Hz";
  int finite = 0;
  for (const json& range : scan["ranges"]) {
    if (range.is_number()) {
      ++finite;
      EXPECT_GE(range.get<double>(), scan["range_min"].get<double>());
    } else {
      EXPECT_TRUE(range == "inf" || range == "-inf") << range;  // REP 117, spelled out
    }
  }
  EXPECT_GT(finite, 500) << "the elevator hall's walls are within 20 m";
  EXPECT_GE(sensors["people"]["tick"].get<int>(), 25) << "10 Hz";
  EXPECT_EQ(sensors["odometry"]["tick"], 30);
  EXPECT_FALSE(sensors["joints"].empty());
  EXPECT_EQ(http(port, "GET", "/api/v1/sessions/" + id + "/robots/ada/sensors").status, 404) << "a human";
  EXPECT_EQ(http(port, "GET", "/api/v1/sessions/" + id + "/robots/nobody/sensors").status, 404);
  WebSocketClient client(port, "/api/v1/sessions/" + id + "/ws");
  const json over_socket = client.exchange({{"type", "sensors"}, {"robot", "robot"}});
  EXPECT_EQ(over_socket["type"], "sensors");
  EXPECT_EQ(over_socket["lasers"][0]["ranges"], scan["ranges"]);
  EXPECT_EQ(client.exchange({{"type", "sensors"}})["error"]["details"]["pointer"], "/robot");

  // The same scan as a binary message: a 56-byte little-endian header, then float32 ranges.
  client.send({{"type", "laser"}, {"robot", "robot"}});
  bool binary = false;
  const std::string frame = client.next(&binary);
  ASSERT_TRUE(binary);
  ASSERT_EQ(frame.size(), 56u + 4u * 1081u);
  const auto read = [&]<typename T>(std::size_t offset, T) {
    T value;
    std::memcpy(&value, frame.data() + offset, sizeof value);
    return value;
  };
  EXPECT_EQ(frame.substr(0, 4), "HRLS");
  EXPECT_EQ(read(4, std::uint16_t{}), 1);
  EXPECT_EQ(read(6, std::uint16_t{}), 56);
  EXPECT_EQ(read(8, std::int64_t{}), scan["tick"].get<std::int64_t>());
  EXPECT_FLOAT_EQ(read(36, float{}), static_cast<float>(scan["angle_min"].get<double>()));
  EXPECT_FLOAT_EQ(read(48, float{}), static_cast<float>(scan["range_max"].get<double>()));
  EXPECT_EQ(read(52, std::uint32_t{}), 1081u);
  for (std::size_t i = 0; i < 1081; ++i) {
    const float range = read(56 + 4 * i, float{});
    if (scan["ranges"][i].is_number()) {
      EXPECT_FLOAT_EQ(range, static_cast<float>(scan["ranges"][i].get<double>())) << i;
    } else {
      EXPECT_EQ(range, scan["ranges"][i] == "inf" ? INFINITY : -INFINITY) << i;
    }
  }
  EXPECT_EQ(client.exchange({{"type", "laser"}, {"robot", "robot"}, {"sensor", "nose"}})["error"]["details"]["pointer"], "/sensor");
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

TEST(SessionSensors, AListeningRobotsAudioOverRestAndWebSocket) {
  TestServer server;
  const std::uint16_t port = server.port();
  // The HSR listens; Ada, 2 m to its left, speaks for 2 s.
  const json scenario = json::parse(R"({
    "name": "talk", "dt": 0.05, "time_limit": 10,
    "world": {"bounds": {"min": [-0.5, -0.5], "max": [8.5, 8.5]},
              "walls": [{"from": [0, 0], "to": [8, 0]}, {"from": [8, 0], "to": [8, 8]}, {"from": [8, 8], "to": [0, 8]}, {"from": [0, 8], "to": [0, 0]}]},
    "humans": [{"id": "ada", "start": {"x": 4, "y": 6}}],
    "robots": [{"id": "hsr", "model": "hsr", "start": {"x": 4, "y": 4, "theta": 0}, "microphones": {}}],
    "steps": [{"name": "talk", "actions": [{"agent": "ada", "say": {"duration": 2}}]}]
  })");
  const HttpReply stored = http(port, "POST", "/api/v1/scenarios", scenario.dump());
  ASSERT_EQ(stored.status, 201) << stored.body;
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", json{{"scenario", json_of(stored)["summary"]["id"]}}.dump()))["id"];
  http(port, "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 20})");
  const json sensors = json_of(http(port, "GET", "/api/v1/sessions/" + id + "/robots/hsr/sensors"));
  const json& microphones = sensors["microphones"];
  EXPECT_EQ(microphones["channels"], 4);
  EXPECT_EQ(microphones["samples"], 800);
  EXPECT_EQ(microphones["first_sample"], 19 * 800);
  ASSERT_TRUE(microphones["direction"].is_object()) << microphones.dump();
  EXPECT_NEAR(microphones["direction"]["bearing"].get<double>(), 1.5708, 0.1745) << "she is to its left, within 10 degrees";

  const HttpReply audio = http(port, "GET", "/api/v1/sessions/" + id + "/robots/hsr/audio");
  ASSERT_EQ(audio.status, 200);
  ASSERT_EQ(audio.body.size(), 48u + 4u * 4u * 800u);
  const auto read = [](const std::string& frame, std::size_t offset, auto value) {
    std::memcpy(&value, frame.data() + offset, sizeof value);
    return value;
  };
  EXPECT_EQ(audio.body.substr(0, 4), "HRAU");
  EXPECT_EQ(read(audio.body, 6, std::uint16_t{}), 48);
  EXPECT_EQ(read(audio.body, 8, std::int64_t{}), 20);
  EXPECT_EQ(read(audio.body, 24, std::int64_t{}), 19 * 800);
  EXPECT_EQ(read(audio.body, 32, std::uint32_t{}), 16000u);
  EXPECT_EQ(read(audio.body, 36, std::uint32_t{}), 4u);
  EXPECT_EQ(read(audio.body, 40, std::uint32_t{}), 800u);
  double energy = 0.0;
  for (std::size_t k = 0; k < 4 * 800; ++k) energy += std::pow(read(audio.body, 48 + 4 * k, float{}), 2);
  EXPECT_GT(std::sqrt(energy / 3200), 0.003) << "her voice, 2 m away, well above the microphones' 0.0006 Pa";

  WebSocketClient client(port, "/api/v1/sessions/" + id + "/ws");
  client.send({{"type", "audio"}, {"robot", "hsr"}});
  bool binary = false;
  EXPECT_EQ(client.next(&binary), audio.body);
  EXPECT_TRUE(binary);
  EXPECT_EQ(client.exchange({{"type", "audio"}})["error"]["details"]["pointer"], "/robot");
  const std::string elevator = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 1})"))["id"];
  const HttpReply deaf = http(port, "GET", "/api/v1/sessions/" + elevator + "/robots/robot/audio");
  EXPECT_EQ(deaf.status, 404);
  EXPECT_NE(deaf.body.find("does not listen"), std::string::npos);
  EXPECT_TRUE(json_of(http(port, "GET", "/api/v1/sessions/" + elevator + "/robots/robot/sensors"))["microphones"].is_null());
}

TEST(SessionGym, SpacesObservationsActionsAndReset) {
  TestServer server;
  const std::uint16_t port = server.port();
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 4})"))["id"];
  const std::string base = "/api/v1/sessions/" + id;
  const json action_space = json_of(http(port, "GET", base + "/action_space"));
  EXPECT_EQ(action_space["name"], "Box");
  EXPECT_EQ(action_space["shape"], json::array({2}));
  EXPECT_EQ(action_space["dtype"], "float64");
  // The HSR's drive limits (0.8 km/h), forward and back.
  const json hsr = json_of(http(port, "GET", "/api/v1/robots/hsr"))["summary"]["drive"];
  EXPECT_EQ(action_space["high"][0], hsr["max_linear_speed"]);
  EXPECT_EQ(action_space["high"][1], hsr["max_angular_speed"]);
  EXPECT_EQ(action_space["low"][0], -action_space["high"][0].get<double>());
  const json observation_space = json_of(http(port, "GET", base + "/observation_space"));
  ASSERT_EQ(observation_space["shape"], json::array({48}));
  EXPECT_EQ(observation_space["high"][11], "inf") << "a person's velocity is unbounded, spelled out";
  EXPECT_EQ(observation_space["low"][11], "-inf");

  // Forward at full speed for 2 s: the robot moves along its heading; the observation says so.
  const json start = json_of(http(port, "POST", base + "/step", R"({"n": 1, "action": [0, 0]})"));
  ASSERT_EQ(start["observation"].size(), 48u);
  const json moved = json_of(http(port, "POST", base + "/step", R"({"n": 120, "action": [1.0, 0]})"));
  const json& before = start["observation"];
  const json& after = moved["observation"];
  const double travelled = std::hypot(after[0].get<double>() - before[0].get<double>(), after[1].get<double>() - before[1].get<double>());
  EXPECT_GT(travelled, 0.25) << "clipped to 0.22 m/s, minus the motors' start";
  EXPECT_LT(travelled, 0.45);
  EXPECT_NEAR(after[4].get<double>(), hsr["max_linear_speed"].get<double>(), 0.02) << "forward speed";
  EXPECT_EQ(moved["reward"], 0.0) << "no benchmark task: no reward";
  EXPECT_EQ(moved["info"]["tick"], 121);
  for (std::size_t i = 0; i < after.size(); ++i) {
    const json &low = observation_space["low"][i], &high = observation_space["high"][i];
    EXPECT_TRUE(!low.is_number() || after[i].get<double>() >= low.get<double>()) << i;
    EXPECT_TRUE(!high.is_number() || after[i].get<double>() <= high.get<double>()) << i;
  }
  EXPECT_EQ(json_of(http(port, "POST", base + "/step", R"({"action": [1]})"))["error"]["details"]["pointer"], "/action");
  EXPECT_EQ(json_of(http(port, "POST", base + "/step", R"({"action": [1, "x"]})"))["error"]["details"]["pointer"], "/action/1");

  // reset → {observation, info}; the same seed starts from the same observation; options place agents.
  const json reset = json_of(http(port, "POST", base + "/reset", R"({"seed": 4})"));
  EXPECT_EQ(reset["tick"], 0);
  EXPECT_EQ(reset["info"]["tick"], 0);
  ASSERT_EQ(reset["observation"].size(), 48u);
  EXPECT_EQ(reset["observation"], json_of(http(port, "POST", base + "/reset", R"({"seed": 4})"))["observation"]);
  const json placed = json_of(http(port, "POST", base + "/reset", R"({"options": {"poses": {"robot": {"x": 2.0, "y": -1.0, "yaw": 0}}}})"));
  EXPECT_EQ(placed["observation"][0], 2.0);
  EXPECT_EQ(placed["observation"][1], -1.0);
  const HttpReply bad_pose = http(port, "POST", base + "/reset", R"({"options": {"poses": {"robot": {"x": 2.0}}}})");
  EXPECT_EQ(bad_pose.status, 400);
  EXPECT_EQ(json_of(bad_pose)["error"]["details"]["pointer"], "/options/poses/robot/y");
  EXPECT_EQ(json_of(http(port, "GET", base))["tick"], 0) << "the refused reset left the session as it was";
  EXPECT_EQ(json_of(http(port, "POST", base + "/reset", R"({"options": {"speed": 2}})"))["error"]["details"]["pointer"], "/options/speed");

  // A scenario whose robot has no model: its action is a velocity in the map frame.
  const std::string queue = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue"})"))["id"];
  EXPECT_EQ(json_of(http(port, "GET", "/api/v1/sessions/" + queue + "/action_space"))["high"][1], 2.0);
}

TEST(SessionModes, ARealtimeSessionStepsItselfAndAControllerReplacesTheRobots) {
  TestServer server;
  const std::uint16_t port = server.port();
  const HttpReply created = http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue", "mode": "realtime", "realtime_factor": 4})");
  ASSERT_EQ(created.status, 201) << created.body;
  EXPECT_EQ(json_of(created)["mode"], "realtime");
  const std::string id = json_of(created)["id"];
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const json status = json_of(http(port, "GET", "/api/v1/sessions/" + id));
  // 0.5 s of wall clock at 4× is 2 s of simulation; a loaded machine gets less done, never more.
  EXPECT_GT(status["time"].get<double>(), 0.3);
  EXPECT_LE(status["time"].get<double>(), 2.2);
  EXPECT_EQ(http(port, "POST", "/api/v1/sessions/" + id + "/step", "{}").status, 409) << "the server steps it";

  for (const char* body : {R"({"scenario": "queue", "mode": "fast"})", R"({"scenario": "queue", "realtime_factor": 2})",
                           R"({"scenario": "queue", "mode": "realtime", "realtime_factor": 0})"}) {
    EXPECT_EQ(http(port, "POST", "/api/v1/sessions", body).status, 400) << body;
  }
  const HttpReply no_goal = http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "controller": {"type": "goal", "goal": {"radius": 1}}})");
  EXPECT_EQ(no_goal.status, 400) << "a goal says where";
  EXPECT_EQ(json_of(no_goal)["error"]["details"]["pointer"], "/controller/goal");
  const HttpReply driven =
      http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "controller": {"type": "goal", "goal": {"pose": {"x": 1.0, "y": -0.8, "theta": 0}}}})");
  ASSERT_EQ(driven.status, 201) << driven.body;
  EXPECT_EQ(json_of(driven)["controller"]["type"], "goal");
  // The robot now has the goal (the elevator's choreography still moves it first): the observation
  // holds the goal in the robot's frame, which the scenario's idle robot does not have.
  const std::string plain = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator"})"))["id"];
  const json stepped = json_of(http(port, "POST", "/api/v1/sessions/" + json_of(driven)["id"].get<std::string>() + "/step", R"({"n": 1})"));
  const json as_is = json_of(http(port, "POST", "/api/v1/sessions/" + plain + "/step", R"({"n": 1})"));
  const double x = stepped["observation"][0], y = stepped["observation"][1], c = stepped["observation"][2], s = stepped["observation"][3];
  EXPECT_NEAR(stepped["observation"][6].get<double>(), c * (1.0 - x) + s * (-0.8 - y), 1e-9) << "the goal ahead of the robot";
  EXPECT_EQ(as_is["observation"][6], 0.0) << "an idle robot has no goal";

  // Connected clients are counted.
  WebSocketClient client(port, "/api/v1/sessions/" + id + "/ws");
  EXPECT_EQ(json_of(http(port, "GET", "/api/v1/sessions/" + id))["connected_clients"], 1);
}

}  // namespace
}  // namespace hrisim::testing

#include <cstring>
#include <set>

#include "render/image_codec.hpp"
#include "render/scene_renderer.hpp"
#include "sim/camera_scene.hpp"

namespace hrisim::testing {
namespace {

TEST(SessionFrames, CamerasGiveColourDepthAndSegmentationInEveryFormat) {
  TestServer server;
  const std::uint16_t port = server.port();
  const std::string id = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 1})"))["id"];
  const std::string base = "/api/v1/sessions/" + id + "/frames/";
  // The cameras: the overview ones, the HSR's head RGB-D camera with its description's intrinsics and its hand camera.
  const json cameras = json_of(http(port, "GET", "/api/v1/sessions/" + id + "/cameras"));
  std::vector<std::string> names;
  for (const json& camera : cameras["cameras"]) names.push_back(camera["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"overview", "follow", "robot.head_rgbd", "robot.hand_camera"}));
  const json& head = cameras["cameras"][2];
  EXPECT_EQ(head["width"], 640);
  EXPECT_NEAR(head["fx"].get<double>(), 320.0 / std::tan(1.047 / 2), 1e-6) << "from the horizontal field of view";
  EXPECT_GT(cameras["segmentation"].size(), 6u);

  const HttpReply overview = http(port, "GET", base + "overview?width=320&height=240");
  ASSERT_EQ(overview.status, 200) << overview.body;
  EXPECT_EQ(overview.headers.at("content-type"), "image/png");
  const render::ImageRgba8 image = render::decode_png(overview.body);
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 240);
  const std::uint8_t* middle = image.pixel(160, 120);
  EXPECT_FALSE(std::abs(middle[0] - render::kBackground[0] * 255) < 2 && std::abs(middle[2] - render::kBackground[2] * 255) < 2)
      << "the map fills the middle";
  const HttpReply jpeg = http(port, "GET", base + "robot.head_rgbd?format=jpeg&width=256&height=256");
  ASSERT_EQ(jpeg.status, 200);
  EXPECT_EQ(jpeg.headers.at("content-type"), "image/jpeg");
  EXPECT_EQ(jpeg.body.substr(0, 2), "\xFF\xD8");

  // Depth as millimetres in a 16-bit PNG and as metres in .npy agree.
  const HttpReply depth16 = http(port, "GET", base + "robot.head_rgbd?format=depth16&width=256&height=256");
  ASSERT_EQ(depth16.status, 200);
  int w = 0, h = 0;
  const std::vector<std::uint16_t> millimetres = render::decode_depth16(depth16.body, w, h);
  ASSERT_EQ(w, 256);
  ASSERT_EQ(h, 256);
  const HttpReply npy = http(port, "GET", base + "robot.head_rgbd?format=npy&image=depth&width=256&height=256");
  ASSERT_EQ(npy.status, 200);
  ASSERT_EQ(npy.body.substr(0, 6), "\x93NUMPY");
  EXPECT_NE(npy.body.find("'descr': '<f4', 'fortran_order': False, 'shape': (256, 256)"), std::string::npos);
  const std::size_t data = npy.body.size() - 256 * 256 * 4;
  EXPECT_EQ(data % 64, 0u) << "the data starts on a 64-byte boundary";
  int seen = 0;
  for (std::size_t i = 0; i < millimetres.size(); i += 97) {
    float metres = 0.0f;
    std::memcpy(&metres, npy.body.data() + data + 4 * i, 4);
    EXPECT_NEAR(millimetres[i], std::round(metres * 1000.0f), 1.0);
    seen += metres > 0.1f && metres < 10.0f;
  }
  EXPECT_GT(seen, 100) << "the camera sees the room";

  // Segmentation: every id is in the legend.
  const HttpReply ids = http(port, "GET", base + "overview?format=npy&image=segmentation");
  ASSERT_EQ(ids.status, 200);
  std::set<std::uint32_t> legend;
  for (const json& entry : cameras["segmentation"]) legend.insert(entry["id"].get<std::uint32_t>());
  const std::size_t start = ids.body.size() - 640 * 480 * 4;
  std::set<std::uint32_t> found;
  for (std::size_t i = 0; i < 640 * 480; i += 7) {
    std::uint32_t value = 0;
    std::memcpy(&value, ids.body.data() + start + 4 * i, 4);
    if (value != 0) found.insert(value);
  }
  for (const std::uint32_t value : found) EXPECT_TRUE(legend.contains(value)) << value;
  EXPECT_TRUE(found.contains(sim::kFloorId));
  EXPECT_TRUE(std::any_of(found.begin(), found.end(), [](std::uint32_t v) { return v >= sim::kAgentIdBase && v < sim::kAgentIdBase + 100; }))
      << "people seen from above";

  EXPECT_EQ(http(port, "GET", base + "ceiling").status, 404);
  EXPECT_EQ(http(port, "GET", base + "overview?format=bmp").status, 400);
  EXPECT_EQ(http(port, "GET", base + "overview?format=jpeg&image=depth").status, 400);
  EXPECT_EQ(http(port, "GET", base + "overview?image=normals").status, 400);
  EXPECT_EQ(http(port, "GET", base + "overview?width=4").status, 400);
  const std::string crowd = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "perpendicular_crossing"})"))["id"];
  EXPECT_EQ(http(port, "GET", "/api/v1/sessions/" + crowd + "/frames/follow").status, 404) << "no robot to follow";
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

// 300 people cross a hall through each other: a server computing each crowd on three threads
// (--crowd-threads) steps a session to the same state, bit for bit, as one computing it on one.
TEST(SessionCrowdThreads, AServerWithSeveralCrowdThreadsStepsTheSameTrajectory) {
  json scenario = json::parse(R"({"name": "hall", "time_limit": 60,
    "world": {"bounds": {"min": [-0.5, -0.5], "max": [30.5, 30.5]},
              "walls": [{"from": [0, 0], "to": [30, 0]}, {"from": [30, 0], "to": [30, 30]}, {"from": [30, 30], "to": [0, 30]}, {"from": [0, 30], "to": [0, 0]}]},
    "locomotion": {"avoidance": "social_force"}, "humans": [], "steps": [{"name": "cross", "actions": []}]})");
  for (int i = 0; i < 300; ++i) {
    const double x = i < 150 ? 2.0 + (i % 10) * 0.8 : 28.0 - (i % 10) * 0.8, y = 2.0 + (i % 150 / 10) * 1.7;
    const std::string id = "p" + std::to_string(i);
    scenario["humans"].push_back({{"id", id}, {"start", {{"x", x}, {"y", y}}}});
    scenario["steps"][0]["actions"].push_back({{"agent", id}, {"goto", {{"pose", {{"x", 30.0 - x}, {"y", y}}}}}});
  }
  std::vector<json> hashes;
  for (const char* threads : {"1", "3"}) {
    TestServer server({"--crowd-threads", threads});
    const HttpReply stored = http(server.port(), "POST", "/api/v1/scenarios", scenario.dump());
    ASSERT_EQ(stored.status, 201) << stored.body.substr(0, 400);
    const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions",
                                        json{{"scenario", json_of(stored)["summary"]["id"]}, {"seed", 3}}.dump()))["id"];
    ASSERT_EQ(http(server.port(), "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 150})").status, 200);
    hashes.push_back(json_of(http(server.port(), "GET", "/api/v1/sessions/" + id))["state_hash"]);
  }
  EXPECT_EQ(hashes[1], hashes[0]);
}

}  // namespace
}  // namespace hrisim::testing
