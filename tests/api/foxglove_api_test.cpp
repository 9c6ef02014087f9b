// A session's Foxglove socket against the real server: the upgrade's subprotocol, tokens, tickets and
// Origin as on /ws, the greeting, a client that reads nothing never holds the session up, and a deleted
// session closes the socket. (The protocol itself, with Foxglove's own client: tests/contract.)
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <nlohmann/json.hpp>

#include "test_server.hpp"
#include "websocket_client.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

const std::string kToken = "foxglove-token-0123456789";

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

std::string new_session(std::uint16_t port, const std::string& headers = "") {
  const HttpReply created = http(port, "POST", "/api/v1/sessions", R"({"scenario": "elevator", "seed": 2})", headers);
  EXPECT_EQ(created.status, 201) << created.body;
  return json_of(created)["id"];
}

std::string socket_of(const std::string& id) { return "/api/v1/sessions/" + id + "/foxglove"; }

/// The next text message, past the binary ones (the time) pushed meanwhile.
json next_text(WebSocketClient& client) {
  for (bool binary = true;;) {
    const std::string message = client.next(&binary);
    if (!binary) return json::parse(message);
  }
}

TEST(FoxgloveApi, TheUpgradeAgreesASubprotocolAndTheSocketGreets) {
  TestServer server;
  const std::string id = new_session(server.port());
  const HttpReply refused = upgrade(server.port(), socket_of(id), "Sec-WebSocket-Protocol: ros.bridge\r\n");
  EXPECT_EQ(refused.status, 400);
  EXPECT_NE(refused.body.find("foxglove.sdk.v1 or foxglove.websocket.v1"), std::string::npos) << refused.body;
  EXPECT_EQ(upgrade(server.port(), socket_of(id)).status, 400) << "no subprotocol offered";
  EXPECT_EQ(upgrade(server.port(), socket_of("s00"), "Sec-WebSocket-Protocol: foxglove.sdk.v1\r\n").status, 404);
  EXPECT_EQ(upgrade(server.port(), socket_of(id) + "?rate=0", "Sec-WebSocket-Protocol: foxglove.sdk.v1\r\n").status, 400);

  WebSocketClient client(server.port(), socket_of(id), "", 0, "foxglove.websocket.v1, foxglove.sdk.v1");
  ASSERT_EQ(client.status, 0);
  EXPECT_EQ(client.subprotocol, "foxglove.sdk.v1") << "the SDK's subprotocol first";
  EXPECT_EQ(json::parse(client.next())["op"], "serverInfo");
  EXPECT_EQ(json::parse(client.next())["op"], "advertise");
  EXPECT_EQ(json::parse(client.next())["op"], "advertiseServices");
  client.send_text("[1]");
  EXPECT_EQ(next_text(client)["level"], 2) << "an error status, and the socket stays open";
  client.send_text(R"({"op": "getParameters", "parameterNames": []})");
  EXPECT_EQ(next_text(client)["op"], "status");
  // Nested deeper than any parser's stack: refused before parsing, as text, as a velocity and as a service call.
  const std::string deep(200000, '[');
  client.send_text(deep);
  EXPECT_NE(next_text(client)["message"].get<std::string>().find("nested"), std::string::npos);
  client.send_text(R"({"op": "advertise", "channels": [{"id": 1, "topic": "/cmd_vel", "encoding": "json", "schemaName": "Twist"}]})");
  client.send_binary(std::string("\x01\x01\x00\x00\x00", 5) + deep);
  EXPECT_NE(next_text(client)["message"].get<std::string>().find("nested"), std::string::npos);
  client.send_binary(std::string("\x02\x01\x00\x00\x00\x07\x00\x00\x00\x04\x00\x00\x00json", 17) + deep);
  const json failed = next_text(client);
  EXPECT_EQ(failed["op"], "serviceCallFailure");
  EXPECT_EQ(failed["callId"], 7);
  EXPECT_NE(failed["message"].get<std::string>().find("nested"), std::string::npos);
}

TEST(FoxgloveApi, TokensTicketsAndOriginAreAsOnTheSessionSocket) {
  TestServer server({"--token", "ana:" + kToken});
  const std::string auth = "Authorization: Bearer " + kToken + "\r\n";
  const std::string id = new_session(server.port(), auth);
  const std::string offer = "Sec-WebSocket-Protocol: foxglove.sdk.v1\r\n";
  EXPECT_EQ(upgrade(server.port(), socket_of(id), offer).status, 401);
  EXPECT_EQ(upgrade(server.port(), socket_of(id), offer + auth + "Origin: https://elsewhere.example\r\n").status, 403);
  const std::string ticket = json_of(http(server.port(), "POST", "/api/v1/sessions/" + id + "/ws-ticket", "", auth))["ticket"];
  WebSocketClient browser(server.port(), socket_of(id) + "?ticket=" + ticket, "", 0, "foxglove.sdk.v1");
  ASSERT_EQ(browser.status, 0) << "a ticket opens the Foxglove socket too";
  EXPECT_EQ(json::parse(browser.next())["op"], "serverInfo");
  WebSocketClient with_token(server.port(), socket_of(id), "Bearer " + kToken, 0, "foxglove.sdk.v1");
  EXPECT_EQ(with_token.status, 0);
}

TEST(FoxgloveApi, AClientThatReadsNothingNeverHoldsTheSessionUp) {
  TestServer server;
  const std::string id = new_session(server.port());
  WebSocketClient idle(server.port(), socket_of(id) + "?rate=60&image_rate=60", "", 4096, "foxglove.sdk.v1");
  ASSERT_EQ(idle.status, 0);
  json subscriptions = json::array();
  for (std::uint32_t channel = 1; channel <= 8; ++channel) subscriptions.push_back({{"id", channel}, {"channelId", channel}});
  idle.send({{"op", "subscribe"}, {"subscriptions", subscriptions}});
  // Its frames pile up unread while the session is stepped as fast as REST asks.
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 40; ++i) ASSERT_EQ(http(server.port(), "POST", "/api/v1/sessions/" + id + "/step", R"({"n": 5})").status, 200);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 20.0);
  EXPECT_EQ(json_of(http(server.port(), "GET", "/api/v1/sessions/" + id))["tick"], 200);
  // Still a working socket: what it reads now is a greeting, then what was pushed (old frames dropped).
  EXPECT_EQ(json::parse(idle.next())["op"], "serverInfo");
}

TEST(FoxgloveApi, DeletingTheSessionClosesItsFoxgloveSocket) {
  TestServer server;
  const std::string id = new_session(server.port());
  WebSocketClient client(server.port(), socket_of(id), "", 0, "foxglove.websocket.v1");
  ASSERT_EQ(client.status, 0);
  for (int greeting = 0; greeting < 3; ++greeting) client.next();
  ASSERT_EQ(http(server.port(), "DELETE", "/api/v1/sessions/" + id).status, 204);
  try {
    for (int i = 0; i < 1000; ++i) client.next();  // time messages until the close
  } catch (const std::exception&) {
  }
  EXPECT_EQ(client.close_code(), 1000);
  EXPECT_NE(client.close_reason().find("ended"), std::string::npos) << client.close_reason();
}

}  // namespace
}  // namespace hrisim::testing
