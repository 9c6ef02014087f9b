// The server's WebSocket machinery for any peer (router.hpp): a subprotocol agreed at the upgrade or
// the upgrade refused, a greeting, binary and text messages both ways, answers that send nothing;
// tickets open any socket of their session. A real http::Server on loopback with a test peer.
#include <gtest/gtest.h>

#include <thread>

#include "api/websocket_client.hpp"
#include "http/access.hpp"
#include "http/server.hpp"

namespace hrisim::http {
namespace {

using testing::WebSocketClient;

/// Greets with one text and one binary message, then echoes each message as it came (text as text,
/// bytes as a binary message); "quiet" gets no answer, "later" an answer made on the worker pool.
class EchoPeer : public WebSocketPeer {
 public:
  explicit EchoPeer(std::string subprotocol) : subprotocol_(std::move(subprotocol)) {}
  std::string subprotocol() const override { return subprotocol_; }
  std::vector<Response> on_open() override {
    return {Response{200, "text/plain", "hello " + subprotocol_, {}, {}}, Response{200, kBinaryContentType, std::string("\x00\x01", 2), {}, {}}};
  }
  Response on_message(const WebSocketMessage& message) override {
    if (!message.binary && message.data == "quiet") return Response::nothing();
    if (!message.binary && message.data == "later") return Response::later([] { return Response{200, "text/plain", "done later", {}, {}}; });
    return Response{200, message.binary ? kBinaryContentType : "text/plain", message.data, {}, {}};
  }

 private:
  std::string subprotocol_;
};

/// A server on a free loopback port whose one socket, /echo, speaks echo.v2 or else echo.v1.
class EchoServer {
 public:
  EchoServer() {
    auto router = std::make_shared<Router>();
    router->add_websocket("/echo", [](const Request& upgrade) {
      return std::make_shared<EchoPeer>(agree_subprotocol(upgrade, {"echo.v2", "echo.v1"}));
    });
    ServerOptions options;
    options.port = 0;
    options.threads = 1;
    options.workers = 1;
    options.log_requests = false;
    server_ = std::make_unique<Server>(options, router);
    thread_ = std::thread([this] { server_->run(); });
  }
  ~EchoServer() {
    server_->stop();
    thread_.join();
  }
  std::uint16_t port() const { return server_->port(); }

