// Hardening (issue 17): each defect found by probing the real server as an attacker or a careless
// client would, reproduced by the request that showed it, then the fixed behaviour asserted.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <atomic>
#include <fstream>
#include <sstream>
#include <thread>

#include "storage/store.hpp"
#include "support/sanitizers.hpp"
#include "test_server.hpp"
#include "websocket_client.hpp"

namespace hrisim::testing {
namespace {

nlohmann::json json_of(const HttpReply& reply) { return nlohmann::json::parse(reply.body); }

bool alive(const TestServer& server) { return http(server.port(), "GET", "/healthz").status == 200; }

/// One raw request on its own connection; its reply.
HttpReply raw(const TestServer& server, const std::string& bytes) {
  RawConnection connection(server.port());
  connection.send(bytes);
  return connection.read_reply();
}

// Defect 1: building a JSON error from text that is not UTF-8 threw where nothing caught it, and the
// process aborted — before authentication.

TEST(Hardening, UpgradeToANonUtf8PathOnATokenServerIsRefusedNotFatal) {
  // GET /\xff with an Upgrade header on a server started with --token.
  TestServer server({"--token", "s3cret-token-0123456789"});
  const HttpReply reply = raw(server,
                              "GET /\xff HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n"
                              "Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n");
  EXPECT_GE(reply.status, 400);
  EXPECT_NO_THROW(json_of(reply)) << "the error is JSON even when it quotes the path";
  EXPECT_TRUE(alive(server));
}

TEST(Hardening, PercentEncodedNonUtf8IdsAre400) {
  // GET /api/v1/runs/%ff (also sessions/, scenarios/, episodes/).
  TestServer server;
  for (const char* target : {"/api/v1/runs/%ff", "/api/v1/sessions/%ff", "/api/v1/scenarios/%ff", "/api/v1/episodes/%ff",
                             "/%ff%fe", "/api/v1/runs/%c0%af"}) {
    const HttpReply reply = http(server.port(), "GET", target);
    EXPECT_EQ(reply.status, 400) << target;
    EXPECT_NE(json_of(reply)["error"]["message"].get<std::string>().find("UTF-8"), std::string::npos) << target;
  }
  EXPECT_TRUE(alive(server));
}

TEST(Hardening, UploadOfUtf8ThatIsNotJsonIs400) {
  // POST /api/v1/scenarios of \xe2\x80\xae\xd9\x85: valid UTF-8, neither JSON nor XML.
  TestServer server;
  const HttpReply reply = http(server.port(), "POST", "/api/v1/scenarios", "\xe2\x80\xae\xd9\x85");
  EXPECT_EQ(reply.status, 400);
  EXPECT_TRUE(alive(server));
  // Not UTF-8 at all, as JSON and as XML.
  EXPECT_EQ(http(server.port(), "POST", "/api/v1/scenarios", "{\"name\": \"\xff\"}").status, 400);
  const HttpReply xml = http(server.port(), "POST", "/api/v1/scenarios?format=pedsim",
                             "<?xml version=\"1.0\"?>\n<scenario>\n<waypoint id=\"w\xff\" x=\"1\" y=\"1\" r=\"1\"/>\n</scenario>",
                             "Content-Type: application/xml\r\n");
  EXPECT_EQ(xml.status, 400);
  ASSERT_FALSE(json_of(xml)["error"]["details"]["errors"].empty()) << xml.body;
  EXPECT_EQ(json_of(xml)["error"]["details"]["errors"][0]["line"], 3) << xml.body;
  EXPECT_TRUE(alive(server));
}

TEST(Hardening, OriginWithByteFFIsRefusedNotFatal) {
  // An Origin header with byte 0xFF, on a WebSocket upgrade and on a plain request.
  TestServer server;
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "corridor_passing"})"))["id"];
  const HttpReply upgrade = raw(server, "GET /api/v1/sessions/" + id +
                                            "/ws HTTP/1.1\r\nHost: 127.0.0.1\r\nOrigin: http://\xff\r\nConnection: Upgrade\r\n"
                                            "Upgrade: websocket\r\nSec-WebSocket-Version: 13\r\n"
                                            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n\r\n");
  EXPECT_EQ(upgrade.status, 403);
  EXPECT_NO_THROW(json_of(upgrade));
  EXPECT_GE(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "corridor_passing"})", "Origin: http://\xff\r\n").status, 400);
  EXPECT_TRUE(alive(server));
}

// Defect 2: world.map opened any file of the server's machine, quoted its start in the error, and read
// /dev/zero without end.

/// A scenario whose world is the ROS map `map`.
std::string scenario_with_map(const std::string& map) {
  nlohmann::json scenario = {{"name", "probe"},
                             {"world", {{"map", map}}},
                             {"humans", {{{"id", "ana"}, {"start", {{"x", 1.0}, {"y", 1.0}, {"theta", 0.0}}}}}},
                             {"steps", nlohmann::json::array()}};
  return scenario.dump();
}

