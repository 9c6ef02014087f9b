// Runs over REST against the real server: submit, poll to the end, report with aggregates and gate
// verdict, episodes with trajectories, cancel, list and filter, bad input; and a server killed with
// SIGKILL in the middle of a run.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "storage/store.hpp"
#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

class RunsApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new TestServer({"--run-jobs", "2"}); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static json submit(const json& body) {
    const HttpReply reply = http(port(), "POST", "/api/v1/runs", body.dump());
    EXPECT_EQ(reply.status, 201) << reply.body;
    EXPECT_EQ(reply.headers.at("location"), "/api/v1/runs/" + json_of(reply)["id"].get<std::string>());
    return json_of(reply);
  }
  static TestServer* server_;
};
TestServer* RunsApi::server_ = nullptr;

TEST_F(RunsApi, ARequestNamesItsRoutineAndTheFormerKeyStillWorks) {
  // The queue's robot asks once by itself; one more request at 1 s makes two, whichever key names it.
  const json named = wait_for_run(port(), submit({{"scenario", "queue"}, {"seeds", {2}}, {"requests", {{{"time", 1}, {"routine", "help_robot"}}}}})["id"]);
  const json former = wait_for_run(port(), submit({{"scenario", "queue"}, {"seeds", {2}}, {"requests", {{{"time", 1}, {"task", "help_robot"}}}}})["id"]);
  ASSERT_EQ(named["status"], "finished");
  EXPECT_EQ(named["aggregates"]["requests_sent"]["mean"], 2.0);
  const auto episode_of = [](const json& run) {
    return json_of(http(port(), "GET", "/api/v1/episodes/" + run["episodes"][0]["episode_id"].get<std::string>()));
  };
  EXPECT_EQ(episode_of(named)["state_hash"], episode_of(former)["state_hash"]);
}

