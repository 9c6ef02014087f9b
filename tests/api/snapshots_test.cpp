// Snapshots of live sessions over REST and the WebSocket: restore, then step, gives the states that
// stepping the original gave, bit for bit (with a robot, commands and the physics world); bad input is
// refused with its place, and a reset drops a session's snapshots.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>
#include <vector>

#include "test_server.hpp"
#include "websocket_client.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

class Snapshots : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new TestServer(); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static std::string create(const std::string& scenario) {
    const HttpReply reply = http(port(), "POST", "/api/v1/sessions", json{{"scenario", scenario}, {"seed", 4}}.dump());
    EXPECT_EQ(reply.status, 201) << reply.body;
    return json_of(reply)["id"];
  }
  static json post(const std::string& target, const json& body = json::object()) {
    return json_of(http(port(), "POST", target, body.dump()));
  }
  static TestServer* server_;
};
TestServer* Snapshots::server_ = nullptr;

TEST_F(Snapshots, RestoreThenStepGivesTheOriginalsStatesBitForBit) {
  // The elevator: an HSR with its path follower in the Bullet world, people answering its request.
  const std::string id = create("elevator");
  const std::string session = "/api/v1/sessions/" + id;
  post(session + "/step", {{"n", 300}});
  post(session + "/commands", {{"commands", {{{"robot", "robot"}, {"request", "call_elevator_floor2"}}}}});
  const HttpReply taken = http(port(), "POST", session + "/snapshots", "");
  ASSERT_EQ(taken.status, 201) << taken.body;
  const json snapshot = json_of(taken);
  EXPECT_EQ(snapshot["tick"], 300);
  std::vector<std::string> original;
  for (int i = 0; i < 4; ++i) original.push_back(post(session + "/step", {{"n", 150}})["state_hash"]);

  const HttpReply restored = http(port(), "POST", session + "/restore", json{{"snapshot", snapshot["snapshot"]}}.dump());
  ASSERT_EQ(restored.status, 200) << restored.body;
  EXPECT_EQ(json_of(restored)["tick"], 300);
  EXPECT_EQ(json_of(restored)["state_hash"], snapshot["state_hash"]);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(post(session + "/step", {{"n", 150}})["state_hash"], original[i]) << "after " << 150 * (i + 1) << " ticks";

  // Restoring works from anywhere, again and again; the list names what is kept.
  ASSERT_EQ(http(port(), "POST", session + "/restore", json{{"snapshot", snapshot["snapshot"]}}.dump()).status, 200);
  EXPECT_EQ(post(session + "/step", {{"n", 150}})["state_hash"], original[0]);
  const json list = json_of(http(port(), "GET", session + "/snapshots"));
  ASSERT_EQ(list["items"].size(), 1u);
  EXPECT_EQ(list["items"][0], snapshot);
  EXPECT_EQ(list["max_snapshots"], 32);
  EXPECT_EQ(http(port(), "DELETE", session + "/snapshots/" + snapshot["snapshot"].get<std::string>()).status, 204);
  EXPECT_EQ(http(port(), "DELETE", session + "/snapshots/" + snapshot["snapshot"].get<std::string>()).status, 404);
}

TEST_F(Snapshots, TheWebSocketTakesAndRestoresThemToo) {
  // A benchmark task with actions: the actions are part of what is restored.
  const std::string id = create("approach_human");
  WebSocketClient client(port(), "/api/v1/sessions/" + id + "/ws");
  client.exchange({{"type", "step"}, {"n", 5}, {"action", {0.2, 0.3}}});
  const json snapshot = client.exchange({{"type", "snapshot"}});
  ASSERT_EQ(snapshot["type"], "snapshot") << snapshot.dump();
  const json original = client.exchange({{"type", "step"}, {"n", 20}, {"action", {0.3, -0.2}}});
  const json restored = client.exchange({{"type", "restore"}, {"snapshot", snapshot["snapshot"]}});
  ASSERT_EQ(restored["type"], "restore") << restored.dump();
  EXPECT_EQ(restored["state_hash"], snapshot["state_hash"]);
  EXPECT_EQ(restored["observation"].size(), 11u) << "Gymnasium's observation at the snapshot";
  const json again = client.exchange({{"type", "step"}, {"n", 20}, {"action", {0.3, -0.2}}});
  EXPECT_EQ(again["state_hash"], original["state_hash"]);
  EXPECT_EQ(again["reward"], original["reward"]);
  const json missing = client.exchange({{"type", "restore"}, {"snapshot", "snap-999"}});
  EXPECT_EQ(missing["type"], "error");
  EXPECT_EQ(missing["error"]["details"]["pointer"], "/snapshot");
}