TEST(Hardening, UploadedMapsCannotNameFilesOutsideTheScenarios) {
  // {"world": {"map": "/etc/shadow"}}, "../../../../etc/passwd", /proc/self/environ, /dev/zero.
  TempDir scenarios;
  std::filesystem::create_directories(scenarios / "maps");
  std::ofstream(scenarios / "secret.yaml") << "root:x:0:0\n";
  std::filesystem::create_symlink("/etc/passwd", scenarios / "maps/link.yaml");
  TestServer server({"--scenarios", scenarios.path().string()});
  std::string first_message;
  for (const std::string map : {"/etc/passwd", "/etc/shadow", "../../../../../../etc/passwd", "/proc/self/environ", "/dev/zero",
                                 "maps/../../../../../../../etc/passwd", "maps/link.yaml", "/nonexistent/x.yaml", "absent.yaml"}) {
    const HttpReply reply = http(server.port(), "POST", "/api/v1/scenarios/validate", scenario_with_map(map));
    ASSERT_EQ(reply.status, 200) << map;
    const nlohmann::json result = json_of(reply);
    EXPECT_FALSE(result["valid"].get<bool>()) << map;
    ASSERT_FALSE(result["errors"].empty()) << map;
    const std::string message = result["errors"][0]["message"];
    EXPECT_EQ(result["errors"][0]["pointer"], "/world/map") << map;
    // The same words for every file outside, present or not: nothing tells them apart.
    const std::string without_name = message.substr(message.find("' ") + 2);
    if (first_message.empty()) first_message = without_name;
    EXPECT_EQ(without_name, first_message) << map << ": " << message;
    EXPECT_EQ(reply.body.find("root"), std::string::npos) << map << ": " << reply.body;
  }
  // Inside the scenarios folder is fine, but a map's image may not lead out either.
  std::ofstream(scenarios / "maps/escape.yaml") << "image: ../../../../../../../etc/passwd\nresolution: 0.05\norigin: [0, 0, 0]\n";
  const nlohmann::json escape = json_of(http(server.port(), "POST", "/api/v1/scenarios/validate", scenario_with_map("maps/escape.yaml")));
  EXPECT_FALSE(escape["valid"].get<bool>());
  EXPECT_EQ(escape.dump().find("root"), std::string::npos) << escape.dump();
  EXPECT_TRUE(alive(server));
}

/// A scenario bundled with its ROS map: 4 m × 3 m at 0.1 m, free but for a wall along y = 1.5 m from
/// x = 0 to 2 m; a robot that drives to the east.
nlohmann::json scenario_bundle() {
  std::string pgm = "P5\n40 30\n255\n";
  for (int row = 0; row < 30; ++row) {
    for (int column = 0; column < 40; ++column) pgm.push_back(static_cast<char>(row == 15 && column < 20 ? 0 : 254));
  }
  nlohmann::json scenario = nlohmann::json::parse(scenario_with_map("maps/lab.yaml"));
  scenario["robots"] = {{{"id", "robot"}, {"model", "hsr"}, {"start", {{"x", 0.5}, {"y", 0.5}, {"theta", 0.0}}}}};
  return {{"scenario", scenario},
          {"files", {{"maps/lab.yaml", "image: lab.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"},
                     {"maps/lab.pgm", {{"base64", base64(pgm)}}}}}};
}