TEST_F(RunsApi, ARunEndsWithAggregatesAVerdictAndItsEpisodes) {
  const json submitted = submit({{"scenario", "queue"}, {"seeds", {3, 4, 5}}, {"gates", {"requests_sent.min >= 1", "episode_length.max < 1"}}});
  EXPECT_EQ(submitted["progress"]["total"], 3);
  const json run = wait_for_run(port(), submitted["id"]);
  EXPECT_EQ(run["status"], "finished");
  EXPECT_EQ(run["scenario"], "queue");
  EXPECT_EQ(run["progress"]["finished"], 3);
  ASSERT_EQ(run["episodes"].size(), 3u);
  EXPECT_EQ(run["episodes"][0]["seed"], 3);
  EXPECT_EQ(run["episodes"][0]["status"], "finished");
  // The queue's robot asks once per episode: every statistic of requests_sent is 1.
  const json& sent = run["aggregates"]["requests_sent"];
  EXPECT_EQ(sent["count"], 3);
  EXPECT_EQ(sent["mean"], 1.0);
  EXPECT_EQ(sent["std"], 0.0);
  // One gate passes, one fails, so the verdict fails and names the failing one only.
  const json& verdict = run["verdict"];
  EXPECT_FALSE(verdict["passed"].get<bool>());
  EXPECT_TRUE(verdict["complete"].get<bool>());
  ASSERT_EQ(verdict["gates"].size(), 2u);
  EXPECT_TRUE(verdict["gates"][0]["passed"].get<bool>());
  EXPECT_FALSE(verdict["gates"][1]["passed"].get<bool>());
  ASSERT_EQ(verdict["reasons"].size(), 1u);
  EXPECT_NE(verdict["reasons"][0].get<std::string>().find("episode_length.max < 1"), std::string::npos);

  const json episodes = json_of(http(port(), "GET", "/api/v1/runs/" + run["id"].get<std::string>() + "/episodes"));
  ASSERT_EQ(episodes["items"].size(), 3u);
  const std::string episode_id = run["episodes"][1]["episode_id"];
  const json episode = json_of(http(port(), "GET", "/api/v1/episodes/" + episode_id));
  EXPECT_EQ(episode["seed"], 4);
  EXPECT_EQ(episode["metrics"]["requests_sent"], 1.0);
  EXPECT_TRUE(episode["metrics"]["time_to_goal"].is_null());
  EXPECT_EQ(episode["null_reasons"]["time_to_goal"], "the robot has no navigation goal");
  EXPECT_FALSE(episode["events"].empty());
  // The queue's three choreography steps, each with its duration.
  ASSERT_EQ(episode["step_durations"].size(), 3u);
  EXPECT_EQ(episode["step_durations"][0]["step"], "line_up");
  EXPECT_GT(episode["step_durations"][0]["duration"].get<double>(), 0.0);

  const json trajectory = json_of(http(port(), "GET", "/api/v1/episodes/" + episode_id + "/trajectory"));
  EXPECT_EQ(trajectory["rate"], 10.0);
  const json& robot = trajectory["agents"]["robot"];
  ASSERT_GT(robot.size(), 10u);
  EXPECT_EQ(robot[0]["tick"], 0);
  EXPECT_NEAR(robot[1]["time"].get<double>() - robot[0]["time"].get<double>(), 0.1, 1e-9);
  const HttpReply csv = http(port(), "GET", "/api/v1/episodes/" + episode_id + "/trajectory?format=csv");
  EXPECT_EQ(csv.status, 200);
  EXPECT_EQ(csv.headers.at("content-type"), "text/csv; charset=utf-8");
  EXPECT_EQ(csv.body.substr(0, csv.body.find('\n')), "agent,tick,time,x,y,theta");

  // Per-step series for plots, at 10 Hz like the trajectory.
  const json series = json_of(http(port(), "GET", "/api/v1/episodes/" + episode_id + "/series?name=distance_to_closest_person"));
  ASSERT_EQ(series["items"].size(), 1u);
  const json& distance = series["items"][0];
  EXPECT_EQ(distance["unit"], "m");
  EXPECT_NEAR(distance["dt"].get<double>(), 0.1, 1e-9);
  EXPECT_EQ(distance["ticks"].size(), distance["values"].size());
  EXPECT_EQ(distance["ticks"][1], 6);
  double smallest = 1e9;
  for (const json& value : distance["values"]) {
    if (value.is_number()) smallest = std::min(smallest, value.get<double>());
  }
  EXPECT_GE(smallest, episode["metrics"]["minimum_distance_to_people"].get<double>()) << "sampled at 10 Hz, the minimum at 60 Hz";
  EXPECT_EQ(json_of(http(port(), "GET", "/api/v1/episodes/" + episode_id + "/series"))["items"].size(), 6u) << "every series of GET /api/v1/metrics";
  const HttpReply series_csv = http(port(), "GET", "/api/v1/episodes/" + episode_id + "/series?name=robot_speed&format=csv");
  EXPECT_EQ(series_csv.body.substr(0, series_csv.body.find('\n')), "tick,time,robot_speed");
  EXPECT_EQ(http(port(), "GET", "/api/v1/episodes/" + episode_id + "/series?name=mood").status, 400);
  EXPECT_EQ(http(port(), "GET", "/api/v1/episodes/" + episode_id + "/series?format=csv").status, 400);

  const HttpReply junit = http(port(), "GET", "/api/v1/runs/" + run["id"].get<std::string>() + "/junit");
  EXPECT_EQ(junit.headers.at("content-type"), "application/xml");
  EXPECT_NE(junit.body.find("<failure message=\"episode_length.max is"), std::string::npos) << junit.body;
}

TEST_F(RunsApi, ABaselineWithoutTheRobotGivesTheHumanPathDeviation) {
  const json run = wait_for_run(port(), submit({{"scenario", "corridor_passing"}, {"count", 2}, {"baseline_without_robot", true}})["id"]);
  EXPECT_EQ(run["config"]["baseline_without_robot"], true);
  EXPECT_EQ(run["aggregates"]["human_path_deviation"]["count"], 2);
}