 private:
  std::unique_ptr<Server> server_;
  std::thread thread_;
};

Request upgrade_offering(const std::string& subprotocols) {
  Request request;
  request.method = "GET";
  request.path = "/echo";
  if (!subprotocols.empty()) request.headers["sec-websocket-protocol"] = subprotocols;
  return request;
}

TEST(Subprotocols, TheOfferIsReadInTheClientsOrderWithoutSpaces) {
  EXPECT_EQ(offered_subprotocols(upgrade_offering(" b.v1 ,a.v2,,  c ")), (std::vector<std::string>{"b.v1", "a.v2", "c"}));
  EXPECT_TRUE(offered_subprotocols(upgrade_offering("")).empty());
}

TEST(Subprotocols, TheServersFirstChoiceThatIsOfferedIsAgreed) {
  EXPECT_EQ(agree_subprotocol(upgrade_offering("echo.v1, echo.v2"), {"echo.v2", "echo.v1"}), "echo.v2");
  EXPECT_EQ(agree_subprotocol(upgrade_offering("other, echo.v1"), {"echo.v2", "echo.v1"}), "echo.v1");
}

TEST(Subprotocols, AnUpgradeOfferingNoneAcceptedIsRefusedWith400) {
  for (const std::string offer : {"other.v1", ""}) {
    try {
      agree_subprotocol(upgrade_offering(offer), {"echo.v2", "echo.v1"});
      FAIL() << "offer '" << offer << "' was agreed";
    } catch (const core::Error& e) {
      EXPECT_EQ(core::http_status(e.code()), 400);
      EXPECT_NE(std::string(e.what()).find("echo.v2 or echo.v1"), std::string::npos) << e.what();
    }
  }
}

TEST(WebSocketPeers, TheAgreedSubprotocolIsInTheHandshakesAnswer) {
  EchoServer server;
  WebSocketClient older(server.port(), "/echo", "", 0, "echo.v1");
  ASSERT_EQ(older.status, 0);
  EXPECT_EQ(older.subprotocol, "echo.v1");
  EXPECT_EQ(older.next(), "hello echo.v1");
  WebSocketClient newer(server.port(), "/echo", "", 0, "something, echo.v1, echo.v2");
  ASSERT_EQ(newer.status, 0);
  EXPECT_EQ(newer.subprotocol, "echo.v2");
}

TEST(WebSocketPeers, AnUpgradeWithoutAnAcceptedSubprotocolGets400AndNoSocket) {
  EchoServer server;
  const testing::HttpReply refused = testing::upgrade(server.port(), "/echo", "Sec-WebSocket-Protocol: echo.v3\r\n");
  EXPECT_EQ(refused.status, 400);
  EXPECT_NE(refused.body.find("echo.v3"), std::string::npos) << refused.body;
  EXPECT_EQ(testing::upgrade(server.port(), "/echo").status, 400);
  EXPECT_NE(WebSocketClient(server.port(), "/echo", "", 0, "echo.v3").status, 0) << "a client's handshake fails";
}

TEST(WebSocketPeers, TheGreetingComesFirstThenEachMessageIsAnsweredInItsKind) {
  EchoServer server;
  WebSocketClient client(server.port(), "/echo", "", 0, "echo.v2");
  bool binary = true;
  EXPECT_EQ(client.next(&binary), "hello echo.v2");
  EXPECT_FALSE(binary);
  EXPECT_EQ(client.next(&binary), std::string("\x00\x01", 2));
  EXPECT_TRUE(binary);

  const std::string bytes("\x01\x00\xff{\"not\": text}", 15);
  client.send_binary(bytes);
  EXPECT_EQ(client.next(&binary), bytes);
  EXPECT_TRUE(binary) << "bytes in, bytes out";
  client.send_text("quiet");  // no answer: the next message read is the next one's answer
  client.send_text("later");
  EXPECT_EQ(client.next(&binary), "done later");
  EXPECT_FALSE(binary);
  EXPECT_EQ(client.exchange_text("{\"text\": 1}"), "{\"text\": 1}");
}

TEST(WebSocketTickets, ATicketOpensAnySocketOfItsSessionOnly) {
  const auto tickets = std::make_shared<TicketBook>();
  const auto guard = make_guard(AccessPolicy{{{"alice", "a-long-enough-secret-0001", Role::user}}, {}, {}}, tickets);
  const auto upgrade_to = [](const std::string& path, const std::string& ticket) {
    Request request;
    request.method = "GET";
    request.path = path;
    request.query = "ticket=" + ticket;
    request.headers = {{"host", "127.0.0.1"}, {"upgrade", "websocket"}};
    return request;
  };
  Request bridge = upgrade_to("/api/v1/sessions/s1/bridge", tickets->issue("s1", Caller{"alice", false, false}));
  EXPECT_FALSE(guard(bridge).has_value()) << "a ticket opens a bridge's socket as it opens /ws";
  EXPECT_EQ(bridge.caller.owner, "alice");
  Request other = upgrade_to("/api/v1/sessions/s2/bridge", tickets->issue("s1", Caller{"alice", false, false}));
  EXPECT_EQ(guard(other).value().status, 401) << "a ticket is for its session";
  Request deeper = upgrade_to("/api/v1/sessions/s1/bridge/more", tickets->issue("s1", Caller{"alice", false, false}));
  EXPECT_EQ(guard(deeper).value().status, 401) << "a session's sockets are one segment below it";
}

}  // namespace
}  // namespace hrisim::http