TEST(Hardening, AScenarioBringsItsMapAlongAndNothingElseCanBeNamed) {
  // A scenario may reference maps only inside the scenarios folder or uploaded alongside it.
  TempDir data;
  const std::string database = (data / "hrisim.db").string();
  const nlohmann::json bundle = scenario_bundle();
  std::string id;
  {
    TestServer server({"--db", database});
    const nlohmann::json alone = json_of(http(server.port(), "POST", "/api/v1/scenarios/validate", bundle["scenario"].dump()));
    EXPECT_FALSE(alone["valid"].get<bool>()) << "without its files the map is not found";
    const nlohmann::json checked = json_of(http(server.port(), "POST", "/api/v1/scenarios/validate", bundle.dump()));
    EXPECT_TRUE(checked["valid"].get<bool>()) << checked.dump();
    const HttpReply stored = http(server.port(), "POST", "/api/v1/scenarios", bundle.dump());
    ASSERT_EQ(stored.status, 201) << stored.body;
    id = json_of(stored)["summary"]["id"];
    const nlohmann::json world = json_of(http(server.port(), "GET", "/api/v1/scenarios/" + id + "/world"));
    EXPECT_EQ(world.dump().find("hrisim-files"), std::string::npos) << "the private folder is never named";
    // Compiled again with another controller (a session's and a run's): the files are still found.
    const nlohmann::json kGoal = {{"type", "goal"}, {"goal", {{"pose", {{"x", 3.5}, {"y", 0.5}, {"theta", 0.0}}}}}};
    const HttpReply session = http(server.port(), "POST", "/api/v1/sessions",
                                   nlohmann::json{{"scenario", id}, {"controller", kGoal}}.dump());
    EXPECT_EQ(session.status, 201) << session.body;
    const HttpReply run = http(server.port(), "POST", "/api/v1/runs",
                               nlohmann::json{{"scenario", id}, {"count", 1}, {"max_time", 2}, {"controller", kGoal}}.dump());
    EXPECT_EQ(run.status, 201) << run.body;

    // The files' own paths and contents are checked; nothing is stored for a refused upload.
    const auto refused = [&](nlohmann::json changed, const std::string& pointer) {
      const HttpReply reply = http(server.port(), "POST", "/api/v1/scenarios", changed.dump());
      EXPECT_EQ(reply.status, 400) << pointer << ": " << reply.body;
      EXPECT_EQ(json_of(reply)["error"]["details"]["pointer"], pointer) << reply.body;
    };
    for (const std::string path : {"../lab.yaml", "/etc/passwd", "maps//lab.yaml", "maps/./lab.yaml", "maps/lab yaml", ""}) {
      nlohmann::json changed = bundle;
      changed["files"][path] = "x";
      std::string token;
      for (const char c : path) token += c == '/' ? "~1" : std::string(1, c);
      refused(changed, "/files/" + token);
    }
    nlohmann::json bad_base64 = bundle;
    bad_base64["files"]["maps/lab.pgm"]["base64"] = "P5 not base64";
    refused(bad_base64, "/files/maps~1lab.pgm/base64");
    nlohmann::json extra = bundle;
    extra["notes"] = "x";
    refused(extra, "/notes");
    // A bundled map's image may not lead out of the bundle either: same words as a missing file.
    nlohmann::json escape = bundle;
    escape["files"]["maps/lab.yaml"] = "image: ../../../../../../etc/passwd\nresolution: 0.1\norigin: [0, 0, 0]\n";
    const HttpReply escaped = http(server.port(), "POST", "/api/v1/scenarios", escape.dump());
    EXPECT_EQ(escaped.status, 400);
    EXPECT_EQ(escaped.body.find("root"), std::string::npos) << escaped.body;
    EXPECT_EQ(escaped.body.find("hrisim-files"), std::string::npos) << escaped.body;
    std::size_t uploads = 0;
    const nlohmann::json listed = json_of(http(server.port(), "GET", "/api/v1/scenarios?limit=200"));
    for (const auto& item : listed["items"]) uploads += item["origin"] == "uploaded";
    EXPECT_EQ(uploads, 1u) << "only the valid bundle was stored";
  }
  // A new server compiles the upload from the database, its files with it.
  TestServer restarted({"--db", database});
  const HttpReply world = http(restarted.port(), "GET", "/api/v1/scenarios/" + id + "/world");
  ASSERT_EQ(world.status, 200) << world.body;
  EXPECT_NEAR(json_of(world)["bounds"]["max"][0].get<double>(), 4.0, 1e-9) << world.body.substr(0, 300);
}

TEST(Hardening, ALargeMapIsRefusedBeforeItsPixelsAreRead) {
  // A 20000 × 20000 PGM header (4e8 cells) inside the scenarios folder.
  TempDir scenarios;
  std::ofstream(scenarios / "big.pgm", std::ios::binary) << "P5\n20000 20000\n255\n";
  std::ofstream(scenarios / "big.yaml") << "image: big.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  TestServer server({"--scenarios", scenarios.path().string(), "--max-grid-cells", "1000000"});
  const nlohmann::json result = json_of(http(server.port(), "POST", "/api/v1/scenarios/validate", scenario_with_map("big.yaml")));
  EXPECT_FALSE(result["valid"].get<bool>());
  EXPECT_NE(result["errors"][0]["message"].get<std::string>().find("--max-grid-cells"), std::string::npos) << result.dump();
  // The same limit for bounds and a resolution: 1e8 cells.
  nlohmann::json bounds = nlohmann::json::parse(scenario_with_map("x"));
  bounds["world"] = {{"bounds", {{"min", {0, 0}}, {"max", {1000, 1000}}}}, {"resolution", 0.1}};
  const nlohmann::json refused = json_of(http(server.port(), "POST", "/api/v1/scenarios/validate", bounds.dump()));
  EXPECT_FALSE(refused["valid"].get<bool>());
  EXPECT_EQ(refused["errors"][0]["pointer"], "/world/resolution") << refused.dump();
}

// Defect 3: unbounded work from one request.

TEST(Hardening, PedsimClustersMayNotAddUpToMillionsOfPeople) {
  // 600 bytes of Pedsim XML: n="100000" in ten clusters made 1e6 people (28 s CPU, 3.5 GB).
  std::string xml = "<?xml version=\"1.0\"?>\n<scenario>\n<obstacle x1=\"-50\" y1=\"-50\" x2=\"50\" y2=\"-50\"/>\n"
                    "<waypoint id=\"w\" x=\"0\" y=\"0\" r=\"2\"/>\n";
  for (int i = 0; i < 10; ++i) xml += "<agent x=\"0\" y=\"0\" n=\"100000\" dx=\"40\" dy=\"40\" type=\"0\"><addwaypoint id=\"w\"/></agent>\n";
  xml += "</scenario>\n";
  TestServer server({"--max-people", "500"});
  const HttpReply reply = http(server.port(), "POST", "/api/v1/scenarios?format=pedsim", xml, "Content-Type: application/xml\r\n");
  EXPECT_EQ(reply.status, 400);
  EXPECT_NE(reply.body.find("--max-people"), std::string::npos) << reply.body;
  EXPECT_EQ(json_of(reply)["error"]["details"]["errors"][0]["line"], 5) << "the first cluster already passes 500";
}