TEST_F(Snapshots, BadInputIsRefusedAndAResetDropsThem) {
  const std::string id = create("queue");
  const std::string session = "/api/v1/sessions/" + id;
  const json snapshot = json_of(http(port(), "POST", session + "/snapshots", "{}"));
  const HttpReply extra = http(port(), "POST", session + "/snapshots", R"({"name": "x"})");
  EXPECT_EQ(extra.status, 400);
  EXPECT_EQ(json_of(extra)["error"]["details"]["pointer"], "/name");
  const HttpReply no_id = http(port(), "POST", session + "/restore", "{}");
  EXPECT_EQ(no_id.status, 400);
  EXPECT_EQ(json_of(no_id)["error"]["details"]["pointer"], "/snapshot");
  const HttpReply wrong_type = http(port(), "POST", session + "/restore", R"({"snapshot": 3})");
  EXPECT_EQ(wrong_type.status, 400);
  const HttpReply unknown = http(port(), "POST", session + "/restore", R"({"snapshot": "snap-999"})");
  EXPECT_EQ(unknown.status, 404);
  EXPECT_NE(json_of(unknown)["error"]["message"].get<std::string>().find("snap-999"), std::string::npos) << unknown.body;
  EXPECT_EQ(http(port(), "POST", "/api/v1/sessions/s0/snapshots", "").status, 404) << "no such session";
  // At most 32 per session.
  for (int i = 1; i < 32; ++i) ASSERT_EQ(http(port(), "POST", session + "/snapshots", "").status, 201);
  const HttpReply full = http(port(), "POST", session + "/snapshots", "");
  EXPECT_EQ(full.status, 409);
  EXPECT_NE(json_of(full)["error"]["message"].get<std::string>().find("maximum of 32"), std::string::npos) << full.body;
  // A reset starts another episode: the old one's snapshots are gone.
  ASSERT_EQ(http(port(), "POST", session + "/reset", "{}").status, 200);
  EXPECT_EQ(http(port(), "POST", session + "/restore", json{{"snapshot", snapshot["snapshot"]}}.dump()).status, 404);
  EXPECT_TRUE(json_of(http(port(), "GET", session + "/snapshots"))["items"].empty());
}

TEST_F(Snapshots, ASeekBackReturnsTheOriginalPassStateHashFromACheckpoint) {
  const std::string id = create("elevator");
  const std::string session = "/api/v1/sessions/" + id;
  const json at_2000 = post(session + "/step", {{"n", 2000}});
  const json at_2999 = post(session + "/step", {{"n", 999}});
  post(session + "/step", {{"n", 1}});

  const HttpReply back = http(port(), "POST", session + "/seek", json{{"tick", 2999}}.dump());
  ASSERT_EQ(back.status, 200) << back.body;
  EXPECT_EQ(json_of(back)["tick"], 2999);
  EXPECT_EQ(json_of(back)["state_hash"], at_2999["state_hash"]);
  // From the checkpoint before it (one about every 600 ticks), not from tick 0.
  EXPECT_LE(json_of(back)["resimulated_ticks"].get<int>(), 1200);

  const json further = post(session + "/seek", {{"tick", 2000}});
  EXPECT_EQ(further["state_hash"], at_2000["state_hash"]);
  EXPECT_EQ(post(session + "/step", {{"n", 999}})["state_hash"], at_2999["state_hash"]) << "forth again, the same states";
  const json forth = post(session + "/seek", {{"tick", 3100}});
  EXPECT_EQ(forth["resimulated_ticks"], 0);
}

TEST_F(Snapshots, AnOwnerHasOneSeekAtATimeSoOthersStepsAreNotStarved) {
  // The elevator kept going (ada waits at the end, a 25-minute limit): a seek 80,000 ticks ahead keeps
  // a worker for seconds.
  std::ifstream file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/elevator.json");
  json elevator = json::parse(file);
  elevator["time_limit"] = 1500;
  elevator["steps"].push_back({{"name", "linger"}, {"actions", json::array({{{"agent", "ada"}, {"wait", {{"duration", 1500}}}}})}});
  const HttpReply uploaded = http(port(), "POST", "/api/v1/scenarios", elevator.dump(), "Content-Type: application/json\r\n");
  ASSERT_EQ(uploaded.status, 201) << uploaded.body;
  const std::string id = create(json_of(uploaded)["summary"]["id"]), other = create("elevator");
  const std::string session = "/api/v1/sessions/" + id;
  std::atomic<bool> done = false;
  HttpReply long_seek;
  std::thread client([&] {
    long_seek = http(port(), "POST", session + "/seek", json{{"tick", 80000}}.dump());
    done = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  // The same owner's next seeks (this server has no owners: everyone is one) wait outside the pool.
  for (const std::string& target : {session, "/api/v1/sessions/" + other}) {
    const HttpReply refused = http(port(), "POST", target + "/seek", json{{"tick", 0}}.dump());
    EXPECT_EQ(refused.status, 503) << refused.body;
    EXPECT_EQ(refused.headers.count("retry-after") ? refused.headers.at("retry-after") : "", "1");
    EXPECT_EQ(json_of(refused)["error"]["details"]["max_simulations"], 1);
  }
  // Another session's step is answered meanwhile, on another worker.
  EXPECT_EQ(http(port(), "POST", "/api/v1/sessions/" + other + "/step", json{{"n", 1}}.dump()).status, 200);
  EXPECT_FALSE(done) << "the step was answered while the seek still ran";
  client.join();
  ASSERT_EQ(long_seek.status, 200) << long_seek.body;
  EXPECT_EQ(json_of(long_seek)["tick"], 80000);
  EXPECT_EQ(http(port(), "POST", session + "/seek", json{{"tick", 79000}}.dump()).status, 200) << "its place is given back";
}

}  // namespace
}  // namespace hrisim::testing
