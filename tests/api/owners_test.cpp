// Owners (issue 17): every route against the real server, asked by no token, a wrong token, another
// owner, the owner's read-only token, the owner and an admin.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "test_server.hpp"
#include "websocket_client.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

const std::string kAlice = "alice-secret-0123456789", kAliceReader = "alice-reader-0123456789", kBob = "bob-secret-0123456789ab",
                  kRoot = "root-secret-0123456789ab";

std::string bearer(const std::string& secret) { return secret.empty() ? "" : "Authorization: Bearer " + secret + "\r\n"; }

enum class Who { nobody, wrong, other, reader, owner, admin };
const char* name_of(Who who) {
  switch (who) {
    case Who::nobody: return "no token";
    case Who::wrong: return "a wrong token";
    case Who::other: return "another owner";
    case Who::reader: return "the owner's read-only token";
    case Who::owner: return "the owner";
    case Who::admin: return "an admin";
  }
  return "";
}
std::string secret_of(Who who) {
  switch (who) {
    case Who::nobody: return "";
    case Who::wrong: return "not-a-token-0123456789";
    case Who::other: return kBob;
    case Who::reader: return kAliceReader;
    case Who::owner: return kAlice;
    case Who::admin: return kRoot;
  }
  return "";
}

/// What a route is to an owner: open to all, a list or a creation anyone with a token may use, or
/// about one thing of alice's (to read or to change).
enum class Kind { open, list, create, read_own, change_own };

struct Route {
  std::string method, target, body;
  Kind kind;
};