TEST(Hardening, EpisodesLongerThanTheLimitAreRefused) {
  // A run of a scenario with time_limit or max_time 1e9 that never ends grew by ~210 MB/s.
  TestServer server;
  nlohmann::json scenario = nlohmann::json::parse(scenario_with_map("x"));
  scenario["world"] = {{"bounds", {{"min", {0, 0}}, {"max", {10, 10}}}}};
  scenario["time_limit"] = 1e9;
  const nlohmann::json checked = json_of(http(server.port(), "POST", "/api/v1/scenarios/validate", scenario.dump()));
  EXPECT_FALSE(checked["valid"].get<bool>());
  EXPECT_EQ(checked["errors"][0]["pointer"], "/time_limit") << checked.dump();
  EXPECT_NE(checked["errors"][0]["message"].get<std::string>().find("--max-episode-ticks"), std::string::npos);
  const HttpReply run = http(server.port(), "POST", "/api/v1/runs", R"({"scenario": "queue", "count": 1, "max_time": 1e9})");
  EXPECT_EQ(run.status, 400);
  EXPECT_EQ(json_of(run)["error"]["details"]["pointer"], "/max_time") << run.body;
  EXPECT_EQ(json_of(http(server.port(), "GET", "/api/v1/runs"))["items"].size(), 0u) << "nothing stored";
}

TEST(Hardening, RecordingsOfSessionsAndRunsShareOneBoundedBudget) {
  // Every live session and every run's episode in flight records each tick (packed, ~120 B on
  // family_day); eight sessions of a day and a run's long episodes together had no ceiling.
  TestServer server({"--max-recording-mb", "1", "--run-jobs", "1"});
  const HttpReply created = http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "family_day", "seed": 1})");
  ASSERT_EQ(created.status, 201) << created.body;
  const std::string session = json_of(created)["id"];
  ASSERT_EQ(http(server.port(), "POST", "/api/v1/sessions/" + session + "/step", R"({"n": 20000})").status, 200);
  const nlohmann::json metrics = json_of(http(server.port(), "GET", "/api/v1/sessions/" + session + "/metrics"));
  EXPECT_LT(metrics["recorded_until_tick"].get<std::int64_t>(), metrics["tick"].get<std::int64_t>()) << metrics.dump().substr(0, 300);
  EXPECT_EQ(metrics["recording_stopped"], "the recordings of all sessions and runs hold their maximum of 1 MiB");

  // The session holds the MiB: a run's episode cannot record and ends in error, saying why.
  const HttpReply started = http(server.port(), "POST", "/api/v1/runs", R"({"scenario": "elevator", "count": 1})");
  ASSERT_EQ(started.status, 201) << started.body;
  const std::string run_id = json_of(started)["id"];
  const nlohmann::json run = wait_for_run(server.port(), run_id);
  EXPECT_EQ(run["status"], "failed") << run.dump().substr(0, 400);
  const nlohmann::json episodes = json_of(http(server.port(), "GET", "/api/v1/runs/" + run_id + "/episodes"));
  ASSERT_EQ(episodes["items"].size(), 1u) << episodes.dump().substr(0, 400);
  const nlohmann::json episode = json_of(http(server.port(), "GET", "/api/v1/episodes/" + episodes["items"][0]["id"].get<std::string>()));
  EXPECT_EQ(episode["status"], "error");
  EXPECT_NE(episode.dump().find("--max-recording-mb"), std::string::npos) << episode.dump().substr(0, 600);

  // Deleting the session gives its MiB back: a new session records again.
  ASSERT_EQ(http(server.port(), "DELETE", "/api/v1/sessions/" + session).status, 204);
  const std::string fresh = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 2})"))["id"];
  ASSERT_EQ(http(server.port(), "POST", "/api/v1/sessions/" + fresh + "/step", R"({"n": 100})").status, 200);
  const nlohmann::json again = json_of(http(server.port(), "GET", "/api/v1/sessions/" + fresh + "/metrics"));
  EXPECT_EQ(again["recorded_until_tick"], again["tick"]);
  EXPECT_TRUE(again["recording_stopped"].is_null()) << again["recording_stopped"];
}

// Defect 4: answers queued without limit for a WebSocket client that does not read.