TEST_F(RunsApi, ALiveSessionsMetricsOnDemandEqualTheRunsForTheSameSeed) {
  const std::string session = json_of(http(port(), "POST", "/api/v1/sessions", R"({"scenario": "queue", "seed": 4})"))["id"];
  const json early = json_of(http(port(), "GET", "/api/v1/sessions/" + session + "/metrics"));
  EXPECT_EQ(early["tick"], 0);
  EXPECT_EQ(early["metrics"]["episode_length"], 0.0);
  http(port(), "POST", "/api/v1/sessions/" + session + "/step", R"({"n": 100000})");
  const json live = json_of(http(port(), "GET", "/api/v1/sessions/" + session + "/metrics"));
  const json run = wait_for_run(port(), submit({{"scenario", "queue"}, {"seeds", {4}}})["id"]);
  const json episode = json_of(http(port(), "GET", "/api/v1/episodes/" + run["episodes"][0]["episode_id"].get<std::string>()));
  EXPECT_EQ(live["recorded_until_tick"], live["tick"]);
  EXPECT_EQ(live["metrics"], episode["metrics"]) << "the same seed, stepped over REST or run headless";
  EXPECT_EQ(live["null_reasons"], episode["null_reasons"]);
  EXPECT_EQ(http(port(), "GET", "/api/v1/sessions/snope/metrics").status, 404);
}

TEST_F(RunsApi, TheSameSeedGivesTheSameEpisodeInEveryRun) {
  const json a = wait_for_run(port(), submit({{"scenario", "corridor_passing"}, {"count", 2}, {"first_seed", 7}})["id"]);
  const json b = wait_for_run(port(), submit({{"scenario", "corridor_passing"}, {"seeds", {8}}})["id"]);
  const json first = json_of(http(port(), "GET", "/api/v1/episodes/" + a["episodes"][1]["episode_id"].get<std::string>() + "/trajectory"));
  const json second = json_of(http(port(), "GET", "/api/v1/episodes/" + b["episodes"][0]["episode_id"].get<std::string>() + "/trajectory"));
  EXPECT_EQ(a["episodes"][1]["seed"], 8);
  EXPECT_EQ(first["agents"], second["agents"]);
}

TEST_F(RunsApi, ListFiltersAndPages) {
  const std::string older = submit({{"scenario", "queue"}, {"count", 1}})["id"];
  const std::string id = submit({{"scenario", "pair_walking"}, {"count", 1}})["id"];
  wait_for_run(port(), older);
  wait_for_run(port(), id);
  const json page = json_of(http(port(), "GET", "/api/v1/runs?scenario=pair_walking&limit=1"));
  ASSERT_EQ(page["items"].size(), 1u);
  EXPECT_EQ(page["items"][0]["id"], id);
  EXPECT_EQ(page["items"][0]["scenario"], "pair_walking");
  const json finished = json_of(http(port(), "GET", "/api/v1/runs?status=finished&limit=100"));
  for (const json& run : finished["items"]) EXPECT_EQ(run["status"], "finished");
  // Newest first; the cursor continues after the last item.
  const json first = json_of(http(port(), "GET", "/api/v1/runs?limit=1"));
  const json next = json_of(http(port(), "GET", "/api/v1/runs?limit=1&cursor=" + first["next_cursor"].get<std::string>()));
  ASSERT_EQ(next["items"].size(), 1u);
  EXPECT_NE(next["items"][0]["id"], first["items"][0]["id"]);
  EXPECT_LT(next["items"][0]["created_at"].get<std::string>(), first["items"][0]["created_at"].get<std::string>() + "~");
  EXPECT_EQ(http(port(), "GET", "/api/v1/runs?status=done").status, 400);
  EXPECT_EQ(http(port(), "GET", "/api/v1/runs?cursor=nope").status, 400);
}

