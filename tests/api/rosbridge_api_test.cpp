// A session's rosbridge socket against the real server: the upgrade (no subprotocol, as rosbridge
// clients offer none; 404 for an unknown session; a bad rate refused), tokens, tickets and Origin as on
// /ws, a read-only token that may not drive, a client that reads nothing never holds the session up,
// and a deleted session closes the socket. (The protocol itself, with roslib: tests/contract.)
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <nlohmann/json.hpp>

#include "test_server.hpp"
#include "websocket_client.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

const std::string kToken = "rosbridge-token-0123456789";
const std::string kReader = "rosbridge-reader-0123456789";

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

std::string new_session(std::uint16_t port, const std::string& headers = "") {
  const HttpReply created = http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 2})", headers);
  EXPECT_EQ(created.status, 201) << created.body;
  return json_of(created)["id"];
}

std::string socket_of(const std::string& id) { return "/api/v1/sessions/" + id + "/rosbridge"; }

TEST(RosbridgeApi, TheUpgradeNeedsNoSubprotocolAndAnswersOps) {
  TestServer server;
  const std::string id = new_session(server.port());
  EXPECT_EQ(upgrade(server.port(), socket_of("s00")).status, 404);
  EXPECT_EQ(upgrade(server.port(), socket_of(id) + "?rate=0").status, 400);
  EXPECT_EQ(upgrade(server.port(), socket_of(id) + "?image_rate=61").status, 400);

  WebSocketClient client(server.port(), socket_of(id));
  ASSERT_EQ(client.status, 0);
  EXPECT_EQ(client.subprotocol, "");
  const json version = client.exchange({{"op", "call_service"}, {"service", "/rosapi/get_ros_version"}, {"id", 4}});
  EXPECT_EQ(version, json::parse(R"({"op": "service_response", "service": "/rosapi/get_ros_version", "values": {"version": 2, "distro": "jazzy"}, "result": true, "id": 4})"));
  const json stepped = client.exchange({{"op", "call_service"}, {"service", "/hrisim/step"}, {"args", {{"n", 3}}}});
  EXPECT_EQ(stepped["values"]["tick"], 3) << stepped;
  EXPECT_EQ(json::parse(client.exchange_text("[1]"))["level"], "error") << "an error status, and the socket stays open";
  const json deep = json::parse(client.exchange_text(std::string(100000, '[') + std::string(100000, ']')));
  EXPECT_EQ(deep["level"], "error") << "text nested too deep is refused before it is parsed";
  EXPECT_NE(deep["msg"].get<std::string>().find("nested"), std::string::npos) << deep;
  const json clock = client.exchange({{"op", "subscribe"}, {"topic", "/clock"}});
  EXPECT_EQ(clock["op"], "publish");
  EXPECT_EQ(clock["msg"]["clock"]["nanosec"], std::llround(stepped["values"]["time"].get<double>() * 1e9)) << clock << " at " << stepped;
}

TEST(RosbridgeApi, EachNewSubscriberGetsWhatIsThereNowThenOnlyWhatChanges) {
  TestServer server;
  const std::string id = new_session(server.port());
  WebSocketClient client(server.port(), socket_of(id));
  ASSERT_EQ(client.status, 0);
  const json first = client.exchange({{"op", "subscribe"}, {"topic", "/tf_static"}, {"id", "a"}});
  EXPECT_EQ(first["topic"], "/tf_static");
  // The session stands still: the latched transforms come again only for a new subscription.
  const json again = client.exchange({{"op", "subscribe"}, {"topic", "tf_static"}, {"id", "b"}});
  EXPECT_EQ(again, first);
  EXPECT_EQ(client.exchange({{"op", "unsubscribe"}, {"topic", "/tf_static"}, {"id", "c"}})["level"], "warning");
  client.send({{"op", "unsubscribe"}, {"topic", "/tf_static"}, {"id", "a"}});
  client.send({{"op", "unsubscribe"}, {"topic", "/tf_static"}, {"id", "b"}});
  EXPECT_EQ(client.exchange({{"op", "unsubscribe"}, {"topic", "/tf_static"}})["msg"], "unsubscribe: /tf_static is not subscribed");
}