TEST(Hardening, AWebSocketClientThatDoesNotReadIsClosedWith1008) {
  // 100 camera requests (256 × 256 RGB-D, about 0.5 MB each) sent without reading an answer.
  TestServer server({"--max-queued-answers", "4"});
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "elevator"})"))["id"];
  WebSocketClient client(server.port(), "/api/v1/sessions/" + id + "/ws", "", 4096);
  ASSERT_EQ(client.status, 0);
  for (int i = 0; i < 100; ++i) client.send({{"type", "camera"}, {"camera", "overview"}, {"width", 256}, {"height", 256}});
  // Not reading: the socket's buffers fill after a few frames, then the answers queue in the server.
  std::this_thread::sleep_for(std::chrono::seconds(3));
  int answers = 0;
  std::string first;
  try {
    for (; answers < 100; ++answers) {
      const std::string answer = client.next();
      if (first.empty()) first = answer.substr(0, 200);
    }
    client.next();  // the close
  } catch (const std::exception&) {
  }
  EXPECT_GT(first.size(), 100u) << "a camera frame, not " << first;
  EXPECT_EQ(client.close_code(), 1008) << "after " << answers << " answers";
  EXPECT_NE(client.close_reason().find("unread"), std::string::npos) << client.close_reason();
  EXPECT_LT(answers, 100);
  EXPECT_TRUE(alive(server));
}

// Defect 5: out of descriptors, the accept loop spun; WebSockets did not count as connections.

/// CPU time the process has used so far, in clock ticks (utime + stime of /proc/PID/stat).
long cpu_ticks(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(stat, line);
  std::istringstream fields(line.substr(line.rfind(')') + 2));
  std::string field;
  long utime = 0, stime = 0;
  for (int index = 3; index <= 15 && fields >> field; ++index) {
    if (index == 14) utime = std::stol(field);
    if (index == 15) stime = std::stol(field);
  }
  return utime + stime;
}

TEST(Hardening, OutOfDescriptorsTheServerWaitsInsteadOfSpinning) {
  // More connections than descriptors: accept failed with EMFILE in a tight loop (136 % CPU, 6.5 MB/s of log).
  if (kUnderSanitizers) {
    // Their checks need descriptors too (UBSan's vptr check tests memory through a pipe) and fail, aborting the server.
    GTEST_SKIP() << "the sanitizers need descriptors this test takes away";
  }
  TestServer server({}, 64);
  std::vector<std::unique_ptr<RawConnection>> connections;
  for (int i = 0; i < 120; ++i) connections.push_back(std::make_unique<RawConnection>(server.port(), std::chrono::milliseconds(500)));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const long before = cpu_ticks(server.pid());
  std::this_thread::sleep_for(std::chrono::seconds(2));
  const long used = cpu_ticks(server.pid()) - before;
  // Spinning costs a whole core, about 200 ticks in 2 s; waiting costs next to nothing.
  EXPECT_LT(used, 60) << "ticks of CPU in 2 s";
  connections.clear();
  // Descriptors come back and so does service.
  bool served = false;
  for (int attempt = 0; attempt < 50 && !served; ++attempt) {
    try {
      served = http(server.port(), "GET", "/healthz").status == 200;
    } catch (const std::exception&) {
    }
    if (!served) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_TRUE(served);
}

TEST(Hardening, WebSocketsCountAsConnections) {
  // 3,500 WebSockets were admitted with --max-connections 256.
  TestServer server({"--max-connections", "3"});
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "queue"})"))["id"];
  // The creation's connection holds its place until the server has seen it close: retry until the
  // socket is admitted.
  const auto open = [&] {
    for (int attempt = 0;; ++attempt) {
      auto client = std::make_unique<WebSocketClient>(server.port(), "/api/v1/sessions/" + id + "/ws");
      if (client->status == 0 || attempt == 50) return client;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  };
  auto first = open();
  const auto second = open(), third = open();
  ASSERT_EQ(third->status, 0);
  ASSERT_EQ(third->exchange({{"type", "state"}})["type"], "state");
  const HttpReply refused = http(server.port(), "GET", "/healthz");
  EXPECT_EQ(refused.status, 503);
  EXPECT_EQ(refused.headers.count("retry-after"), 1u);
  first.reset();
  bool served = false;
  for (int attempt = 0; attempt < 50 && !served; ++attempt) {
    served = http(server.port(), "GET", "/healthz").status == 200;
    if (!served) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(served) << "a closed WebSocket gives its place back";
}

TEST(Hardening, AWebSocketDroppedWithFramesUnreadGivesItsPlaceBackWhileItsSessionLives) {
  // A socket dropped with pushed frames unread must give its place back though its session lives on.
  // (CI's soak found the server holding such sockets in CLOSE-WAIT until their watch timer's next look,
  // up to a second: a client dropping 60 a second ran out of its 64 connections. The soak's
  // descriptor curve is the test of "at once"; this one has no timing threshold.)
  TestServer server({"--max-connections", "1"});
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "elevator"})"))["id"];
  {
    // The creation's connection holds the only place until the server has seen it close.
    std::unique_ptr<WebSocketClient> viewer;
    for (int attempt = 0; attempt < 50 && (!viewer || viewer->status != 0); ++attempt) {
      if (viewer) std::this_thread::sleep_for(std::chrono::milliseconds(50));
      viewer = std::make_unique<WebSocketClient>(server.port(), "/api/v1/sessions/" + id + "/ws");
    }
    ASSERT_EQ(viewer->status, 0);
    viewer->send({{"type", "subscribe"}, {"rate", 30}, {"camera", {{"name", "overview"}, {"width", 64}, {"height", 48}}}});
    for (int i = 0; i < 10; ++i) viewer->send({{"type", "step"}, {"n", 5}});
    viewer->next();
  }
  bool served = false;
  for (int attempt = 0; attempt < 50 && !served; ++attempt) {
    served = http(server.port(), "GET", "/healthz").status == 200;
    if (!served) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(served) << "the dropped socket still holds its place while its session lives";
}

