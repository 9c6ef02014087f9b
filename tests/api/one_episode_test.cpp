// One episode loop: every bundled scenario, seed 1, driven four ways — a lockstep session stepped over
// REST, a realtime session, a run, and `hrisim run` replayed by `hrisim render` — gives the same metrics
// and the same final state hash. (Before issue 18 a run never built a benchmark task's episode and a
// realtime session skipped the task's hooks.)
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <thread>

#include "storage/store.hpp"
#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

const std::string kScenarios = std::string(HRISIM_SOURCE_DIR) + "/scenarios";
const std::string kHrisim = "HRISIM_SCENARIOS=" + kScenarios + " " + HRISIM_BINARY;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

/// The end of one episode, as each path reports it.
struct Outcome {
  json metrics;
  std::string state_hash;
  std::string termination;
};

class OneEpisode : public ::testing::TestWithParam<std::string> {
 protected:
  static void SetUpTestSuite() { server_ = new TestServer({"--run-jobs", "1"}); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }

  static Outcome session_metrics(const std::string& id) {
    const json status = json_of(http(port(), "GET", "/api/v1/sessions/" + id));
    const json metrics = json_of(http(port(), "GET", "/api/v1/sessions/" + id + "/metrics"));
    EXPECT_EQ(http(port(), "DELETE", "/api/v1/sessions/" + id).status, 204);
    return {metrics["metrics"], status["state_hash"], status["termination"]};
  }

  static Outcome lockstep(const std::string& scenario) {
    const HttpReply created = http(port(), "POST", "/api/v1/sessions", json{{"scenario", scenario}, {"seed", 1}}.dump());
    EXPECT_EQ(created.status, 201) << created.body;
    const std::string id = json_of(created)["id"];
    for (int request = 0; request < 100; ++request) {
      const json reply = json_of(http(port(), "POST", "/api/v1/sessions/" + id + "/step", json{{"n", 100000}}.dump()));
      if (reply["status"] == "finished") break;
    }
    return session_metrics(id);
  }

  static Outcome realtime(const std::string& scenario) {
    const json body = {{"scenario", scenario}, {"seed", 1}, {"mode", "realtime"}, {"realtime_factor", 100}};
    const HttpReply created = http(port(), "POST", "/api/v1/sessions", body.dump());
    EXPECT_EQ(created.status, 201) << created.body;
    const std::string id = json_of(created)["id"];
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (json_of(http(port(), "GET", "/api/v1/sessions/" + id))["status"] != "finished") {
      if (std::chrono::steady_clock::now() > deadline) {
        ADD_FAILURE() << "the realtime session did not finish within 60 s";
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return session_metrics(id);
  }

  static Outcome run(const std::string& scenario) {
    const HttpReply submitted = http(port(), "POST", "/api/v1/runs", json{{"scenario", scenario}, {"seeds", {1}}}.dump());
    EXPECT_EQ(submitted.status, 201) << submitted.body;
    const json finished = wait_for_run(port(), json_of(submitted)["id"]);
    const json episode = json_of(http(port(), "GET", "/api/v1/episodes/" + finished["episodes"][0]["episode_id"].get<std::string>()));
    return {episode["metrics"], episode["state_hash"], episode["termination"]};
  }

  static TestServer* server_;
};
TestServer* OneEpisode::server_ = nullptr;

TEST_P(OneEpisode, EveryWayOfDrivingItGivesTheSameMetricsAndFinalState) {
  const std::string& scenario = GetParam();
  const Outcome stepped = lockstep(scenario), clocked = realtime(scenario), ran = run(scenario);
  ASSERT_FALSE(stepped.metrics.empty());
  EXPECT_EQ(stepped.state_hash.size(), 16u);
  EXPECT_EQ(clocked.state_hash, stepped.state_hash) << "realtime session";
  EXPECT_EQ(ran.state_hash, stepped.state_hash) << "run";
  EXPECT_EQ(clocked.termination, stepped.termination);
  EXPECT_EQ(ran.termination, stepped.termination);
  for (const auto& [key, value] : stepped.metrics.items()) {
    EXPECT_EQ(clocked.metrics[key], value) << key << " in the realtime session";
    EXPECT_EQ(ran.metrics[key], value) << key << " in the run";
  }

  // The command line: `hrisim run` stores the episode, `hrisim render` replays it to a video.
  const TempDir dir;
  const std::string db = (dir.path() / "cli.db").string();
  const CommandResult cli = run_command(kHrisim + " run " + kScenarios + "/" + scenario + ".json --seeds 1 --db " + db, false);
  ASSERT_EQ(cli.exit_status, 0) << cli.output;
  const json printed = json::parse(cli.output);
  const std::string episode = printed["episodes"][0]["episode_id"];
  const CommandResult replay = run_command(kHrisim + " render " + episode + " --db " + db + " --width 32 --height 32 --fps 1 --out " +
                                               (dir.path() / "replay.mp4").string(),
                                           false);
  ASSERT_EQ(replay.exit_status, 0) << replay.output;
  EXPECT_TRUE(json::parse(replay.output)["matches_stored_episode"].get<bool>()) << "the replay ends in the stored final state";
  const auto stored = storage::Store(db).episode(episode);
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->state_hash, stepped.state_hash) << "hrisim run";
}

INSTANTIATE_TEST_SUITE_P(Bundled, OneEpisode,
                         ::testing::Values("apartment", "apartment_search", "approach_human", "approach_human_apartment", "conversation_group", "corridor_passing",
                                           "elevator", "family_day", "follow_human", "mirror_gesture", "pair_walking", "perpendicular_crossing",
                                           "pick_and_place", "queue", "tea_break"));

}  // namespace
}  // namespace hrisim::testing