TEST_F(RunsApi, CancelStopsARunAndLeavesItsFinishedEpisodes) {
  const json run = submit({{"scenario", "elevator"}, {"count", 200}});
  const std::string id = run["id"];
  const HttpReply cancelled = http(port(), "POST", "/api/v1/runs/" + id + "/cancel");
  EXPECT_EQ(cancelled.status, 202) << cancelled.body;
  EXPECT_EQ(json_of(cancelled)["progress"]["queued"], 0) << "seeds that will never run are cancelled at once";
  const json ended = wait_for_run(port(), id);
  EXPECT_EQ(ended["status"], "cancelled");
  EXPECT_LT(ended["progress"]["finished"].get<int>(), 200);
  EXPECT_EQ(ended["progress"]["cancelled"].get<int>() + ended["progress"]["finished"].get<int>(), 200);
  EXPECT_FALSE(ended["verdict"]["passed"].get<bool>()) << "an incomplete run never passes";
  EXPECT_EQ(http(port(), "POST", "/api/v1/runs/" + id + "/cancel").status, 409);
}

TEST_F(RunsApi, BadSubmissionsAreRefusedAndNothingIsStored) {
  const auto runs_before = json_of(http(port(), "GET", "/api/v1/runs?limit=100"))["items"].size();
  struct Case {
    json body;
    int status;
    std::string pointer;
  };
  const std::vector<Case> cases{
      {{{"scenario", "nowhere"}, {"count", 1}}, 404, "/scenario"},
      {{{"count", 1}}, 400, "/scenario"},
      {{{"scenario", "queue"}}, 400, ""},
      {{{"scenario", "queue"}, {"count", 1}, {"seeds", {1}}}, 400, "/count"},
      {{{"scenario", "queue"}, {"seeds", {1, -2}}}, 400, "/seeds/1"},
      {{{"scenario", "queue"}, {"seeds", {1, 1}}}, 400, "/seeds/1"},
      {{{"scenario", "queue"}, {"count", 0}}, 400, "/count"},
      {{{"scenario", "queue"}, {"seeds", {1}}, {"first_seed", 3}}, 400, "/first_seed"},
      {{{"scenario", "queue"}, {"count", 1}, {"gates", {"collisions.max == 0", "speed.max < 2"}}}, 400, "/gates/1"},
      {{{"scenario", "queue"}, {"count", 1}, {"gates", {"collisions.median == 0"}}}, 400, "/gates/0"},
      {{{"scenario", "queue"}, {"count", 1}, {"gates", {"collisions.max = 0"}}}, 400, "/gates/0"},
      {{{"scenario", "queue"}, {"count", 1}, {"gates", {"collisions.max == many"}}}, 400, "/gates/0"},
      {{{"scenario", "queue"}, {"count", 1}, {"max_time", -1}}, 400, "/max_time"},
      {{{"scenario", "queue"}, {"count", 1}, {"requests", {{{"time", 1}, {"routine", "fly"}}}}}, 400, "/requests/0"},
      {{{"scenario", "queue"}, {"count", 1}, {"requests", {{{"time", 1}, {"routine", "help_robot"}, {"task", "help_robot"}}}}}, 400, "/requests/0"},
      {{{"scenario", "elevator"}, {"count", 1}, {"controller", {{"type", "goal"}, {"goal", {{"radius", 1}}}}}}, 400, "/controller/goal"},
      {{{"scenario", "queue"}, {"count", 1}, {"colour", "red"}}, 400, "/colour"},
      {{{"scenario", "queue"}, {"count", 1}, {"baseline_without_robot", "yes"}}, 400, "/baseline_without_robot"},
  };
  for (const Case& c : cases) {
    const HttpReply reply = http(port(), "POST", "/api/v1/runs", c.body.dump());
    EXPECT_EQ(reply.status, c.status) << c.body.dump() << "\n" << reply.body;
    EXPECT_EQ(json_of(reply)["error"]["details"]["pointer"], c.pointer) << c.body.dump() << "\n" << reply.body;
  }
  EXPECT_EQ(json_of(http(port(), "GET", "/api/v1/runs?limit=100"))["items"].size(), runs_before);
  EXPECT_EQ(http(port(), "GET", "/api/v1/runs/rnope").status, 404);
  EXPECT_EQ(http(port(), "GET", "/api/v1/episodes/enope").status, 404);
  EXPECT_EQ(http(port(), "GET", "/api/v1/episodes/enope/trajectory?format=xml").status, 400);
}