// Defect 7: I/O threads waited on session locks.

TEST(Hardening, HealthIsAnsweredWhileALongStepHoldsASession) {
  // /healthz waited 6.8 s behind a 100,000-tick step on one session (here with one I/O thread).
  TestServer server({"--threads", "1", "--workers", "2"});
  // Eighty people standing in a room for half an hour: a step of 100,000 ticks takes seconds.
  nlohmann::json crowd = {{"name", "crowd"}, {"time_limit", 1800}, {"world", {{"bounds", {{"min", {0, 0}}, {"max", {20, 20}}}}}},
                          {"humans", nlohmann::json::array()}, {"steps", {{{"name", "stand"}, {"actions", nlohmann::json::array()}}}}};
  for (int i = 0; i < 80; ++i) {
    const std::string person = "p" + std::to_string(i);
    crowd["humans"].push_back({{"id", person}, {"start", {{"x", 1 + (i % 10) * 2}, {"y", 1 + (i / 10) * 2}, {"theta", 0}}}});
    crowd["steps"][0]["actions"].push_back({{"agent", person}, {"wait", {{"duration", 1800}}}});
  }
  const HttpReply uploaded = http(server.port(), "POST", "/api/v1/scenarios", crowd.dump());
  ASSERT_EQ(uploaded.status, 201) << uploaded.body;
  const std::string scenario = json_of(uploaded)["summary"]["id"];
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", nlohmann::json{{"scenario", scenario}}.dump()))["id"];
  std::atomic<bool> step_done{false};
  std::thread stepper([&] {
    RawConnection connection(server.port(), std::chrono::seconds(120));
    // Under the sanitizers ticks are several times slower: fewer still take seconds.
    const std::string body = kUnderSanitizers ? R"({"n": 15000})" : R"({"n": 100000})";
    connection.send("POST /api/v1/sessions/" + id + "/step HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: " +
                    std::to_string(body.size()) + "\r\n\r\n" + body);
    connection.read_reply();
    step_done = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  // A request for the busy session's state waits for it, but not on the I/O thread.
  std::thread reader([&] { http(server.port(), "GET", "/api/v1/sessions/" + id + "/state"); });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const HttpReply health = http(server.port(), "GET", "/healthz");
  const bool answered_during_the_step = !step_done;
  stepper.join();
  reader.join();
  EXPECT_EQ(health.status, 200);
  EXPECT_TRUE(answered_during_the_step) << "health waited for the step";
}

// Defect 8: the token-less default could be driven from any web page.

TEST(Hardening, ForeignPagesCannotDriveATokenlessServer) {
  TestServer server({"--allowed-hosts", "sim.lab.example"});
  const std::uint16_t port = server.port();
  // A text/plain POST from a foreign Origin started a run (201).
  const HttpReply foreign = http(port, "POST", "/api/v1/runs", R"({"scenario": "queue", "count": 1})", "Origin: http://evil.example\r\n");
  EXPECT_EQ(foreign.status, 403);
  const HttpReply plain = http(port, "POST", "/api/v1/runs", R"({"scenario": "queue", "count": 1})", "Content-Type: text/plain\r\n");
  EXPECT_EQ(plain.status, 415);
  EXPECT_EQ(json_of(plain)["error"]["code"], "unsupported_media_type");
  EXPECT_EQ(http(port, "POST", "/api/v1/runs", R"({"scenario": "queue", "count": 1})", "Content-Type: application/x-www-form-urlencoded\r\n").status, 415);
  EXPECT_EQ(json_of(http(port, "GET", "/api/v1/runs"))["items"].size(), 0u) << "nothing started";
  // The Origin is compared with its scheme.
  const std::string own = "127.0.0.1:" + std::to_string(port);
  EXPECT_EQ(http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue"})", "Origin: https://" + own + "\r\n").status, 403);
  EXPECT_EQ(http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue"})", "Origin: http://" + own + "\r\n").status, 403)
      << "the Host the request names is 127.0.0.1 without the port";
  // DNS rebinding: a name the operator did not list.
  RawConnection rebound(port);
  rebound.send("GET /api/v1/runs HTTP/1.1\r\nHost: attacker.example:" + std::to_string(port) + "\r\n\r\n");
  EXPECT_EQ(rebound.read_reply().status, 403);
  RawConnection listed(port);
  listed.send("GET /api/v1/runs HTTP/1.1\r\nHost: sim.lab.example:" + std::to_string(port) + "\r\n\r\n");
  EXPECT_EQ(listed.read_reply().status, 200);
  RawConnection local(port);
  local.send("GET /api/v1/runs HTTP/1.1\r\nHost: localhost:" + std::to_string(port) + "\r\n\r\n");
  EXPECT_EQ(local.read_reply().status, 200);
  // JSON from a client that is not a browser is fine.
  EXPECT_EQ(http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue"})").status, 201);
}