TEST(RosbridgeApi, ARealtimeSessionIsDrivenAsARobotIs) {
  TestServer server;
  const HttpReply created = http(server.port(), "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 2, "mode": "realtime", "realtime_factor": 4})");
  ASSERT_EQ(created.status, 201) << created.body;
  const std::string id = json_of(created)["id"];
  WebSocketClient client(server.port(), socket_of(id));
  ASSERT_EQ(client.status, 0);
  const json refused = client.exchange({{"op", "call_service"}, {"service", "/hrisim/step"}, {"id", 1}});
  EXPECT_EQ(refused["result"], false);
  EXPECT_NE(refused["values"].get<std::string>().find("the server steps it"), std::string::npos) << refused;
  // Published and left: the server's clock moves the robot, as a robot's own would.
  client.send({{"op", "publish"}, {"topic", "/cmd_vel"}, {"msg", {{"linear", {{"x", 0.15}}}}}});
  const auto seconds = [](const json& odometry) { return odometry["header"]["stamp"]["sec"].get<double>() + odometry["header"]["stamp"]["nanosec"].get<double>() * 1e-9; };
  const json start = client.exchange({{"op", "subscribe"}, {"topic", "/odom"}})["msg"];
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  // The first odometry two simulated seconds after the start (half a second at four times real time),
  // the robot at its speed by then even when the start was read late.
  json later = start;
  for (int read = 0; read < 2000 && seconds(later) < seconds(start) + 2.0; ++read) later = json::parse(client.next())["msg"];
  EXPECT_GT(later["pose"]["pose"]["position"]["x"].get<double>() - start["pose"]["pose"]["position"]["x"].get<double>(), 0.1) << later;
  EXPECT_NEAR(later["twist"]["twist"]["linear"]["x"].get<double>(), 0.15, 0.03);
  client.send({{"op", "unsubscribe"}, {"topic", "/odom"}});

  // throttle_rate: at most one clock a half second, where the socket pushes 30 a second.
  client.send({{"op", "subscribe"}, {"topic", "/clock"}, {"throttle_rate", 500}});
  const auto start_reading = std::chrono::steady_clock::now();
  int clocks = 0;
  while (std::chrono::steady_clock::now() - start_reading < std::chrono::milliseconds(1200)) {
    if (json::parse(client.next())["topic"] == "/clock") ++clocks;
  }
  EXPECT_GE(clocks, 2);
  EXPECT_LE(clocks, 4);
}

TEST(RosbridgeApi, TokensTicketsAndOriginAreAsOnTheSessionSocket) {
  TestServer server({"--token", "ana:" + kToken, "--token", "ana:" + kReader + ":read"});
  const std::string auth = "Authorization: Bearer " + kToken + "\r\n";
  const std::string id = new_session(server.port(), auth);
  EXPECT_EQ(upgrade(server.port(), socket_of(id)).status, 401);
  EXPECT_EQ(upgrade(server.port(), socket_of(id), auth + "Origin: https://elsewhere.example\r\n").status, 403);
  const std::string ticket = json_of(http(server.port(), "POST", "/api/v1/sessions/" + id + "/ws-ticket", "", auth))["ticket"];
  WebSocketClient browser(server.port(), socket_of(id) + "?ticket=" + ticket);
  ASSERT_EQ(browser.status, 0) << "a ticket opens the rosbridge socket too";
  EXPECT_EQ(browser.exchange({{"op", "call_service"}, {"service", "/rosapi/nodes"}})["values"]["nodes"], json::array({"/hrisim"}));

  WebSocketClient reader(server.port(), socket_of(id), "Bearer " + kReader);
  ASSERT_EQ(reader.status, 0);
  const json refused = reader.exchange({{"op", "publish"}, {"topic", "/cmd_vel"}, {"msg", {{"linear", {{"x", 0.1}}}}}});
  EXPECT_EQ(refused["level"], "error");
  EXPECT_NE(refused["msg"].get<std::string>().find("only read"), std::string::npos) << refused;
  const json reset = reader.exchange({{"op", "call_service"}, {"service", "/hrisim/reset"}});
  EXPECT_EQ(reset["result"], false) << reset;
  EXPECT_EQ(reader.exchange({{"op", "call_service"}, {"service", "/rosapi/get_time"}})["result"], true) << "reading is allowed";
}

TEST(RosbridgeApi, AClientThatReadsNothingNeverHoldsTheSessionUp) {
  TestServer server;
  const std::string id = new_session(server.port());
  WebSocketClient idle(server.port(), socket_of(id) + "?rate=60&image_rate=60", "", 4096);
  ASSERT_EQ(idle.status, 0);
  for (const char* topic : {"/clock", "/tf", "/tf_static", "/people_markers", "/people", "/rosout", "/scan", "/odom", "/camera/overview/compressed"}) {
    idle.send({{"op", "subscribe"}, {"topic", topic}, {"compression", "cbor-raw"}});
  }
  // Its messages pile up unread while the session is stepped as fast as REST asks.
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 40; ++i) ASSERT_EQ(http(server.port(), "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 5})").status, 200);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 20.0);
  EXPECT_EQ(json_of(http(server.port(), "GET", "/api/v1/sessions/" + id))["tick"], 200);
  // Still a working socket: what it reads now is what was pushed (old messages dropped), in CBOR.
  bool binary = false;
  idle.next(&binary);
  EXPECT_TRUE(binary);
}

TEST(RosbridgeApi, DeletingTheSessionClosesItsRosbridgeSocket) {
  TestServer server;
  const std::string id = new_session(server.port());
  WebSocketClient client(server.port(), socket_of(id));
  ASSERT_EQ(client.status, 0);
  client.send({{"op", "subscribe"}, {"topic", "/clock"}});
  ASSERT_EQ(http(server.port(), "DELETE", "/api/v1/sessions/" + id).status, 204);
  try {
    for (int i = 0; i < 1000; ++i) client.next();  // clock messages until the close
  } catch (const std::exception&) {
  }
  EXPECT_EQ(client.close_code(), 1000);
  EXPECT_NE(client.close_reason().find("ended"), std::string::npos) << client.close_reason();
}

}  // namespace
}  // namespace hrisim::testing
