// Snapshots as files: downloaded from one server process, they start a session on another that goes on
// bit for bit as the original; a reset can come back to one; a file that is malformed, of another
// version, of another scenario or changed is refused with its place, and leaves no session behind.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

class SnapshotFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    taker_ = new TestServer();
    other_ = new TestServer();
  }
  static void TearDownTestSuite() {
    delete taker_;
    delete other_;
  }
  static json post(std::uint16_t port, const std::string& target, const json& body = json::object()) {
    const HttpReply reply = http(port, "POST", target, body.dump());
    EXPECT_LT(reply.status, 300) << target << ": " << reply.body;
    return json_of(reply);
  }
  /// An elevator session driven by env steps with actions, a robot's request, a placement and ticks,
  /// and a file of its snapshot at tick 300.
  static std::pair<std::string, json> driven_session_and_its_file() {
    const std::uint16_t port = taker_->port();
    const std::string id = post(port, "/api/v1/sessions", {{"scenario", "elevator"}, {"seed", 6}})["id"];
    const std::string session = "/api/v1/sessions/" + id;
    post(port, session + "/step", {{"n", 100}, {"action", {0.2, 0.1}}});
    post(port, session + "/commands", {{"commands", {{{"robot", "robot"}, {"request", "call_elevator_floor2"}}}}});
    EXPECT_EQ(http(port, "PUT", session + "/poses/ada", json{{"x", 1.0}, {"y", 2.0}, {"yaw", 0.5}}.dump()).status, 200);
    post(port, session + "/step", {{"n", 200}});
    const json taken = post(port, session + "/snapshots");
    const HttpReply file = http(port, "GET", session + "/snapshots/" + taken["snapshot"].get<std::string>());
    EXPECT_EQ(file.status, 200) << file.body;
    EXPECT_NE(file.headers.count("content-disposition"), 0u) << "a file to keep";
    return {id, json_of(file)};
  }
  static std::size_t sessions_on(std::uint16_t port) { return json_of(http(port, "GET", "/api/v1/sessions"))["items"].size(); }
  static TestServer* taker_;
  static TestServer* other_;
};
TestServer* SnapshotFiles::taker_ = nullptr;
TestServer* SnapshotFiles::other_ = nullptr;

TEST_F(SnapshotFiles, ADownloadedSnapshotStartsABitIdenticalEpisodeOnAnotherServer) {
  const auto [id, file] = driven_session_and_its_file();
  EXPECT_EQ(file["tick"], 300);
  EXPECT_EQ(file["scenario"], "elevator");
  EXPECT_EQ(file["seed"], 6);
  // The input log, as the API takes inputs, each with its tick.
  const json& inputs = file["inputs"];
  ASSERT_EQ(inputs.size(), 4u) << inputs.dump();
  EXPECT_EQ(inputs[0], (json{{"tick", 0}, {"steps", 100}, {"action", {0.2, 0.1}}}));
  EXPECT_EQ(inputs[1], (json{{"tick", 100}, {"command", {{"robot", "robot"}, {"request", "call_elevator_floor2"}}}}));
  EXPECT_EQ(inputs[2], (json{{"tick", 100}, {"place", "ada"}, {"pose", {{"x", 1.0}, {"y", 2.0}, {"yaw", 0.5}}}}));
  EXPECT_EQ(inputs[3], (json{{"tick", 100}, {"steps", 200}}));
  EXPECT_EQ(json_of(http(taker_->port(), "GET", "/api/v1/sessions/" + id + "/inputs"))["items"], inputs) << "the session's input log is the file's";

  const HttpReply started = http(other_->port(), "POST", "/api/v1/sessions", json{{"snapshot", file}}.dump());
  ASSERT_EQ(started.status, 201) << started.body;
  const json copy = json_of(started);
  EXPECT_EQ(copy["tick"], 300);
  EXPECT_EQ(copy["state_hash"], file["state_hash"]);
  EXPECT_EQ(copy["seed"], 6);
  for (int i = 0; i < 3; ++i) {
    const json step = {{"n", 150}, {"action", {0.1, -0.1}}};
    const json original = post(taker_->port(), "/api/v1/sessions/" + id + "/step", step);
    const json again = post(other_->port(), "/api/v1/sessions/" + copy["id"].get<std::string>() + "/step", step);
    EXPECT_EQ(again["state_hash"], original["state_hash"]) << "after " << 150 * (i + 1) << " more ticks";
  }
}

TEST_F(SnapshotFiles, AResetComesBackToTheFilesMomentWithItsSeed) {
  const auto [id, file] = driven_session_and_its_file();
  const std::string session = "/api/v1/sessions/" + id;
  const json later = post(taker_->port(), session + "/step", {{"n", 120}});
  post(taker_->port(), session + "/reset", {{"seed", 2}});
  const json back = post(taker_->port(), session + "/reset", {{"options", {{"snapshot", file}}}});
  EXPECT_EQ(back["tick"], 300);
  EXPECT_EQ(back["state_hash"], file["state_hash"]);
  EXPECT_EQ(back["seed"], 6);
  EXPECT_TRUE(back.contains("observation")) << "Gymnasium's reset";
  EXPECT_EQ(post(taker_->port(), session + "/step", {{"n", 120}})["state_hash"], later["state_hash"]);
}