// Defect 9: 256 slow connections filled the global cap; no per-client limit.

TEST(Hardening, OneClientCannotTakeEveryConnection) {
  TestServer server({"--max-connections-per-client", "4"});
  std::vector<std::unique_ptr<RawConnection>> slow;
  for (int i = 0; i < 4; ++i) {
    slow.push_back(std::make_unique<RawConnection>(server.port()));
    slow.back()->send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n");  // never finished
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  RawConnection fifth(server.port());
  fifth.send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  const HttpReply refused = fifth.read_reply();
  EXPECT_EQ(refused.status, 503);
  EXPECT_NE(json_of(refused)["error"]["message"].get<std::string>().find("127.0.0.1"), std::string::npos);
  // Another client (another loopback address) is served.
  RawConnection other(server.port(), std::chrono::seconds(10), "127.0.0.2");
  other.send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(other.read_reply().status, 200);
}

// Defect 10: an open WebSocket kept a deleted or expired session alive.

TEST(Hardening, DeletingASessionClosesItsWebSockets) {
  TestServer server;
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "queue"})"))["id"];
  WebSocketClient client(server.port(), "/api/v1/sessions/" + id + "/ws");
  ASSERT_EQ(client.exchange({{"type", "step"}})["tick"], 1);
  EXPECT_EQ(http(server.port(), "DELETE", "/api/v1/sessions/" + id).status, 204);
  EXPECT_THROW(client.next(), std::exception) << "the socket is closed by the server";
  EXPECT_EQ(client.close_code(), 1000);
  EXPECT_NE(client.close_reason().find("ended"), std::string::npos) << client.close_reason();
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/sessions/" + id).status, 404);
}

// Defect 11: bookkeeping.

TEST(Hardening, ASessionWithASilentWebSocketDoesNotExpire) {
  TestServer server({"--session-idle-timeout", "1"});
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "queue"})"))["id"];
  {
    WebSocketClient silent(server.port(), "/api/v1/sessions/" + id + "/ws");
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    EXPECT_EQ(http(server.port(), "GET", "/api/v1/sessions/" + id).status, 200) << "in use while a socket is open";
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/sessions/" + id).status, 404) << "idle once the socket closed";
}

TEST(Hardening, TheBearerSchemeIsCaseInsensitive) {
  // RFC 7235: "bearer" in lower case was refused.
  TestServer server({"--token", "s3cret-token-0123456789"});
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/runs", "", "Authorization: bearer s3cret-token-0123456789\r\n").status, 200);
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/runs", "", "Authorization: BEARER  s3cret-token-0123456789\r\n").status, 200);
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/runs", "", "Authorization: Basic s3cret-token-0123456789\r\n").status, 401);
}

TEST(Hardening, APlainGetDoesNotSpendAWebSocketTicket) {
  // GET /ws?ticket= without an upgrade consumed the ticket.
  TestServer server({"--token", "s3cret-token-0123456789"});
  const std::string auth = "Authorization: Bearer s3cret-token-0123456789\r\n";
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "queue"})", auth))["id"];
  const std::string ticket = json_of(http(server.port(), "POST", "/api/v1/sessions/" + id + "/ws-ticket", "", auth))["ticket"];
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/sessions/" + id + "/ws?ticket=" + ticket).status, 401);
  WebSocketClient browser(server.port(), "/api/v1/sessions/" + id + "/ws?ticket=" + ticket);
  EXPECT_EQ(browser.status, 0) << "the ticket still opens the socket";
}

TEST(Hardening, AFullDatabaseFailsTheRunAndTheHealthCheck) {
  // On a full disk a failed run listed its unstored episodes as `queued`, and /healthz said ok.
  TestServer server({"--max-database-mb", "1", "--run-jobs", "1"});
  const HttpReply started = http(server.port(), "POST", "/api/v1/runs", R"({"scenario": "elevator", "count": 6})");
  ASSERT_EQ(started.status, 201) << started.body;
  const nlohmann::json run = wait_for_run(server.port(), json_of(started)["id"]);
  EXPECT_EQ(run["status"], "failed") << run.dump().substr(0, 400);
  EXPECT_EQ(run["progress"]["queued"], 0) << "every seed ran";
  EXPECT_GT(run["progress"]["error"].get<int>(), 0) << "the unstored episodes are errors";
  const HttpReply health = http(server.port(), "GET", "/healthz");
  EXPECT_EQ(health.status, 503);
  EXPECT_NE(json_of(health)["database"].get<std::string>().find("writes fail"), std::string::npos) << health.body;
  ASSERT_EQ(server.terminate(std::chrono::seconds(20)), 0);
  EXPECT_EQ(storage::Store(server.database()).integrity_check(), "ok");
}