TEST_F(RunsApi, ComparingTwoRunsOfTheElevatorWithDifferentControllers) {
  const json a = wait_for_run(port(), submit({{"scenario", "elevator"}, {"count", 3}, {"max_time", 20}})["id"]);
  const json b = wait_for_run(port(), submit({{"scenario", "elevator"}, {"count", 3}, {"max_time", 20},
                                                {"controller", {{"type", "social"}, {"goal", {{"pose", {{"x", 1.0}, {"y", -0.8}, {"theta", 0}}}}}}}})["id"]);
  const std::string target = "/api/v1/runs/compare?a=" + a["id"].get<std::string>() + "&b=" + b["id"].get<std::string>();
  const json compared = json_of(http(port(), "GET", target));
  EXPECT_EQ(compared["a"], a["id"]);
  EXPECT_EQ(compared["significance_level"], 0.05);
  const json metrics = json_of(http(port(), "GET", "/api/v1/metrics"))["items"];
  ASSERT_EQ(compared["metrics"].size(), metrics.size());
  for (const json& item : compared["metrics"]) {
    if (item["p_value"].is_number()) {
      EXPECT_GE(item["p_value"].get<double>(), 0.0) << item.dump();
      EXPECT_LE(item["p_value"].get<double>(), 1.0) << item.dump();
    }
    EXPECT_EQ(item["test"], item["unit"] == "bool" ? "fisher_exact" : "welch_t") << item.dump();
    const bool significant = item["significant"];
    EXPECT_EQ(significant, item["p_value"].is_number() && item["p_value"].get<double>() < 0.05) << item.dump();
    EXPECT_TRUE(significant || item["change"] == "no significant change") << item.dump();
  }
  // A run against itself: no difference anywhere.
  const json self = json_of(http(port(), "GET", "/api/v1/runs/compare?a=" + a["id"].get<std::string>() + "&b=" + a["id"].get<std::string>()));
  for (const json& item : self["metrics"]) {
    EXPECT_FALSE(item["significant"].get<bool>()) << item.dump();
    EXPECT_TRUE(item["difference"].is_null() || item["difference"] == 0.0) << item.dump();
  }
  EXPECT_EQ(http(port(), "GET", "/api/v1/runs/compare?a=" + a["id"].get<std::string>()).status, 400);
  EXPECT_EQ(http(port(), "GET", "/api/v1/runs/compare?a=rnope&b=" + a["id"].get<std::string>()).status, 404);
}

TEST_F(RunsApi, MetricDefinitionsAreServed) {
  const json metrics = json_of(http(port(), "GET", "/api/v1/metrics"));
  ASSERT_GT(metrics["items"].size(), 20u);
  const auto find = [&](const std::string& key) {
    for (const json& m : metrics["items"]) {
      if (m["key"] == key) return m;
    }
    return json();
  };
  EXPECT_EQ(find("collisions")["better"], "lower");
  EXPECT_EQ(find("collisions")["category"], "contact");
  EXPECT_EQ(find("minimum_distance_to_people")["unit"], "m");
  EXPECT_EQ(find("success")["better"], "higher");
}

