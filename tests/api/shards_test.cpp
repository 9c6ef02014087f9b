// Runs split over machines, as a user runs them: hrisim run --shard into one database per shard, and
// hrisim merge into one; the merged run is, bit for bit, the run made on one machine. Merging twice
// changes nothing; shards of another scenario, controller or hrisim, or of an unfinished run, are
// refused with both sides named, and nothing of them is kept.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "storage/store.hpp"
#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

const std::string kQueue = kScenarios + "/queue.json";
const std::string kRun = " --max-time 2 --jobs 2 --gate 'collisions.max < 5' ";

/// Every stored episode of the run, by seed, as comparable text.
std::map<std::uint64_t, std::string> contents(storage::Store& store, const std::string& run) {
  std::map<std::uint64_t, std::string> by_seed;
  for (const storage::EpisodeRecord& episode : store.episodes_of_run(run)) by_seed[episode.seed] = stored_content(store, episode.id);
  return by_seed;
}

TEST(Shards, AThousandSeedsSplitFourWaysAndMergedAreTheRunOfOneMachine) {
  TempDir dir;
  const std::string whole_db = (dir.path() / "whole.db").string();
  const CommandResult whole = run_command(kHrisim + " run " + kQueue + " --seeds 1-1000" + kRun + "--db " + whole_db, false);
  ASSERT_EQ(whole.exit_status, 0) << whole.output.substr(0, 2000);
  const json unsplit = json::parse(whole.output);

  std::string shards;
  std::string run_id;
  for (int k = 1; k <= 4; ++k) {
    const std::string db = (dir.path() / ("shard-" + std::to_string(k) + ".db")).string();
    const std::string said = (dir.path() / "stderr.txt").string();
    const CommandResult shard =
        run_command("(" + kHrisim + " run " + kQueue + " --seeds 1-1000" + kRun + "--shard " + std::to_string(k) + "/4 --db " + db + " 2>" + said + ")", false);
    ASSERT_EQ(shard.exit_status, 0) << shard.output.substr(0, 2000);
    const json report = json::parse(shard.output);
    const std::string verdict_line = [&] {
      std::ifstream in(said);
      return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    EXPECT_EQ(report["episodes"].size(), 250u);
    EXPECT_EQ(report["episodes"][0]["seed"], k) << "seeds keep their identity: every 4th from the k-th";
    EXPECT_EQ(report["config"]["sharding"]["index"], k);
    if (run_id.empty()) run_id = report["id"];
    EXPECT_EQ(report["id"], run_id) << "every shard is the same run";
    EXPECT_NE(verdict_line.find("queue: 250 episodes (shard " + std::to_string(k) + "/4 of run " + run_id + "), verdict PASSED"), std::string::npos);
    shards += " " + db;
  }

  const std::string merged_db = (dir.path() / "results.db").string();
  const CommandResult merge = run_command(kHrisim + " merge" + shards + " --into " + merged_db, false);
  ASSERT_EQ(merge.exit_status, 0) << merge.output.substr(0, 2000);
  const json merged = json::parse(merge.output);
  EXPECT_EQ(merged["id"], run_id);
  EXPECT_EQ(merged["aggregates"], unsplit["aggregates"]) << "every aggregate, to the bit";
  EXPECT_EQ(merged["rates"], unsplit["rates"]);
  EXPECT_EQ(merged["verdict"], unsplit["verdict"]);
  EXPECT_EQ(merged["progress"], unsplit["progress"]);
  EXPECT_EQ(merged["config"]["seeds"], unsplit["config"]["seeds"]);
  ASSERT_EQ(merged["episodes"].size(), 1000u);
  for (std::size_t i = 0; i < 1000; ++i) {
    EXPECT_EQ(merged["episodes"][i]["seed"], unsplit["episodes"][i]["seed"]);
    EXPECT_EQ(merged["episodes"][i]["sim_time"], unsplit["episodes"][i]["sim_time"]);
  }
  // Every episode's metrics, events, trajectory and series are those of the machine that ran it whole.
  storage::Store one(whole_db), results(merged_db);
  const auto expected = contents(one, unsplit["id"]);
  const auto got = contents(results, run_id);
  ASSERT_EQ(got.size(), expected.size());
  for (const auto& [seed, content] : expected) EXPECT_EQ(got.at(seed), content) << "seed " << seed;

  // Merging again changes nothing.
  const storage::StoreCounts before = results.counts();
  const CommandResult again = run_command(kHrisim + " merge" + shards + " --into " + merged_db);
  ASSERT_EQ(again.exit_status, 0) << again.output.substr(0, 2000);
  EXPECT_NE(again.output.find("0 episodes added, 250 already in"), std::string::npos);
  const storage::StoreCounts after = results.counts();
  EXPECT_EQ(after.episodes, before.episodes);
  EXPECT_EQ(after.runs, before.runs);
  EXPECT_EQ(after.trajectory_samples, before.trajectory_samples);
  EXPECT_EQ(after.events, before.events);
}

TEST(Shards, AMergeOfSomeShardsSaysWhichAreMissingAndFails) {
  TempDir dir;
  const std::string shard = (dir.path() / "shard-2.db").string(), results = (dir.path() / "results.db").string();
  ASSERT_EQ(run_command(kHrisim + " run " + kQueue + " --seeds 1-9" + kRun + "--shard 2/3 --db " + shard).exit_status, 0);
  const CommandResult merge = run_command(kHrisim + " merge " + shard + " --into " + results);
  EXPECT_EQ(merge.exit_status, 1) << "an incomplete run fails its verdict";
  EXPECT_NE(merge.output.find("1 of 3 shards are merged (missing: 1, 3): 3 of 9 seeds"), std::string::npos) << merge.output;
}

TEST(Shards, ARunMadeWholeMergesAsItIsAndAgainToNothing) {
  TempDir dir;
  const std::string whole = (dir.path() / "whole.db").string(), results = (dir.path() / "results.db").string();
  const CommandResult run = run_command(kHrisim + " run " + kQueue + " --seeds 1-3" + kRun + "--db " + whole, false);
  ASSERT_EQ(run.exit_status, 0) << run.output;
  const CommandResult first = run_command(kHrisim + " merge " + whole + " --into " + results, false);
  ASSERT_EQ(first.exit_status, 0) << first.output;
  EXPECT_EQ(json::parse(first.output)["aggregates"], json::parse(run.output)["aggregates"]);
  const CommandResult again = run_command(kHrisim + " merge " + whole + " --into " + results);
  EXPECT_EQ(again.exit_status, 0) << again.output;
  EXPECT_NE(again.output.find("0 episodes added, 3 already in"), std::string::npos) << again.output;
}

TEST(Shards, AShardOfAnotherScenarioControllerOrUnfinishedRunIsRefusedAndNothingOfItKept) {
  TempDir dir;
  const std::string elevator = kScenarios + "/elevator.json";
  const std::string one = (dir.path() / "shard-1.db").string(), results = (dir.path() / "results.db").string();
  ASSERT_EQ(run_command(kHrisim + " run " + elevator + " --seeds 1-6" + kRun + "--shard 1/2 --db " + one).exit_status, 0);
  ASSERT_EQ(run_command(kHrisim + " merge " + one + " --into " + results).exit_status, 1);

  // The same scenario with a changed description: another file content under the same name.
  json edited = json::parse(std::ifstream(elevator));
  edited["description"] = "edited between the shards";
  const std::string edited_file = (dir.path() / "elevator.json").string();
  std::ofstream(edited_file) << edited.dump(2);
  const std::string other_scenario = (dir.path() / "scenario-2.db").string();
  ASSERT_EQ(run_command(kHrisim + " run " + edited_file + " --seeds 1-6" + kRun + "--shard 2/2 --db " + other_scenario).exit_status, 0);
  const std::string other_controller = (dir.path() / "controller-2.db").string();
  const std::string controller = R"({"type":"goal","goal":{"pose":{"x":1.0,"y":-0.8,"theta":0}}})";
  ASSERT_EQ(run_command(kHrisim + " run " + elevator + " --seeds 1-6" + kRun + "--shard 2/2 --controller '" + controller + "' --db " + other_controller)
                .exit_status,
            0);

  storage::Store store(results);
  const storage::StoreCounts before = store.counts();
  const CommandResult scenario = run_command(kHrisim + " merge " + other_scenario + " --into " + results);
  EXPECT_EQ(scenario.exit_status, 1);
  EXPECT_NE(scenario.output.find("cannot be merged: its scenario's content (sha256) is "), std::string::npos) << scenario.output;
  EXPECT_NE(scenario.output.find(" in " + other_scenario + " but "), std::string::npos) << scenario.output;
  EXPECT_NE(scenario.output.find(" in " + results), std::string::npos) << scenario.output;
  const CommandResult by_controller = run_command(kHrisim + " merge " + other_controller + " --into " + results);
  EXPECT_EQ(by_controller.exit_status, 1);
  EXPECT_NE(by_controller.output.find("its controller is " + json::parse(controller).dump() + " in " + other_controller + " but none in " + results),
            std::string::npos)
      << by_controller.output;
  EXPECT_EQ(store.counts().episodes, before.episodes) << "nothing of a refused shard is kept";

  // A shard whose process died: its run is not finished.
  {
    storage::Store shard(one);
    shard.set_run_status(shard.all_runs().front().id, "interrupted");
  }
  const CommandResult unfinished = run_command(kHrisim + " merge " + one + " --into " + (dir.path() / "fresh.db").string());
  EXPECT_EQ(unfinished.exit_status, 1);
  EXPECT_NE(unfinished.output.find("it is interrupted, not finished: run that part again"), std::string::npos) << unfinished.output;
}

TEST(Shards, TheServerImportsAMergedDatabaseAtStartAndShowsItsRuns) {
  TempDir dir;
  std::string shards;
  for (int k = 1; k <= 2; ++k) {
    const std::string db = (dir.path() / ("shard-" + std::to_string(k) + ".db")).string();
    ASSERT_EQ(run_command(kHrisim + " run " + kQueue + " --seeds 1-6" + kRun + "--name imported --shard " + std::to_string(k) + "/2 --db " + db).exit_status, 0);
    shards += " " + db;
  }
  const std::string results = (dir.path() / "results.db").string();
  const CommandResult merge = run_command(kHrisim + " merge" + shards + " --into " + results, false);
  ASSERT_EQ(merge.exit_status, 0) << merge.output;
  const json merged = json::parse(merge.output);

  TestServer server({"--import", results});
  const HttpReply reply = http(server.port(), "GET", "/api/v1/runs/" + merged["id"].get<std::string>());
  ASSERT_EQ(reply.status, 200) << reply.body;
  const json report = json::parse(reply.body);
  EXPECT_EQ(report["name"], "imported");
  EXPECT_EQ(report["aggregates"], merged["aggregates"]);
  EXPECT_EQ(report["verdict"], merged["verdict"]);
  // Its episodes replay from the scenario record that came with them.
  const std::string episode = report["episodes"][0]["episode_id"];
  EXPECT_EQ(http(server.port(), "GET", "/api/v1/episodes/" + episode + "/cameras").status, 200);
  EXPECT_NE(server.output().find("imported run " + merged["id"].get<std::string>() + " from " + results + ": 6 episodes added"), std::string::npos)
      << server.output();

  const CommandResult missing = run_command(kHrisim + " serve --port 0 --web " + std::string(HRISIM_SOURCE_DIR) + "/web --db " + (dir.path() / "s.db").string() +
                                            " --import " + (dir.path() / "none.db").string());
  EXPECT_EQ(missing.exit_status, 2);
  EXPECT_NE(missing.output.find("--import: no database"), std::string::npos) << missing.output;
}

/// Runs of a printed {"runs": [...]}, by name.
std::map<std::string, json> runs_by_name(const std::string& output) {
  const json printed = json::parse(output);
  std::map<std::string, json> runs;
  for (const json& run : printed["runs"]) runs[run["name"]] = run;
  return runs;
}

TEST(Sweeps, ASweepsShardsMergeIntoItsRunsOnOneMachine) {
  TempDir dir;
  const std::string sweep = (dir.path() / "sweep.json").string();
  std::ofstream(sweep) << R"({"name": "nightly", "scenarios": ["elevator", ")" + kScenarios + R"(/crossing_navigation.json"],
                             "controllers": [null, {"type": "goal", "goal": {"pose": {"x": 1.0, "y": -0.8, "theta": 0}}}],
                             "seeds": "1-6", "gates": ["collisions.max < 5"], "max_time": 2})";
  const CommandResult whole = run_command(kHrisim + " sweep " + sweep + " --db " + (dir.path() / "whole.db").string(), false);
  ASSERT_EQ(whole.exit_status, 0) << whole.output.substr(0, 2000);
  const auto one_machine = runs_by_name(whole.output);
  ASSERT_EQ(one_machine.size(), 4u);
  EXPECT_TRUE(one_machine.contains("nightly · elevator · own controller"));
  EXPECT_TRUE(one_machine.contains("nightly · crossing_navigation · goal"));
  std::string shards;
  for (int k = 1; k <= 3; ++k) {
    const std::string db = (dir.path() / ("shard-" + std::to_string(k) + ".db")).string();
    ASSERT_EQ(run_command(kHrisim + " sweep " + sweep + " --shard " + std::to_string(k) + "/3 --db " + db).exit_status, 0);
    shards += " " + db;
  }
  const CommandResult merge = run_command(kHrisim + " merge" + shards + " --into " + (dir.path() / "results.db").string(), false);
  ASSERT_EQ(merge.exit_status, 0) << merge.output.substr(0, 2000);
  const auto merged = runs_by_name(merge.output);
  ASSERT_EQ(merged.size(), 4u);
  for (const auto& [name, run] : one_machine) {
    EXPECT_EQ(merged.at(name)["aggregates"], run["aggregates"]) << name;
    EXPECT_EQ(merged.at(name)["episodes"].size(), 6u) << name;
    EXPECT_EQ(merged.at(name)["config"]["controller"], run["config"]["controller"]) << name;
  }
}