TEST_F(SnapshotFiles, BadFilesAreRefusedAtTheirPointerAndLeaveNoSession) {
  const json file = driven_session_and_its_file().second;
  const std::uint16_t port = other_->port();
  const std::size_t before = sessions_on(port);
  const auto refused = [&](json changed, int status, const std::string& pointer, const std::string& words) {
    const HttpReply reply = http(port, "POST", "/api/v1/sessions", json{{"snapshot", std::move(changed)}}.dump());
    EXPECT_EQ(reply.status, status) << pointer << ": " << reply.body;
    if (reply.status < 400) return;
    const json error = json_of(reply)["error"];
    EXPECT_EQ(error["details"].value("pointer", ""), pointer) << reply.body;
    EXPECT_NE(error["message"].get<std::string>().find(words), std::string::npos) << reply.body;
  };
  json changed = file;
  changed["hrisim"]["version"] = "0.0.1";
  refused(changed, 409, "/snapshot/hrisim/version", "taken by hrisim 0.0.1");
  changed = file;
  changed["hrisim_snapshot"] = 2;
  refused(changed, 400, "/snapshot/hrisim_snapshot", "must be 1");
  changed = file;
  changed["state_hash"] = "00000000000000ff";
  refused(changed, 409, "/snapshot/state_hash", "did not reach the state it names");
  changed = file;
  changed["state_hash"] = "xyz";
  refused(changed, 400, "/snapshot/state_hash", "must match the pattern ^[0-9a-f]{16}$");
  changed = file;
  changed["inputs"][1]["command"]["robot"] = "nobody";
  refused(changed, 400, "/snapshot/inputs/1/command/robot", "no agent 'nobody'");
  changed = file;
  changed["inputs"][1]["command"]["request"] = "dance";
  refused(changed, 400, "/snapshot/inputs/1/command/request", "no routine");
  changed = file;
  changed["inputs"][3]["tick"] = 50;
  refused(changed, 400, "/snapshot/inputs/3/tick", "tick");
  changed = file;
  changed["inputs"][3]["steps"] = 150;
  refused(changed, 409, "/snapshot/state_hash", "did not reach");
  changed = file;
  changed["inputs"][2]["tick"] = 101;
  changed["inputs"][3]["tick"] = 101;
  refused(changed, 409, "/snapshot/inputs/2/tick", "given at tick 101");
  changed = file;
  changed["inputs"][0]["dance"] = true;
  refused(changed, 400, "/snapshot/inputs/0/dance", "unknown");
  changed = file;
  changed["scenario_sha256"] = std::string(64, 'a');
  refused(changed, 409, "/snapshot/scenario_sha256", "differs");
  changed = file;
  changed["scenario"] = "no_such_scenario";
  refused(changed, 404, "/snapshot/scenario", "no scenario");
  changed = file;
  changed.erase("seed");
  refused(changed, 400, "/snapshot/seed", "seed");
  refused(json::array(), 400, "/snapshot", "expected object, got array");
  // What a snapshot brings may not be given alongside.
  const HttpReply both = http(port, "POST", "/api/v1/sessions", json{{"snapshot", file}, {"scenario", "elevator"}}.dump());
  EXPECT_EQ(both.status, 400);
  EXPECT_EQ(json_of(both)["error"]["details"]["pointer"], "/snapshot") << "the first form, a scenario, takes no snapshot";
  EXPECT_EQ(sessions_on(port), before) << "no session is left behind by a refused file";

  // A reset to a snapshot of another scenario (or seed given alongside) leaves the session as it was.
  const std::string other = post(port, "/api/v1/sessions", {{"scenario", "queue"}})["id"];
  const json status = post(port, "/api/v1/sessions/" + other + "/step", {{"n", 10}});
  const HttpReply wrong = http(port, "POST", "/api/v1/sessions/" + other + "/reset", json{{"options", {{"snapshot", file}}}}.dump());
  EXPECT_EQ(wrong.status, 409) << wrong.body;
  EXPECT_EQ(json_of(wrong)["error"]["details"]["pointer"], "/options/snapshot/scenario_sha256");
  const HttpReply seeded = http(port, "POST", "/api/v1/sessions/" + other + "/reset", json{{"seed", 1}, {"options", {{"snapshot", file}}}}.dump());
  EXPECT_EQ(seeded.status, 400);
  EXPECT_EQ(json_of(seeded)["error"]["details"]["pointer"], "/seed");
  const json now = json_of(http(port, "GET", "/api/v1/sessions/" + other));
  EXPECT_EQ(now["tick"], status["tick"]);
  EXPECT_EQ(now["state_hash"], status["state_hash"]);
}

}  // namespace
}  // namespace hrisim::testing