class Owners : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    server_ = new TestServer({"--token", "alice:" + kAlice, "--token", "alice:" + kAliceReader + ":read", "--token", "bob:" + kBob,
                              "--token", "root:" + kRoot + ":admin"});
    const std::uint16_t port = server_->port();
    const std::string alice = bearer(kAlice);
    json scenario = {{"name", "alices room"}, {"world", {{"bounds", {{"min", {0, 0}}, {"max", {6, 6}}}}}},
                     {"humans", {{{"id", "ana"}, {"start", {{"x", 1}, {"y", 1}, {"theta", 0}}}}}},
                     {"robots", {{{"id", "robot"}, {"model", "hsr"}, {"start", {{"x", 4}, {"y", 4}, {"theta", 0}}}}}},
                     {"steps", {{{"name", "walk"}, {"actions", {{{"agent", "ana"}, {"goto", {{"pose", {{"x", 5}, {"y", 1}}}}}}}}}}}};
    const HttpReply uploaded = http(port, "POST", "/api/v1/scenarios", scenario.dump(), alice);
    ASSERT_EQ(uploaded.status, 201) << uploaded.body;
    scenario_ = json_of(uploaded)["summary"]["id"];
    session_ = json_of(http(port, "POST", "/api/v1/sessions", json{{"scenario", scenario_}}.dump(), alice))["id"];
    run_ = json_of(http(port, "POST", "/api/v1/runs", json{{"scenario", scenario_}, {"count", 1}}.dump(), alice))["id"];
    for (int i = 0; i < 600; ++i) {
      const json run = json_of(http(port, "GET", "/api/v1/runs/" + run_, "", alice));
      if (run["status"] == "finished") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    const json episodes = json_of(http(port, "GET", "/api/v1/runs/" + run_ + "/episodes", "", alice));
    ASSERT_EQ(episodes["items"].size(), 1u) << episodes.dump();
    episode_ = episodes["items"][0]["id"];
    const HttpReply video = http(port, "POST", "/api/v1/episodes/" + episode_ + "/videos", json{{"width", 32}, {"fps", 5}}.dump(), alice);
    ASSERT_EQ(video.status, 202) << video.body;
    video_ = json_of(video)["id"];
    for (int i = 0; i < 600 && json_of(http(port, "GET", "/api/v1/videos/" + video_, "", alice))["status"] != "done"; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }

  static std::vector<Route> routes() {
    const std::string s = "/api/v1/sessions/" + session_, r = "/api/v1/runs/" + run_, e = "/api/v1/episodes/" + episode_,
                      c = "/api/v1/scenarios/" + scenario_, v = "/api/v1/videos/" + video_;
    return {
        {"GET", "/healthz", "", Kind::open},
        {"GET", "/api/v1/version", "", Kind::open},
        {"GET", "/api/v1/openapi.json", "", Kind::list},
        {"GET", "/api/v1/robots", "", Kind::list},
        {"GET", "/api/v1/robots/hsr", "", Kind::list},
        {"GET", "/api/v1/metrics", "", Kind::list},
        {"GET", "/api/v1/scenarios", "", Kind::list},
        {"GET", "/api/v1/scenarios/queue", "", Kind::list},
        {"GET", "/api/v1/sessions", "", Kind::list},
        {"GET", "/api/v1/runs", "", Kind::list},
        {"POST", "/api/v1/scenarios/validate", R"({"name": "x", "world": {"bounds": {"min": [0, 0], "max": [2, 2]}}, "steps": []})", Kind::create},
        {"POST", "/api/v1/sessions", R"({"scenario": "queue"})", Kind::create},
        {"GET", c, "", Kind::read_own},
        {"GET", c + "/world", "", Kind::read_own},
        {"GET", c + "/thumbnail?width=64", "", Kind::read_own},
        {"GET", s, "", Kind::read_own},
        {"GET", s + "/state", "", Kind::read_own},
        {"GET", s + "/poses", "", Kind::read_own},
        {"GET", s + "/cameras", "", Kind::read_own},
        {"GET", s + "/metrics", "", Kind::read_own},
        {"GET", s + "/action_space", "", Kind::read_own},
        {"GET", s + "/observation_space", "", Kind::read_own},
        {"GET", s + "/robots/robot/sensors", "", Kind::read_own},
        {"GET", s + "/frames/overview?width=64&height=48", "", Kind::read_own},
        {"GET", r, "", Kind::read_own},
        {"GET", r + "/episodes", "", Kind::read_own},
        {"GET", r + "/junit", "", Kind::read_own},
        {"GET", "/api/v1/runs/compare?a=" + run_ + "&b=" + run_, "", Kind::read_own},
        {"GET", e, "", Kind::read_own},
        {"GET", e + "/trajectory", "", Kind::read_own},
        {"GET", e + "/series?name=robot_speed", "", Kind::read_own},
        {"GET", e + "/cameras", "", Kind::read_own},
        {"GET", v, "", Kind::read_own},
        {"GET", v + "/file", "", Kind::read_own},
        {"POST", s + "/step", R"({"n": 2})", Kind::change_own},
        {"POST", s + "/commands", R"({"commands": [{"human": "ana", "command": "wait 1"}]})", Kind::change_own},
        {"PUT", s + "/poses/ana", R"({"x": 2, "y": 2})", Kind::change_own},
        {"POST", s + "/reset", "{}", Kind::change_own},
        {"POST", r + "/cancel", "", Kind::change_own},
        {"POST", e + "/videos", R"({"width": 32, "fps": 5})", Kind::change_own},
    };
  }

  static TestServer* server_;
  static std::string scenario_, session_, run_, episode_, video_;
};
TestServer* Owners::server_ = nullptr;
std::string Owners::scenario_, Owners::session_, Owners::run_, Owners::episode_, Owners::video_;