/// A thousand generated malformed run requests: nothing is stored, nothing breaks, the file is sound.
TEST(RunsFuzz, MalformedRunRequestsStoreNothing) {
  std::filesystem::path database;
  TestServer server;
  database = server.database();
  const std::uint16_t port = server.port();
  std::mt19937_64 random(11);
  const auto pick = [&](std::size_t n) { return static_cast<std::size_t>(random() % n); };
  const json junk[] = {nullptr, true, -1, 1e308, "x", json::array(), json::object(), 0.5, std::string(300, 'z'), json::array({1, "a"}),
                       "collisions.max ==", json::array({"success.mean >= 2", 3}), json{{"type", "goal"}}, json::array({-5, 1})};
  const auto any = [&] { return junk[pick(std::size(junk))]; };
  std::vector<std::string> accepted;
  const char* keys[] = {"scenario", "seeds", "count", "first_seed", "controller", "max_time", "gates", "requests", "colour"};
  for (int i = 0; i < 1000; ++i) {
    std::string method = "POST", target = "/api/v1/runs", body;
    if (i % 5 == 4) {
      method = pick(2) ? "GET" : "POST";
      target = method == "GET" ? "/api/v1/runs?status=" + any().dump() + "&limit=" + any().dump() + "&cursor=" + std::to_string(i)
                               : "/api/v1/runs/r" + std::to_string(i) + "/cancel";
    } else if (i % 5 == 3) {
      for (std::size_t k = 0, n = pick(80); k < n; ++k) body += static_cast<char>(random() & 0xFF);
    } else {
      // A valid-looking run with at least one field wrong, so nothing may start.
      json request{{"scenario", "queue"}, {"count", 1}};
      request[keys[pick(std::size(keys))]] = any();
      if (request["scenario"] == "queue" && request["count"] == 1 && request.size() == 2) request["gates"] = json::array({"nonsense"});
      body = request.dump();
    }
    const HttpReply reply = http(port, method, target, body);
    ASSERT_LT(reply.status, 500) << i << " " << method << " " << target << " " << body << " → " << reply.body;
    EXPECT_NO_THROW(json_of(reply)) << i;
    // Some generated requests are valid after all (a null controller, no gates): those run.
    if (reply.status == 201) accepted.push_back(json_of(reply)["id"]);
  }
  EXPECT_EQ(http(port, "GET", "/healthz").status, 200);
  ASSERT_LT(accepted.size(), 100u) << "the generator makes mostly malformed requests";
  EXPECT_EQ(json_of(http(port, "GET", "/api/v1/runs?limit=100"))["items"].size(), accepted.size()) << "only accepted runs are stored";
  for (const std::string& id : accepted) wait_for_run(port, id);
  ASSERT_EQ(server.terminate(std::chrono::seconds(20)), 0);
  storage::Store store(database);
  EXPECT_EQ(store.integrity_check(), "ok");
  EXPECT_EQ(store.counts().runs, static_cast<std::int64_t>(accepted.size()));
}

TEST(RunsAfterAKill, ARunKilledMidwayShowsItsLostEpisodesAsInterrupted) {
  std::string id;
  std::filesystem::path database;
  int stored_before_kill = 0;
  TestServer first({"--run-jobs", "1"});
  database = first.database();
  const HttpReply submitted = http(first.port(), "POST", "/api/v1/runs", json{{"scenario", "elevator"}, {"count", 500}}.dump());
  ASSERT_EQ(submitted.status, 201) << submitted.body;
  id = json_of(submitted)["id"];
  // Kill once a few episodes are stored: the next is in flight then.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (json_of(http(first.port(), "GET", "/api/v1/runs/" + id))["progress"]["finished"].get<int>() < 2) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  first.kill_now();
  {
    storage::Store store(database);
    EXPECT_EQ(store.integrity_check(), "ok");
    stored_before_kill = static_cast<int>(store.episode_ids_of_run(id).size());
    EXPECT_EQ(store.run(id)->status, "running") << "nothing ran after the kill to change it";
  }
  // `first` stays: its folder holds the database.
  TestServer second({"--db", database.string()});
  const HttpReply reply = http(second.port(), "GET", "/api/v1/runs/" + id);
  ASSERT_EQ(reply.status, 200) << reply.body;
  const json run = json_of(reply);
  EXPECT_EQ(run["status"], "interrupted");
  EXPECT_EQ(run["progress"]["finished"], stored_before_kill);
  EXPECT_EQ(run["progress"]["interrupted"], 500 - stored_before_kill);
  EXPECT_FALSE(run["verdict"]["passed"].get<bool>());
  // Every stored episode is whole: its metrics and trajectory are there.
  for (const json& episode : run["episodes"]) {
    if (episode["status"] != "finished") continue;
    const json stored = json_of(http(second.port(), "GET", "/api/v1/episodes/" + episode["episode_id"].get<std::string>()));
    EXPECT_FALSE(stored["metrics"].empty());
    EXPECT_FALSE(json_of(http(second.port(), "GET", "/api/v1/episodes/" + episode["episode_id"].get<std::string>() + "/trajectory"))["agents"].empty());
  }
}

}  // namespace
}  // namespace hrisim::testing