// Found by fuzzing (fuzz/corpus/*/found-*): each was an internal error (500) or, on a WebSocket and on
// the command line, an uncaught exception.

TEST(Hardening, FuzzFindingsAreClearRefusals) {
  TestServer server({"--token", "s3cret-token-0123456789"});
  const std::string auth = "Authorization: Bearer s3cret-token-0123456789\r\n";
  // An Authorization header whose scheme is followed by spaces only.
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/runs", "", "Authorization: bi//x   \r\n").status, 401);
  // A number beyond a double's range, in a request body and in an uploaded scenario.
  const HttpReply session = http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "queue", "seed": 2e1000})", auth);
  EXPECT_EQ(session.status, 400) << session.body;
  const HttpReply upload = http(server.port(), "POST", "/api/v1/scenarios", R"({"name": "x", "time_limit": 1e999})", auth);
  EXPECT_EQ(upload.status, 400) << upload.body;
  EXPECT_NE(upload.body.find("too large"), std::string::npos) << upload.body;
  const std::string id = json_of(http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "queue"})", auth))["id"];
  WebSocketClient client(server.port(), "/api/v1/sessions/" + id + "/ws", "Bearer s3cret-token-0123456789");
  const nlohmann::json answer = nlohmann::json::parse(client.exchange_text(R"({"type": "step", "n": 444444000000000000000002e1000})"));
  EXPECT_EQ(answer["type"], "error");
  EXPECT_EQ(answer["error"]["code"], "bad_request");
  // A message whose type is not a string.
  const nlohmann::json typed = client.exchange({{"type", 999999999999999}});
  EXPECT_EQ(typed["error"]["code"], "bad_request");
  EXPECT_EQ(typed["error"]["details"]["pointer"], "/type");
  EXPECT_TRUE(alive(server));
}

/// Starts `hrisim run` in the background; its pid.
pid_t start_cli_run(const std::string& arguments) {
  const CommandResult started = run_command("(" + std::string(HRISIM_BINARY) + " run " + arguments + " >/dev/null 2>&1 & echo $!)", false);
  return static_cast<pid_t>(std::stol(started.output));
}

/// Waits until the database holds a run with at least one stored episode; its id.
std::string wait_for_stored_episode(const std::filesystem::path& database) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    if (std::filesystem::exists(database)) {
      storage::Store store(database);
      for (const auto& run : store.runs(10)) {
        if (!store.episode_ids_of_run(run.id).empty()) return run.id;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return "";
}

TEST(Hardening, AKilledCommandLineRunIsFoundInterruptedAndALiveOneIsLeftAlone) {
  // A killed `hrisim run` left its run `running` until a server opened the database.
  TempDir dir;
  const std::filesystem::path database = dir / "runs.db";
  const std::string elevator = std::string(HRISIM_SOURCE_DIR) + "/scenarios/elevator.json";
  const std::string short_run = std::string(HRISIM_BINARY) + " run " + HRISIM_SOURCE_DIR + "/scenarios/queue.json --seed 1 --db " + database.string();
  const pid_t killed = start_cli_run(elevator + " --seeds 1-500 --jobs 1 --db " + database.string());
  const std::string killed_run = wait_for_stored_episode(database);
  ASSERT_FALSE(killed_run.empty());
  kill(killed, SIGKILL);
  waitpid(killed, nullptr, 0);  // not this process's child: its reaper may be slow, a zombie counts as gone
  while (std::filesystem::exists("/proc/" + std::to_string(killed) + "/stat")) {
    std::ifstream stat("/proc/" + std::to_string(killed) + "/stat");
    std::string line;
    std::getline(stat, line);
    if (line.find(") Z ") != std::string::npos || line.empty()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const CommandResult next = run_command(short_run);
  EXPECT_NE(next.output.find("1 run whose process ended marked interrupted"), std::string::npos) << next.output.substr(0, 400);
  EXPECT_EQ(storage::Store(database).run(killed_run)->status, "interrupted");
  // A run in progress in another process, alive, shares the file and is left alone.
  const pid_t alive_pid = start_cli_run(elevator + " --seeds 1001-1500 --jobs 1 --db " + database.string());
  std::string alive_run;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (alive_run.empty() && std::chrono::steady_clock::now() < deadline) {
    for (const auto& run : storage::Store(database).runs(10, "", "running")) alive_run = run.id;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_FALSE(alive_run.empty());
  const CommandResult after = run_command(short_run);
  EXPECT_EQ(after.output.find("marked interrupted"), std::string::npos) << after.output.substr(0, 400);
  EXPECT_EQ(storage::Store(database).run(alive_run)->status, "running") << "its process is alive";
  kill(alive_pid, SIGKILL);
}

}  // namespace
}  // namespace hrisim::testing