TEST_F(Owners, EveryRouteForEveryKindOfCaller) {
  const std::uint16_t port = server_->port();
  for (const Who who : {Who::nobody, Who::wrong, Who::other, Who::reader, Who::owner, Who::admin}) {
    for (const Route& route : routes()) {
      const HttpReply reply = http(port, route.method, route.target, route.body, bearer(secret_of(who)));
      const std::string what = route.method + " " + route.target + " by " + name_of(who) + " → " + std::to_string(reply.status) + " " + reply.body.substr(0, 200);
      const bool authenticated = who != Who::nobody && who != Who::wrong;
      if (route.kind == Kind::open) {
        EXPECT_EQ(reply.status, 200) << what;
      } else if (!authenticated) {
        EXPECT_EQ(reply.status, 401) << what;
      } else if (who == Who::reader && (route.kind == Kind::create || route.kind == Kind::change_own)) {
        EXPECT_EQ(reply.status, 403) << what;
      } else if (who == Who::other && (route.kind == Kind::read_own || route.kind == Kind::change_own)) {
        EXPECT_EQ(reply.status, 404) << what << ": another owner's things are absent to bob";
      } else if (route.target.ends_with("/cancel")) {
        EXPECT_EQ(reply.status, 409) << what << ": the run has ended; the caller may ask";
      } else {
        EXPECT_LT(reply.status, 300) << what;
      }
    }
  }
}

TEST_F(Owners, ListsShowOnlyWhatTheCallerMaySee) {
  const std::uint16_t port = server_->port();
  const auto ids = [&](const std::string& target, Who who) {
    std::vector<std::string> found;
    const json list = json_of(http(port, "GET", target, "", bearer(secret_of(who))));
    for (const json& item : list["items"]) found.push_back(item["id"]);
    return found;
  };
  const auto has = [](const std::vector<std::string>& list, const std::string& id) { return std::find(list.begin(), list.end(), id) != list.end(); };
  for (const auto& [target, id] : std::vector<std::pair<std::string, std::string>>{
           {"/api/v1/sessions", session_}, {"/api/v1/runs", run_}, {"/api/v1/scenarios?limit=200", scenario_}}) {
    EXPECT_TRUE(has(ids(target, Who::owner), id)) << target;
    EXPECT_TRUE(has(ids(target, Who::reader), id)) << target;
    EXPECT_TRUE(has(ids(target, Who::admin), id)) << target;
    EXPECT_FALSE(has(ids(target, Who::other), id)) << target;
  }
  EXPECT_TRUE(has(ids("/api/v1/scenarios?limit=200", Who::other), "queue")) << "bundled scenarios are everyone's";
  // What bob makes is bob's.
  const std::string bobs = json_of(http(port, "POST", "/api/v1/sessions", R"({"scenario": "queue"})", bearer(kBob)))["id"];
  EXPECT_TRUE(has(ids("/api/v1/sessions", Who::other), bobs));
  EXPECT_FALSE(has(ids("/api/v1/sessions", Who::owner), bobs));
  EXPECT_EQ(http(port, "DELETE", "/api/v1/sessions/" + bobs, "", bearer(kAlice)).status, 404);
  EXPECT_EQ(http(port, "DELETE", "/api/v1/sessions/" + bobs, "", bearer(kBob)).status, 204);
}

TEST_F(Owners, WebSocketsAndTicketsFollowTheOwner) {
  const std::uint16_t port = server_->port();
  const std::string socket = "/api/v1/sessions/" + session_ + "/ws";
  EXPECT_EQ(upgrade(port, socket, bearer(kBob)).status, 404);
  EXPECT_EQ(http(port, "POST", "/api/v1/sessions/" + session_ + "/ws-ticket", "", bearer(kBob)).status, 404);
  // The read-only token may watch over a ticket, not step.
  const HttpReply ticket = http(port, "POST", "/api/v1/sessions/" + session_ + "/ws-ticket", "", bearer(kAliceReader));
  ASSERT_EQ(ticket.status, 201) << ticket.body;
  WebSocketClient watcher(port, socket + "?ticket=" + json_of(ticket)["ticket"].get<std::string>());
  ASSERT_EQ(watcher.status, 0);
  EXPECT_EQ(watcher.exchange({{"type", "state"}})["type"], "state");
  const json refused = watcher.exchange({{"type", "step"}});
  EXPECT_EQ(refused["type"], "error");
  EXPECT_EQ(refused["error"]["code"], "forbidden");
  WebSocketClient admin(port, socket, "Bearer " + kRoot);
  EXPECT_EQ(admin.exchange({{"type", "step"}})["type"], "step");
}

}  // namespace
}  // namespace hrisim::testing
