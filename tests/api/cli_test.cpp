// The command line as a user runs it: hrisim validate and hrisim run on real files.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <nlohmann/json.hpp>

#include "storage/store.hpp"
#include "cli_support.hpp"
#include "test_server.hpp"

namespace hrisim::testing {
namespace {


TEST(Cli, ValidateAcceptsTheBundledScenarios) {
  const CommandResult result = run_command(kHrisim + " validate " + kScenarios + "/queue.json " + kScenarios + "/corridor_passing.json");
  EXPECT_EQ(result.exit_status, 0) << result.output;
  EXPECT_NE(result.output.find("queue.json: ok (5 humans, 1 robots, 3 steps)"), std::string::npos) << result.output;
}

TEST(Cli, ValidateListsEveryErrorWithItsPointer) {
  TempDir dir;
  std::ofstream(dir / "bad.json") << R"({"name": "bad", "world": {"bounds": {"min": [0, 0], "max": [5, 5]}},
    "humans": [{"id": "ana", "start": {"x": 9, "y": 1}}],
    "steps": [{"name": "s", "actions": [{"agent": "bob", "wait": {"duration": 1}}]}]})";
  const CommandResult result = run_command(kHrisim + " validate " + (dir / "bad.json").string());
  EXPECT_EQ(result.exit_status, 1);
  EXPECT_NE(result.output.find("/humans/0/start: human 'ana' at (9, 1) is outside the map"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("/steps/0/actions/0/agent: unknown agent 'bob'"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("2 errors"), std::string::npos) << result.output;
}

TEST(Cli, RunPrintsASummaryAndIsReproducible) {
  const std::string command = kHrisim + " run " + kScenarios + "/queue.json --seed 4";
  const CommandResult first = run_command(command, false);
  ASSERT_EQ(first.exit_status, 0) << first.output;
  const auto summary = nlohmann::json::parse(first.output);
  EXPECT_EQ(summary["scenario"], "queue");
  EXPECT_EQ(summary["seed"], 4);
  EXPECT_TRUE(summary["completed"].get<bool>());
  EXPECT_EQ(summary["termination"], "scenario_end");
  EXPECT_EQ(summary["steps"].size(), 3u);
  EXPECT_EQ(summary["events"]["request_accepted"], 1);
  EXPECT_EQ(summary["ticks"].get<std::int64_t>() * summary["dt"].get<double>(), summary["sim_time"].get<double>());
  EXPECT_EQ(nlohmann::json::parse(run_command(command, false).output)["state_hash"], summary["state_hash"]);
}

TEST(Cli, RunStopsAtTheTimeLimitAndNamesTheStep) {
  const CommandResult result = run_command(kHrisim + " run " + kScenarios + "/queue.json --max-time 2 --events", false);
  ASSERT_EQ(result.exit_status, 0);
  const auto summary = nlohmann::json::parse(result.output);
  EXPECT_FALSE(summary["completed"].get<bool>());
  EXPECT_EQ(summary["termination"], "timeout");
  EXPECT_EQ(summary["current_step"]["name"], "line_up");
  EXPECT_EQ(summary["step"], summary["current_step"]);  // the former name, for one version
  EXPECT_EQ(summary["event_log"].back()["kind"], "time_limit");
}

TEST(Cli, RunWithScriptedRequests) {
  const CommandResult result = run_command(kHrisim + " run " + kScenarios + "/queue.json --request 1:help_robot --request 2:help_robot", false);
  ASSERT_EQ(result.exit_status, 0);
  EXPECT_EQ(nlohmann::json::parse(result.output)["events"]["request"], 3) << "two from the command line, one from the file";
}

TEST(Cli, BadArgumentsExitWithTwo) {
  for (const std::string& args : std::vector<std::string>{"run", "run x.json --seed abc", "run " + kScenarios + "/queue.json --request soon",
                                 "run " + kScenarios + "/queue.json --request 1:fly", "run a.json --colour red", "serve --crowd-threads 0"}) {
    const CommandResult result = run_command(kHrisim + " " + args);
    EXPECT_EQ(result.exit_status, 2) << args << "\n" << result.output;
  }
  EXPECT_EQ(run_command(kHrisim + " run /nonexistent.json").exit_status, 2);
}


const std::string kFixtures = std::string(HRISIM_SOURCE_DIR) + "/tests/fixtures";

TEST(CliImport, ImhusToNativeJsonOnStdout) {
  const CommandResult result = run_command(kHrisim + " import --from imhus " + kFixtures + "/imhus/office.xml", false);
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const auto scenario = nlohmann::json::parse(result.output);
  EXPECT_EQ(scenario["name"], "meeting");
  EXPECT_EQ(scenario["steps"].size(), 3u);
  EXPECT_TRUE(scenario.contains("routines") && !scenario.contains("tasks")) << "IMHuS's compound tasks are routines";
  // The output is a valid native scenario.
  TempDir dir;
  std::ofstream(dir / "meeting.json") << result.output;
  EXPECT_EQ(run_command(kHrisim + " validate " + (dir / "meeting.json").string()).exit_status, 0);
}

TEST(CliImport, FormatIsDetectedAndErrorsCarryLines) {
  const CommandResult pedsim = run_command(kHrisim + " import " + kFixtures + "/pedsim/bookshop.xml");
  EXPECT_EQ(pedsim.exit_status, 0);
  EXPECT_NE(pedsim.output.find("bookshop.xml:27: warning: <agent>: the robot agent's route is not walked"), std::string::npos) << pedsim.output;
  TempDir dir;
  std::ofstream(dir / "broken.xml") << "<agents>\n  <human id=\"a\"/>\n</agents>\n<goals>\n  <scenarios>\n    <s>\n      <step>\n"
                                       "        <goto_action entityID=\"a\" poseID=\"nowhere\"/>\n      </step>\n    </s>\n  </scenarios>\n</goals>\n";
  const CommandResult broken = run_command(kHrisim + " import " + (dir / "broken.xml").string());
  EXPECT_EQ(broken.exit_status, 1);
  EXPECT_NE(broken.output.find("broken.xml:8: <goto_action>: unknown pose 'nowhere'"), std::string::npos) << broken.output;
}

TEST(CliImport, AScenarioThatDoesNotValidateIsAnImportError) {
  TempDir dir;
  // A lone agent standing on a wall among walls 0.25 m apart, where no body fits within 1 m: imported
  // as written, refused when validated (one less striped, it would be moved, with a warning).
  std::ofstream xml(dir / "on_wall.xml");
  xml << "<scenario>\n";
  for (int k = 0; k <= 8; ++k) xml << "  <obstacle x1=\"0\" y1=\"" << 3 + 0.25 * k << "\" x2=\"10\" y2=\"" << 3 + 0.25 * k << "\"/>\n";
  xml << "  <agent x=\"5\" y=\"4\" n=\"1\"/>\n</scenario>\n";
  xml.close();
  const CommandResult result = run_command(kHrisim + " import " + (dir / "on_wall.xml").string());
  EXPECT_EQ(result.exit_status, 1) << result.output;
  EXPECT_NE(result.output.find("on_wall.xml:11: /humans/0/start: human 'agent_0' at (5, 4) is inside obstacle"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("on_wall.xml: the imported scenario does not validate (1 error)"), std::string::npos) << result.output;
}

TEST(CliImport, ValidateAndRunTakeTheImportOptions) {
  const CommandResult late = run_command(kHrisim + " validate " + kFixtures + "/imhus/office.xml --scenario solo");
  EXPECT_EQ(late.exit_status, 0) << late.output;
  EXPECT_NE(late.output.find("office.xml: ok (1 humans, 1 robots, 1 steps)"), std::string::npos) << late.output;
  TempDir dir;
  std::filesystem::copy_file(kFixtures + "/pedsim/welcome.xml", dir / "welcome.txt");
  const CommandResult run = run_command(kHrisim + " run --from pedsim " + (dir / "welcome.txt").string() + " --max-time 1", false);
  ASSERT_EQ(run.exit_status, 0) << run.output;
  EXPECT_EQ(nlohmann::json::parse(run.output)["termination"], "timeout");
}

TEST(CliImport, AHuNavSimFileIsReadAndItsFaultsSaidAtTheirLines) {
  TempDir dir;
  std::ofstream(dir / "agents.yaml") << "hunav_loader:\n  ros__parameters:\n    agents:\n      - agent1\n";
  const CommandResult result = run_command(kHrisim + " validate " + (dir / "agents.yaml").string());
  EXPECT_EQ(result.exit_status, 1);
  EXPECT_NE(result.output.find("agents.yaml:4: agent 'agent1' has no block of its parameters"), std::string::npos) << result.output;
  std::ofstream(dir / "map.yaml") << "image: map.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  const CommandResult map = run_command(kHrisim + " validate " + (dir / "map.yaml").string());
  EXPECT_EQ(map.exit_status, 1);
  EXPECT_NE(map.output.find("this is a ROS map YAML: give it with --map"), std::string::npos) << map.output;
}

std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// A bundled scenario's text written with the routine's former keys, as before they were renamed.
std::string with_former_keys(const std::string& scenario) {
  std::string text = file_text(kScenarios + "/" + scenario + ".json");
  for (const auto& [current, former] : {std::pair<std::string, std::string>{"\"routines\":", "\"tasks\":"}, {"\"routine\": \"", "\"task\": \""}}) {
    for (std::size_t at = text.find(current); at != std::string::npos; at = text.find(current, at)) text.replace(at, current.size(), former);
  }
  return text;
}

/// What a command wrote on stdout, and on stderr apart.
struct SplitResult {
  int exit_status;
  std::string out, err;
};

SplitResult run_split(const std::string& command) {
  TempDir dir;
  const CommandResult result = run_command("(" + command + " 2>" + (dir / "stderr").string() + ")", false);
  return {result.exit_status, result.output, file_text(dir / "stderr")};
}

TEST(CliImport, UpgradeRenamesTheFormerKeysAndNothingElse) {
  TempDir dir;
  const std::string old_queue = (dir / "queue.json").string();
  std::ofstream(old_queue) << with_former_keys("queue");
  const CommandResult warned = run_command(kHrisim + " validate " + old_queue);
  EXPECT_EQ(warned.exit_status, 0) << warned.output;
  EXPECT_NE(warned.output.find("queue.json: /tasks: warning: 'tasks' is the former name of 'routines' and will stop being read in the next version; "
                               "run `hrisim import --upgrade FILE`"), std::string::npos) << warned.output;
  EXPECT_NE(warned.output.find("queue.json: /requests/0/task: warning: 'task' is the former name of 'routine'"), std::string::npos) << warned.output;

  const SplitResult upgraded = run_split(kHrisim + " import --upgrade " + old_queue);
  EXPECT_EQ(upgraded.exit_status, 0) << upgraded.err;
  EXPECT_EQ(upgraded.out, file_text(kScenarios + "/queue.json")) << "byte for byte the bundled file";
  EXPECT_EQ(upgraded.err, old_queue + ": /tasks: 'tasks' renamed 'routines'\n" + old_queue + ": /steps/1/actions/0/task: 'task' renamed 'routine'\n" +
                              old_queue + ": /steps/2/actions/0/task: 'task' renamed 'routine'\n" + old_queue + ": /async/0/task: 'task' renamed 'routine'\n" +
                              old_queue + ": /requests/0/task: 'task' renamed 'routine'\n");
  EXPECT_EQ(file_text(old_queue), with_former_keys("queue")) << "stdout only: the file is as it was";

  const std::string run = " run " + old_queue + " --seed 3";
  const std::string before = nlohmann::json::parse(run_command(kHrisim + run, false).output)["state_hash"];
  const SplitResult in_place = run_split(kHrisim + " import --upgrade --in-place " + old_queue);
  EXPECT_EQ(in_place.exit_status, 0) << in_place.err;
  EXPECT_EQ(in_place.out, "");
  EXPECT_NE(in_place.err.find(old_queue + ": upgraded in place (5 keys renamed)"), std::string::npos) << in_place.err;
  EXPECT_EQ(file_text(old_queue), file_text(kScenarios + "/queue.json"));
  const SplitResult valid = run_split(kHrisim + " validate " + old_queue);
  EXPECT_EQ(valid.exit_status, 0);
  EXPECT_EQ(valid.err, "") << "no warnings left";
  EXPECT_EQ(nlohmann::json::parse(run_command(kHrisim + run, false).output)["state_hash"], before) << "the same simulation";
}

TEST(CliImport, UpgradeOfACurrentFileSaysSo) {
  TempDir dir;
  const std::string file = (dir / "elevator.json").string();
  std::filesystem::copy_file(kScenarios + "/elevator.json", file);
  const SplitResult result = run_split(kHrisim + " import --upgrade " + file);
  EXPECT_EQ(result.exit_status, 0);
  EXPECT_EQ(result.err, file + ": already uses the current keys: nothing to upgrade\n");
  EXPECT_EQ(result.out, file_text(file)) << "a pipe still gets the scenario";
  const SplitResult in_place = run_split(kHrisim + " import --upgrade " + file + " --in-place");
  EXPECT_EQ(in_place.exit_status, 0);
  EXPECT_EQ(in_place.out, "");
  EXPECT_EQ(file_text(file), file_text(kScenarios + "/elevator.json"));
}

TEST(CliImport, UpgradeRefusesWhatItCannotUpgrade) {
  TempDir dir;
  const std::string broken = (dir / "broken.json").string();
  std::ofstream(broken) << "{\n  \"name\": \"x\",\n  \"tasks\": {,\n}";
  const SplitResult invalid = run_split(kHrisim + " import --upgrade --in-place " + broken);
  EXPECT_EQ(invalid.exit_status, 1);
  EXPECT_NE(invalid.err.find("broken.json: invalid JSON at line 3, column 13"), std::string::npos) << invalid.err;
  EXPECT_EQ(file_text(broken), "{\n  \"name\": \"x\",\n  \"tasks\": {,\n}");

  const std::string both = (dir / "both.json").string();
  const std::string both_text = R"({"name": "x", "routines": {"a": [{"wait": {"duration": 1}}]}, "tasks": {"a": [{"wait": {"duration": 1}}]}, "steps": []})";
  std::ofstream(both) << both_text;
  const SplitResult twice = run_split(kHrisim + " import --upgrade --in-place " + both);
  EXPECT_EQ(twice.exit_status, 1);
  EXPECT_NE(twice.err.find("both.json: /tasks: 'tasks' is the former name of 'routines', which is given here too: keep only 'routines'"), std::string::npos)
      << twice.err;
  EXPECT_EQ(file_text(both), both_text) << "nothing written";

  std::ofstream(dir / "list.json") << "[1, 2]";
  EXPECT_EQ(run_command(kHrisim + " import --upgrade " + (dir / "list.json").string()).exit_status, 1);
  EXPECT_EQ(run_command(kHrisim + " import --upgrade " + (dir / "none.json").string()).exit_status, 1);
  for (const std::string& args : {"--upgrade " + kFixtures + "/imhus/office.xml", "--upgrade --from imhus " + both, "--in-place " + both}) {
    const CommandResult result = run_command(kHrisim + " import " + args);
    EXPECT_EQ(result.exit_status, 2) << args << "\n" << result.output;
  }
}

TEST(CliImport, RunAcceptsXmlDirectly) {
  const CommandResult result = run_command(kHrisim + " run " + kFixtures + "/imhus/office.xml --request 1:fetch_coffee", false);
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const auto summary = nlohmann::json::parse(result.output);
  EXPECT_TRUE(summary["completed"].get<bool>());
  EXPECT_EQ(summary["events"]["request_accepted"], 1);
}


TEST(Cli, RunWritesTheTrajectoryAtTenHertz) {
  TempDir dir;
  const std::string csv = (dir / "queue.csv").string();
  const CommandResult result =
      run_command(kHrisim + " run " + kScenarios + "/queue.json --max-time 2 --trajectory " + csv, false);
  ASSERT_EQ(result.exit_status, 0) << result.output;
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "time,tick,agent,x,y,theta,vx,vy");
  int rows = 0;
  std::string last;
  while (std::getline(in, line)) {
    ++rows;
    last = line;
  }
  EXPECT_EQ(rows, 6 * 21) << "six agents at t = 0, 0.1, ..., 2.0 s";
  EXPECT_EQ(last.substr(0, last.find(',')), "2") << last;
  EXPECT_EQ(run_command(kHrisim + " run " + kScenarios + "/queue.json --trajectory /nonexistent/x.csv").exit_status, 2);
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

TEST(Cli, RunsSeveralSeedsAndStoresTheEpisodes) {
  TempDir dir;
  const std::string db = (dir.path() / "runs" / "hrisim.db").string();
  const CommandResult result = run_command(kHrisim + " run " + kScenarios + "/queue.json --seeds 3-5 --jobs 2 --db " + db, false);
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(result.output);
  ASSERT_EQ(report["episodes"].size(), 3u);
  EXPECT_EQ(report["episodes"][0]["seed"], 3);
  EXPECT_EQ(report["episodes"][2]["seed"], 5);
  EXPECT_EQ(report["progress"]["finished"], 3);
  EXPECT_EQ(report["aggregates"]["requests_sent"]["count"], 3);
  EXPECT_TRUE(report["verdict"]["passed"].get<bool>()) << "no gates: a complete run passes";
  storage::Store store(db);
  EXPECT_EQ(store.integrity_check(), "ok");
  const auto run = store.run(report["id"]);
  ASSERT_TRUE(run);
  EXPECT_EQ(run->status, "finished");
  const auto ids = store.episode_ids_of_run(run->id);
  ASSERT_EQ(ids.size(), 3u);
  const auto episode = store.episode(report["episodes"][1]["episode_id"]);
  ASSERT_TRUE(episode);
  EXPECT_EQ(episode->seed, 4u);
  EXPECT_EQ(episode->termination_reason, "scenario_end");
  EXPECT_FALSE(episode->events.empty());
  EXPECT_FALSE(episode->metrics.empty());
  // Every agent at 10 Hz: the first sample of each at tick 0.
  EXPECT_EQ(episode->trajectory.front().tick, 0);
  EXPECT_GT(episode->trajectory.size(), 10u);
  // The same seed alone, in another run, gives the same episode.
  const CommandResult alone = run_command(kHrisim + " run " + kScenarios + "/queue.json --seed 4 --db " + db, false);
  ASSERT_EQ(alone.exit_status, 0) << alone.output;
  const auto again = store.episode(nlohmann::json::parse(alone.output)["episodes"][0]["episode_id"]);
  ASSERT_TRUE(again);
  ASSERT_EQ(again->trajectory.size(), episode->trajectory.size());
  for (std::size_t i = 0; i < episode->trajectory.size(); ++i) {
    EXPECT_EQ(again->trajectory[i].x, episode->trajectory[i].x);
    EXPECT_EQ(again->trajectory[i].y, episode->trajectory[i].y);
  }
  // Runs of the same file reuse its scenario record.
  EXPECT_EQ(store.counts().scenarios, 1);
  EXPECT_EQ(store.counts().episodes, 4);
}

TEST(Cli, OneOrTwoWorkerThreadsStoreTheSameEpisodes) {
  // follow_human: a benchmark task, whose episode the run now builds; queue: a choreography with requests.
  for (const std::string scenario : {"follow_human", "queue"}) {
    TempDir dir;
    std::map<std::uint64_t, std::string> by_jobs[2];
    for (const int jobs : {1, 2}) {
      const std::string db = (dir.path() / ("jobs" + std::to_string(jobs) + ".db")).string();
      const CommandResult result =
          run_command(kHrisim + " run " + kScenarios + "/" + scenario + ".json --seeds 1-4 --jobs " + std::to_string(jobs) + " --db " + db, false);
      ASSERT_EQ(result.exit_status, 0) << result.output;
      storage::Store store(db);
      const nlohmann::json report = nlohmann::json::parse(result.output);
      for (const auto& episode : report["episodes"]) {
        by_jobs[jobs - 1][episode["seed"].get<std::uint64_t>()] = stored_content(store, episode["episode_id"]);
      }
    }
    ASSERT_EQ(by_jobs[0].size(), 4u);
    for (const auto& [seed, content] : by_jobs[0]) EXPECT_EQ(by_jobs[1][seed], content) << scenario << " seed " << seed;
  }
}

TEST(CliRender, AStoredEpisodeReplaysToAVideo) {
  TempDir dir;
  const std::string db = (dir.path() / "hrisim.db").string();
  const CommandResult run = run_command(kHrisim + " run " + kScenarios + "/elevator.json --seeds 2 --max-time 4 --db " + db, false);
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const std::string episode = nlohmann::json::parse(run.output)["episodes"][0]["episode_id"];
  const std::string video = (dir.path() / "run.mp4").string();
  const CommandResult rendered =
      run_command(kHrisim + " render " + episode + " --db " + db + " --camera robot.head_rgbd --width 128 --fps 10 --out " + video, false);
  ASSERT_EQ(rendered.exit_status, 0) << rendered.output;
  const nlohmann::json summary = nlohmann::json::parse(rendered.output);
  // 4 s at 60 Hz, a frame every 6 ticks, the first at tick 0: 41 frames.
  EXPECT_EQ(summary["frames"], 41);
  EXPECT_EQ(summary["fps"], 10.0);
  EXPECT_EQ(summary["codec"], "h264") << "what browsers and players play";
  EXPECT_TRUE(summary["matches_stored_episode"].get<bool>()) << "the replay is the stored episode, tick for tick";
  std::ifstream file(video, std::ios::binary);
  std::string head(12, '\0');
  file.read(head.data(), 12);
  EXPECT_EQ(head.substr(4, 4), "ftyp") << "an MP4 container";
  EXPECT_GT(std::filesystem::file_size(video), 1000u);
  const std::string webm = (dir.path() / "run.webm").string();
  const CommandResult vp8 = run_command(kHrisim + " render " + episode + " --db " + db + " --width 64 --fps 5 --out " + webm, false);
  ASSERT_EQ(vp8.exit_status, 0) << vp8.output;
  EXPECT_EQ(nlohmann::json::parse(vp8.output)["codec"], "vp8");
  std::ifstream webm_file(webm, std::ios::binary);
  std::string magic(4, '\0');
  webm_file.read(magic.data(), 4);
  EXPECT_EQ(magic, "\x1a\x45\xdf\xa3") << "a Matroska (WebM) container";

  EXPECT_EQ(run_command(kHrisim + " render " + episode + " --db " + db).exit_status, 2) << "no --out";
  EXPECT_EQ(run_command(kHrisim + " render " + episode + " --db " + db + " --out " + (dir.path() / "run.gif").string()).exit_status, 2);
  EXPECT_EQ(run_command(kHrisim + " render " + episode + " --db " + db + " --fps 0 --out " + video).exit_status, 2);
  EXPECT_EQ(run_command(kHrisim + " render no-such-episode --db " + db + " --out " + video).exit_status, 1);
  const CommandResult camera = run_command(kHrisim + " render " + episode + " --db " + db + " --camera ceiling --out " + video);
  EXPECT_EQ(camera.exit_status, 1);
  EXPECT_NE(camera.output.find("no camera 'ceiling' (overview, follow, robot.head_rgbd, robot.hand_camera)"), std::string::npos) << camera.output;
}

TEST(Cli, GatesDecideTheExitStatusAndJUnitListsThem) {
  TempDir dir;
  const std::string junit = (dir.path() / "report.xml").string();
  const std::string run = kHrisim + " run " + kScenarios + "/queue.json --seeds 1,2 --junit " + junit;
  const CommandResult passing = run_command(run + " --gate 'requests_sent.min >= 1' --gate 'episode_length.max > 0'", false);
  EXPECT_EQ(passing.exit_status, 0) << passing.output;
  std::ifstream passed_xml(junit);
  const std::string passed((std::istreambuf_iterator<char>(passed_xml)), std::istreambuf_iterator<char>());
  EXPECT_NE(passed.find("tests=\"2\" failures=\"0\""), std::string::npos) << passed;

  const CommandResult failing = run_command(run + " --gate 'requests_sent.min >= 1' --gate 'episode_length.max < 10'");
  EXPECT_EQ(failing.exit_status, 1) << failing.output;
  EXPECT_NE(failing.output.find("gate 'episode_length.max < 10' failed"), std::string::npos) << failing.output;
  EXPECT_EQ(failing.output.find("gate 'requests_sent.min >= 1' failed"), std::string::npos) << failing.output;
  std::ifstream failed_xml(junit);
  const std::string failed((std::istreambuf_iterator<char>(failed_xml)), std::istreambuf_iterator<char>());
  EXPECT_NE(failed.find("<testcase classname=\""), std::string::npos);
  EXPECT_NE(failed.find("name=\"episode_length.max &lt; 10\""), std::string::npos) << failed;
  EXPECT_NE(failed.find("<failure message=\"episode_length.max is"), std::string::npos) << failed;

  // Not a gate, or a scenario that does not load: exit 2, nothing run.
  EXPECT_EQ(run_command(run + " --gate 'collisions.median == 0'").exit_status, 2);
  EXPECT_EQ(run_command(kHrisim + " run /nonexistent.json --seeds 1-2").exit_status, 2);
}

TEST(Cli, ABaselineWithoutTheRobotMeasuresHowFarItMadeThePeopleWalk) {
  const std::string run = kHrisim + " run " + kScenarios + "/corridor_passing.json --seed 3";
  const nlohmann::json plain = nlohmann::json::parse(run_command(run, false).output);
  EXPECT_TRUE(plain["metrics"]["human_path_deviation"].is_null());
  const CommandResult with_baseline = run_command(run + " --baseline-without-robot", false);
  ASSERT_EQ(with_baseline.exit_status, 0) << with_baseline.output;
  const nlohmann::json summary = nlohmann::json::parse(with_baseline.output);
  ASSERT_TRUE(summary["metrics"]["human_path_deviation"].is_number()) << summary["metrics"].dump();
  EXPECT_EQ(summary["state_hash"], plain["state_hash"]) << "the baseline is a second session: the episode is the same";
}

TEST(Cli, AControllerReplacesTheScenariosOwn) {
  // The elevator's robot waits by default; with a goal controller it drives, and reaches the goal.
  const std::string controller = R"('{"type":"goal","goal":{"pose":{"x":1.0,"y":-0.8,"theta":0}}}')";
  const CommandResult result =
      run_command(kHrisim + " run " + kScenarios + "/elevator.json --seeds 1 --max-time 30 --controller " + controller, false);
  ASSERT_EQ(result.exit_status, 0) << result.output;
  const nlohmann::json report = nlohmann::json::parse(result.output);
  EXPECT_EQ(report["controller"], "goal");
  EXPECT_GT(report["aggregates"]["path_length"]["mean"].get<double>(), 0.5);
  const CommandResult bad = run_command(kHrisim + " run " + kScenarios + "/elevator.json --controller '{\"type\":\"dwa\",\"goal\":{\"radius\":1}}'");
  EXPECT_EQ(bad.exit_status, 2);
  EXPECT_NE(bad.output.find("/controller/goal: a goal is a location or a pose"), std::string::npos) << bad.output;
}

TEST(Cli, BadSeedListsExitWithTwo) {
  for (const char* seeds : {"5-3", "1-x", "a,b", "1-200001", ""}) {
    const CommandResult result = run_command(kHrisim + " run " + kScenarios + "/queue.json --seeds '" + seeds + "'");
    EXPECT_EQ(result.exit_status, 2) << seeds << ": " << result.output;
    EXPECT_NE(result.output.find("--seeds"), std::string::npos) << seeds;
  }
  EXPECT_EQ(run_command(kHrisim + " run " + kScenarios + "/queue.json --seed 1 --seeds 1-2").exit_status, 2);
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

/// The shell block after `<!-- ci-job -->` in docs/runs.md, exactly as a user would copy it.
std::string readme_ci_job() {
  std::ifstream in(std::string(HRISIM_SOURCE_DIR) + "/docs/runs.md");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto marker = text.find("<!-- ci-job -->");
  const auto begin = text.find("```bash\n", marker);
  const auto end = text.find("```\n", begin + 8);
  if (marker == std::string::npos || begin == std::string::npos || end == std::string::npos) return "";
  return text.substr(begin + 8, end - begin - 8);
}

TEST(ReadmeCiJob, PassesWithPassingGatesAndFailsOnAFailingOne) {
  const std::string job = readme_ci_job();
  ASSERT_FALSE(job.empty()) << "docs/runs.md has no <!-- ci-job --> block";
  TempDir dir;
  const std::filesystem::path script = dir.path() / "ci-job.sh";
  std::ofstream(script) << job;
  // From a folder of its own (it writes hrisim-junit.xml there), on a free port, with a scratch database.
  const std::string run = "cd " + dir.path().string() + " && HRISIM=" + HRISIM_BINARY + " HRISIM_SCENARIOS=" + HRISIM_SOURCE_DIR +
                          "/scenarios HRISIM_WEB_ROOT=" + HRISIM_SOURCE_DIR + "/web DB=" + (dir.path() / "ci.db").string() + " PORT=18" + std::to_string(100 + getpid() % 800) + " ";
  const CommandResult passing = run_command(run + "bash " + script.string());
  EXPECT_EQ(passing.exit_status, 0) << passing.output;
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "hrisim-junit.xml"));
  const CommandResult failing = run_command(run + "GATES='[\"episode_length.max < 10\"]' bash " + script.string());
  EXPECT_NE(failing.exit_status, 0) << failing.output;
  EXPECT_NE(failing.output.find("episode_length.max < 10"), std::string::npos) << failing.output;
}
TEST(Cli, TrajectoriesPrintsEachPredictorsErrorsOnARecordedFile) {
  const std::string fixture = std::string(HRISIM_SOURCE_DIR) + "/tests/fixtures/trajectories/passing.txt";
  const CommandResult json = run_command(kHrisim + " trajectories " + fixture + " --json", false);
  ASSERT_EQ(json.exit_status, 0) << json.output;
  const auto report = nlohmann::json::parse(json.output);
  EXPECT_EQ(report["windows"], 7);
  EXPECT_EQ(report["people"], 4);
  ASSERT_EQ(report["predictors"].size(), 3u);
  EXPECT_EQ(report["predictors"][0]["predictor"], "constant_velocity");
  EXPECT_LT(report["predictors"][0]["ade"].get<double>(), 1e-9);
  EXPECT_EQ(report["predictors"][1]["predictor"], "orca");
  EXPECT_GT(report["predictors"][1]["ade"].get<double>(), 0.01);
  EXPECT_EQ(report["predictors"][2]["by_frame"].size(), 12u);

  const CommandResult table = run_command(kHrisim + " trajectories " + fixture);
  EXPECT_EQ(table.exit_status, 0) << table.output;
  EXPECT_NE(table.output.find("7 windows from 4 people"), std::string::npos) << table.output;
  EXPECT_NE(table.output.find("constant velocity     0.000    0.000"), std::string::npos) << table.output;
  EXPECT_NE(table.output.find("social force"), std::string::npos) << table.output;
}

TEST(Cli, TrajectoriesNamesTheLineOfABadRow) {
  TempDir dir;
  std::ofstream(dir / "bad.txt") << "0\t1.0\t1.5\t2.0\n10\t1.0\t1.5\n";
  const CommandResult bad = run_command(kHrisim + " trajectories " + (dir / "bad.txt").string());
  EXPECT_EQ(bad.exit_status, 1);
  EXPECT_NE(bad.output.find("bad.txt:2: expected 4 fields (frame, person, x, y), found 3"), std::string::npos) << bad.output;
  std::ofstream(dir / "short.txt") << "0 1 0 0\n10 1 0.5 0\n";
  const CommandResult short_walk = run_command(kHrisim + " trajectories " + (dir / "short.txt").string());
  EXPECT_EQ(short_walk.exit_status, 1);
  EXPECT_NE(short_walk.output.find("nothing to predict"), std::string::npos) << short_walk.output;
  EXPECT_EQ(run_command(kHrisim + " trajectories").exit_status, 2);
}


}  // namespace
}  // namespace hrisim::testing