TEST(Sweeps, ABadSweepFileNamesEachProblemAtItsPointer) {
  TempDir dir;
  const std::string sweep = (dir.path() / "sweep.json").string();
  std::ofstream(sweep) << R"({"scenarios": ["elevator", "no/such.json"], "controllers": [3], "seeds": "9-1", "gates": "x", "colour": 1})";
  const CommandResult bad = run_command(kHrisim + " sweep " + sweep);
  EXPECT_EQ(bad.exit_status, 2);
  for (const std::string line : {": /colour: unknown field", ": /name: the sweep's name is required", ": /scenarios/1: no scenario file",
                                 ": /controllers/0: a controller object, or null", ": /seeds: --seeds: A-B needs A <= B", ": /gates: a list of gates"}) {
    EXPECT_NE(bad.output.find(sweep + line), std::string::npos) << line << " in\n" << bad.output;
  }
  EXPECT_NE(bad.output.find("6 problems in the sweep"), std::string::npos) << bad.output;
  std::ofstream(sweep) << "{not json";
  EXPECT_EQ(run_command(kHrisim + " sweep " + sweep).exit_status, 2);
}

TEST(Shards, BadShardArgumentsExitWithTwo) {
  TempDir dir;
  const std::string db = " --db " + (dir.path() / "s.db").string();
  const CommandResult no_db = run_command(kHrisim + " run " + kQueue + " --seeds 1-4 --shard 1/2");
  EXPECT_EQ(no_db.exit_status, 2);
  EXPECT_NE(no_db.output.find("--shard: give --db FILE"), std::string::npos) << no_db.output;
  EXPECT_EQ(run_command(kHrisim + " run " + kQueue + " --seeds 1-4 --shard 3/2" + db).exit_status, 2);
  const CommandResult no_scheduler = run_command("env -u SLURM_ARRAY_TASK_ID " + kHrisim + " run " + kQueue + " --seeds 1-4 --shard auto" + db);
  EXPECT_EQ(no_scheduler.exit_status, 2);
  EXPECT_NE(no_scheduler.output.find("auto found no scheduler's index"), std::string::npos) << no_scheduler.output;
  const CommandResult slurm = run_command("SLURM_ARRAY_TASK_ID=7 SLURM_ARRAY_TASK_MIN=6 SLURM_ARRAY_TASK_COUNT=3 " + kHrisim + " run " + kQueue +
                                          " --seeds 1-9 --max-time 1 --shard auto" + db);
  EXPECT_EQ(slurm.exit_status, 0) << slurm.output.substr(0, 2000);
  EXPECT_NE(slurm.output.find("(shard 2/3 of run"), std::string::npos) << "task 7 of an array from 6";
  EXPECT_EQ(run_command(kHrisim + " merge --into " + (dir.path() / "r.db").string()).exit_status, 2) << "no database to merge";
  EXPECT_EQ(run_command(kHrisim + " merge " + (dir.path() / "none.db").string() + " --into " + (dir.path() / "r.db").string()).exit_status, 2);
  EXPECT_EQ(run_command(kHrisim + " merge " + (dir.path() / "s.db").string()).exit_status, 2) << "no --into";
}

}  // namespace
}  // namespace hrisim::testing
