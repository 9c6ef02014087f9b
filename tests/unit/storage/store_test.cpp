#include "storage/store.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <limits>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "storage/sqlite.hpp"
#include "support/episodes.hpp"
#include "support/temp_dir.hpp"

namespace hrisim::storage {
namespace {

using testing::make_episode;
using testing::make_scenario;
using testing::TempDir;

TEST(Store, NewFileIsMigratedAndSound) {
  TempDir dir;
  Store store(dir / "nested/folder/hrisim.db");
  EXPECT_EQ(store.schema_version(), schema_migrations().back().version);
  EXPECT_EQ(store.integrity_check(), "ok");
  Database raw(dir / "nested/folder/hrisim.db");
  EXPECT_EQ(raw.scalar_text("PRAGMA journal_mode"), "wal");
  EXPECT_EQ(raw.scalar_integer("PRAGMA foreign_keys"), 1);
  EXPECT_EQ(raw.scalar_integer("PRAGMA synchronous"), 1);  // NORMAL
}

TEST(Store, SeriesRoundTripBitForBitWithGaps) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("s"));
  EpisodeRecord episode = make_episode("s", 2);
  episode.series = {{"robot_speed", 0, 6, {0.0, 0.1, 1.0 / 3.0, std::nullopt, -2.5}}, {"time_to_collision", 6, 6, {std::nullopt}}};
  store.write_episode(episode);
  const auto all = store.series(episode.id);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].name, "robot_speed");
  EXPECT_EQ(all[0].stride, 6);
  EXPECT_EQ(all[0].values, episode.series[0].values);
  EXPECT_EQ(all[1].first_tick, 6);
  EXPECT_FALSE(all[1].values[0]);
  EXPECT_EQ(store.series(episode.id, "time_to_collision").size(), 1u);
  EXPECT_TRUE(store.series(episode.id, "nothing").empty());

  EpisodeRecord infinite = make_episode("s", 3);
  infinite.series = {{"robot_speed", 0, 1, {std::numeric_limits<double>::infinity()}}};
  EXPECT_THROW(store.write_episode(infinite), core::Error);
  EXPECT_FALSE(store.episode(infinite.id)) << "nothing of a refused episode is stored";
}

TEST(Store, ScenarioRoundTripWithHash) {
  TempDir dir;
  Store store(dir / "db");
  const ScenarioRecord stored = store.put_scenario(make_scenario("elevator"));
  EXPECT_EQ(stored.sha256.size(), 64u);
  EXPECT_FALSE(stored.created_at.empty());
  EXPECT_EQ(stored.created_at.back(), 'Z');
  const auto loaded = store.scenario("elevator");
  ASSERT_TRUE(loaded);
  EXPECT_EQ(loaded->source, make_scenario("elevator").source);
  EXPECT_EQ(loaded->sha256, stored.sha256);
  EXPECT_EQ(loaded->created_at, stored.created_at);
  EXPECT_FALSE(store.scenario("missing"));
}

// Two runs of the same bundled scenario started at once both store its snapshot "if missing": one
// stores it, the other finds it, neither fails on the id (it did, with a UNIQUE constraint, when each
// looked before the other stored).
TEST(Store, AScenarioStoredIfMissingFromManyThreadsAtOnceIsStoredOnce) {
  TempDir dir;
  Store store(dir / "db");
  std::vector<std::thread> threads;
  for (int k = 0; k < 8; ++k) {
    threads.emplace_back([&store] { store.put_scenario_if_missing(make_scenario("snapshot")); });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(store.counts().scenarios, 1);
  ScenarioRecord changed = make_scenario("snapshot");
  changed.source = "{}";
  store.put_scenario_if_missing(changed);
  EXPECT_EQ(store.scenario("snapshot")->source, make_scenario("snapshot").source) << "the one stored stays";
}

TEST(Store, FilesUploadedWithAScenarioAreKeptByteForByteAndNamedByItsHash) {
  TempDir dir;
  Store store(dir / "db");
  ScenarioRecord with_files = make_scenario("mapped");
  with_files.files = {{"maps/lab.yaml", "image: lab.pgm\n"}, {"maps/lab.pgm", std::string("P5\n2 1\n255\n\x00\xfe", 13)}};
  const ScenarioRecord stored = store.put_scenario(with_files);
  EXPECT_NE(stored.sha256, store.put_scenario(make_scenario("alone")).sha256) << "the files are part of what the hash names";
  EXPECT_EQ(stored.sha256, scenario_sha256(with_files.source, with_files.files));
  with_files.files["maps/lab.pgm"].back() = '\xfd';
  EXPECT_NE(stored.sha256, scenario_sha256(with_files.source, with_files.files)) << "one byte of a file changes it";
  const auto loaded = store.scenario("mapped");
  ASSERT_TRUE(loaded);
  ASSERT_EQ(loaded->files.size(), 2u);
  EXPECT_EQ(loaded->files.at("maps/lab.pgm"), std::string("P5\n2 1\n255\n\x00\xfe", 13)) << "bytes, NUL included";
  EXPECT_TRUE(store.scenario("mapped", false)->files.empty()) << "read only with the source";
  EXPECT_EQ(scenario_sha256("x", {}), store.put_scenario({"plain", "p", "json", "x", "", "", "", "", {}}).sha256) << "without files: of the source alone";
}

TEST(Store, DuplicateScenarioIsAConflict) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("a"));
  try {
    store.put_scenario(make_scenario("a"));
    FAIL() << "expected a conflict";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::conflict);
  }
}

TEST(Store, ScenarioPaging) {
  TempDir dir;
  Store store(dir / "db");
  for (const char* id : {"d", "a", "c", "b", "e"}) store.put_scenario(make_scenario(id));
  const auto first = store.scenarios(2);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].id, "a");
  EXPECT_EQ(first[1].id, "b");
  const auto rest = store.scenarios(10, first.back().id);
  ASSERT_EQ(rest.size(), 3u);
  EXPECT_EQ(rest[0].id, "c");
  EXPECT_EQ(rest[2].id, "e");
}

TEST(Store, EpisodeRoundTripKeepsEverything) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("s"));
  EpisodeRecord episode = make_episode("s", 7);
  episode.seed = std::numeric_limits<std::uint64_t>::max();  // beyond SQLite's signed range
  store.write_episode(episode);

  const auto loaded = store.episode(episode.id);
  ASSERT_TRUE(loaded);
  EXPECT_EQ(loaded->seed, episode.seed);
  EXPECT_FALSE(loaded->run_id);
  EXPECT_EQ(loaded->termination_reason, "goal_reached");
  EXPECT_EQ(loaded->ticks, episode.ticks);
  EXPECT_DOUBLE_EQ(loaded->sim_time, episode.sim_time);
  ASSERT_EQ(loaded->metrics.size(), episode.metrics.size());
  for (std::size_t i = 0; i < episode.metrics.size(); ++i) {
    EXPECT_EQ(loaded->metrics[i].key, episode.metrics[i].key);
    EXPECT_EQ(loaded->metrics[i].value, episode.metrics[i].value);
    EXPECT_EQ(loaded->metrics[i].null_reason, episode.metrics[i].null_reason);
  }
  ASSERT_EQ(loaded->events.size(), episode.events.size());
  EXPECT_EQ(loaded->events[2].subject, "human_2");
  EXPECT_EQ(loaded->events[2].data["part"], "leg");
  ASSERT_EQ(loaded->trajectory.size(), episode.trajectory.size());
  for (std::size_t i = 0; i < episode.trajectory.size(); ++i) {
    EXPECT_EQ(loaded->trajectory[i].agent_id, episode.trajectory[i].agent_id);
    EXPECT_EQ(loaded->trajectory[i].tick, episode.trajectory[i].tick);
    EXPECT_EQ(loaded->trajectory[i].x, episode.trajectory[i].x);  // bit-exact doubles
    EXPECT_EQ(loaded->trajectory[i].theta, episode.trajectory[i].theta);
  }
}

TEST(Store, DataSurvivesReopen) {
  TempDir dir;
  {
    Store store(dir / "db");
    store.put_scenario(make_scenario("s"));
    store.put_run({"run-1", "s", "teleop", {{"seeds", {1, 2}}}, "running", "", std::nullopt, "", "first try", {"baseline"}, "notes"});
    EpisodeRecord episode = make_episode("s", 1);
    episode.run_id = "run-1";
    store.write_episode(episode);
    store.set_run_status("run-1", "finished");
  }
  Store store(dir / "db");
  EXPECT_EQ(store.integrity_check(), "ok");
  const auto run = store.run("run-1");
  ASSERT_TRUE(run);
  EXPECT_EQ(run->status, "finished");
  EXPECT_TRUE(run->finished_at);
  EXPECT_EQ(run->config["seeds"][1], 2);
  EXPECT_EQ(run->name, "first try");
  EXPECT_EQ(run->tags, std::vector<std::string>{"baseline"});
  EXPECT_EQ(run->notes, "notes");
  EXPECT_EQ(store.episode_ids_of_run("run-1"), std::vector<std::string>{"episode-1"});
  ASSERT_TRUE(store.episode("episode-1"));
}

TEST(Store, ARunsEpisodesComeInTheOrderOfTheirSeedsWhateverOrderTheyWereWritten) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("s"));
  store.put_run({"run-1", "s", "teleop", {{"seeds", {3, 1, 2}}}, "running", "", std::nullopt, "", "", {}, ""});
  for (const int index : {3, 1, 2}) {
    EpisodeRecord episode = make_episode("s", index);
    episode.run_id = "run-1";
    store.write_episode(episode);
  }
  std::vector<std::uint64_t> seeds;
  for (const EpisodeRecord& episode : store.episodes_of_run("run-1")) seeds.push_back(episode.seed);
  EXPECT_EQ(seeds, (std::vector<std::uint64_t>{1001, 1002, 1003})) << "aggregates over them must not depend on which thread ended first";
}

TEST(Store, ABatchKeepsNothingUnlessCommittedAndUpdatesARunItHas) {
  TempDir dir;
  Store store(dir / "db");
  ScenarioRecord scenario = make_scenario("s");
  scenario.created_at = "2026-01-02T03:04:05.000Z";
  RunRecord run{"run-1", "s", "teleop", {{"seeds", {1001}}}, "finished", "2026-01-02T03:04:06.000Z", "2026-01-02T03:05:00.000Z", "ana", "", {}, ""};
  EpisodeRecord episode = make_episode("s", 1);
  episode.run_id = "run-1";
  {
    Store::Batch batch(store);
    batch.put_scenario_if_missing(scenario);
    batch.put_run(run);
    batch.write_episode(episode);
  }  // not committed
  EXPECT_FALSE(store.scenario("s"));
  EXPECT_FALSE(store.run("run-1"));
  EXPECT_EQ(store.counts().episodes, 0);
  {
    Store::Batch batch(store);
    batch.put_scenario_if_missing(scenario);
    batch.put_run(run);
    batch.write_episode(episode);
    batch.commit();
  }
  const auto stored = store.run("run-1");
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->created_at, run.created_at) << "kept as the other database had it";
  EXPECT_EQ(stored->finished_at, run.finished_at);
  EXPECT_EQ(stored->owner, "ana");
  EXPECT_EQ(store.scenario("s")->created_at, scenario.created_at);
  store.set_run_summary("run-1", {{"collisions", {{"mean", 0.0}}}});

  run.config["seeds"] = {1001, 1002};
  run.finished_at = "2026-01-02T04:00:00.000Z";
  EpisodeRecord second = make_episode("s", 2);
  second.run_id = "run-1";
  {
    Store::Batch batch(store);
    batch.put_scenario_if_missing(scenario);  // there already: left as it is
    batch.put_run(run);
    batch.write_episode(second);
    batch.commit();
  }
  EXPECT_EQ(store.run("run-1")->config["seeds"].size(), 2u);
  EXPECT_EQ(store.run("run-1")->finished_at, run.finished_at);
  EXPECT_EQ(store.episodes_of_run("run-1").size(), 2u);
  EXPECT_EQ(store.ended_runs_without_summary().size(), 1u) << "a changed run's summary is computed again";
  EXPECT_EQ(store.all_runs().size(), 1u);
}

TEST(Store, RunsAreFoundByTextAndTagAndSortedAndFilteredByTheirSummaries) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("s"));
  const auto put = [&](const std::string& id, const std::string& name, std::vector<std::string> tags, std::optional<double> success) {
    store.put_run({id, "s", "social", {{"scenario", "elevator"}}, "finished", "", std::nullopt, "", name, std::move(tags), ""});
    if (success) store.set_run_summary(id, {{"success", {{"mean", *success}, {"max", 1.0}}}});
  };
  put("r1", "Baseline DWA", {"dwa", "v1"}, 0.5);
  put("r2", "tuned", {"dwa"}, 0.9);
  put("r3", "other", {"orca"}, 0.7);
  put("r4", "no summary yet", {}, std::nullopt);
  const auto ids = [](const std::vector<RunRecord>& runs) {
    std::vector<std::string> list;
    for (const RunRecord& run : runs) list.push_back(run.id);
    return list;
  };
  RunQuery query;
  EXPECT_EQ(ids(store.runs(query)), (std::vector<std::string>{"r4", "r3", "r2", "r1"})) << "newest first";
  query.text = "baseline";
  EXPECT_EQ(ids(store.runs(query)), std::vector<std::string>{"r1"}) << "any case, in the name";
  query.text = "ELEVATOR";
  EXPECT_EQ(store.runs(query).size(), 4u) << "in the scenario";
  query.text = "";
  query.tag = "dwa";
  EXPECT_EQ(ids(store.runs(query)), (std::vector<std::string>{"r2", "r1"}));
  query.tag = "dw";
  EXPECT_TRUE(store.runs(query).empty()) << "a tag exactly";
  query.tag = "";
  query.sort = {"success", "mean"};
  EXPECT_EQ(ids(store.runs(query)), (std::vector<std::string>{"r2", "r3", "r1", "r4"})) << "highest first, without a value last";
  query.descending = false;
  EXPECT_EQ(ids(store.runs(query)), (std::vector<std::string>{"r1", "r3", "r2", "r4"}));
  query.limit = 2;
  query.offset = 2;
  EXPECT_EQ(ids(store.runs(query)), (std::vector<std::string>{"r2", "r4"})) << "the second page";
  query = RunQuery{};
  query.filters = {{"success", "mean", ">=", 0.7}};
  EXPECT_EQ(ids(store.runs(query)), (std::vector<std::string>{"r3", "r2"}));
  query.filters.push_back({"success", "mean", "<", 0.8});
  EXPECT_EQ(ids(store.runs(query)), std::vector<std::string>{"r3"}) << "every filter holds";
  EXPECT_EQ(ids(store.ended_runs_without_summary()), std::vector<std::string>{"r4"});
  store.set_run_labels("r4", "named", {"a", "b"}, "a note");
  EXPECT_EQ(store.run("r4")->tags, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(store.run("r4")->notes, "a note");
}

TEST(Store, FailedEpisodeWriteStoresNothing) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("s"));
  EpisodeRecord episode = make_episode("s", 1);
  episode.trajectory.push_back(episode.trajectory.front());  // duplicate key, fails last
  EXPECT_THROW(store.write_episode(episode), core::Error);
  const StoreCounts counts = store.counts();
  EXPECT_EQ(counts.episodes, 0);
  EXPECT_EQ(counts.metric_values, 0);
  EXPECT_EQ(counts.events, 0);
  EXPECT_EQ(counts.trajectory_samples, 0);
}

TEST(Store, EpisodeOfUnknownScenarioIsRefused) {
  TempDir dir;
  Store store(dir / "db");
  try {
    store.write_episode(make_episode("nope", 1));
    FAIL() << "expected a foreign key conflict";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::conflict);
  }
  EXPECT_EQ(store.counts().episodes, 0);
}

TEST(Store, NonFiniteMetricIsRefusedWithItsName) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("s"));
  EpisodeRecord episode = make_episode("s", 1);
  episode.metrics[0].value = std::numeric_limits<double>::quiet_NaN();
  try {
    store.write_episode(episode);
    FAIL() << "expected bad_request";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::bad_request);
    EXPECT_NE(std::string(e.what()).find("metric_0"), std::string::npos);
  }
  EXPECT_EQ(store.counts().episodes, 0);
}

TEST(Store, UnknownRunStatusUpdateIsNotFound) {
  TempDir dir;
  Store store(dir / "db");
  try {
    store.set_run_status("ghost", "finished");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::not_found);
  }
}

TEST(Store, InvalidRunStatusIsRefusedByTheSchema) {
  TempDir dir;
  Store store(dir / "db");
  store.put_scenario(make_scenario("s"));
  EXPECT_THROW(store.put_run({"r", "s", "teleop", {}, "exploded", "", std::nullopt, "", "", {}, ""}), core::Error);
}

// Migration from an older schema: a file made by the first migrations keeps its data when a newer
// binary (here: the shipped list plus one more migration) opens it.
TEST(Migrations, OlderFileIsUpgradedKeepingData) {
  TempDir dir;
  const std::vector<Migration> shipped(schema_migrations().begin(), schema_migrations().end());
  {
    Store store(dir / "db", shipped);
    store.put_scenario(make_scenario("s"));
    store.write_episode(make_episode("s", 1));
  }
  std::vector<Migration> newer = shipped;
  newer.push_back({shipped.back().version + 1, "tags.sql",
                   "CREATE TABLE episode_tags (episode_id TEXT NOT NULL REFERENCES episodes (id), tag TEXT NOT NULL);"
                   "INSERT INTO episode_tags SELECT id, 'legacy' FROM episodes;"});
  Store store(dir / "db", newer);
  EXPECT_EQ(store.schema_version(), newer.back().version);
  EXPECT_EQ(store.integrity_check(), "ok");
  ASSERT_TRUE(store.episode("episode-1"));
  Database raw(dir / "db");
  EXPECT_EQ(raw.scalar_text("SELECT tag FROM episode_tags WHERE episode_id = 'episode-1'"), "legacy");
}

// 0007 rebuilds the scenarios table for HuNavSim uploads: what a file of schema 6 holds (a scenario
// with its summary, owner and files, a run and its episode) is all there afterwards.
TEST(Migrations, HunavScenariosComeWithoutLosingWhatWasStored) {
  TempDir dir;
  const std::vector<Migration> shipped(schema_migrations().begin(), schema_migrations().end());
  ASSERT_GE(shipped.size(), 7u);
  ASSERT_EQ(std::string(shipped[6].name), "0007_hunav_scenarios.sql");
  {
    Store store(dir / "db", std::vector<Migration>(shipped.begin(), shipped.begin() + 6));
    storage::ScenarioRecord scenario = make_scenario("s");
    scenario.summary = R"({"humans": 0})";
    scenario.owner = "alice";
    scenario.files = {{"maps/a.yaml", "image: a.pgm"}};
    store.put_scenario(scenario);
    store.write_episode(make_episode("s", 1));
    storage::ScenarioRecord hunav = make_scenario("h");
    hunav.format = "hunav_yaml";
    EXPECT_THROW(store.put_scenario(hunav), core::Error) << "schema 6 knows no HuNavSim format";
  }
  Store store(dir / "db", shipped);
  EXPECT_EQ(store.integrity_check(), "ok");
  const auto kept = store.scenario("s");
  ASSERT_TRUE(kept);
  EXPECT_EQ(kept->summary, R"({"humans": 0})");
  EXPECT_EQ(kept->owner, "alice");
  EXPECT_EQ(kept->files.at("maps/a.yaml"), "image: a.pgm");
  EXPECT_TRUE(store.episode("episode-1"));
  storage::ScenarioRecord hunav = make_scenario("h");
  hunav.format = "hunav_yaml";
  EXPECT_EQ(store.put_scenario(hunav).format, "hunav_yaml");
}

TEST(Migrations, EmptyFileFromAnotherToolIsMigrated) {
  TempDir dir;
  { Database raw(dir / "db"); }
  Store store(dir / "db");
  EXPECT_EQ(store.schema_version(), schema_migrations().back().version);
}

TEST(Migrations, FailingMigrationLeavesVersionAndSchemaUnchanged) {
  TempDir dir;
  const std::vector<Migration> shipped(schema_migrations().begin(), schema_migrations().end());
  { Store store(dir / "db", shipped); }
  std::vector<Migration> broken = shipped;
  broken.push_back({shipped.back().version + 1, "broken.sql", "CREATE TABLE half (x INTEGER); SELECT * FROM nowhere;"});
  try {
    Store store(dir / "db", broken);
    FAIL() << "expected the migration to fail";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.sql"), std::string::npos);
  }
  Database raw(dir / "db");
  EXPECT_EQ(raw.scalar_integer("PRAGMA user_version"), shipped.back().version);
  EXPECT_EQ(raw.scalar_integer("SELECT count(*) FROM sqlite_schema WHERE name = 'half'"), 0);
}

TEST(Migrations, NewerFileIsRefusedUntouched) {
  TempDir dir;
  {
    Database raw(dir / "db");
    raw.exec("PRAGMA user_version = 999");
  }
  try {
    Store store(dir / "db");
    FAIL() << "expected a refusal";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("999"), std::string::npos);
  }
  Database raw(dir / "db");
  EXPECT_EQ(raw.scalar_integer("PRAGMA user_version"), 999);
  EXPECT_EQ(raw.scalar_integer("SELECT count(*) FROM sqlite_schema"), 0);
}

TEST(Migrations, AFileMigratedByAnotherProcessMeanwhileIsNotMigratedTwice) {
  // Two processes opening one new file (a CLI run and a server, say): the second reads version 0,
  // waits for the first one's write lock, and must then find the schema there.
  TempDir dir;
  Database first(dir / "db");
  first.exec("BEGIN IMMEDIATE");
  std::string second_failed;
  std::thread second([&] {
    try {
      Store store(dir / "db");
    } catch (const core::Error& e) {
      second_failed = e.what();
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the second reads version 0 and waits
  for (const Migration& migration : schema_migrations()) first.exec(migration.sql);
  first.exec("PRAGMA user_version = " + std::to_string(schema_migrations().back().version));
  first.exec("COMMIT");
  second.join();
  EXPECT_EQ(second_failed, "");
  EXPECT_EQ(first.scalar_integer("PRAGMA user_version"), schema_migrations().back().version);
}

TEST(Migrations, ShippedListIsNumberedFromOne) {
  const auto migrations = schema_migrations();
  ASSERT_FALSE(migrations.empty());
  for (std::size_t i = 0; i < migrations.size(); ++i) EXPECT_EQ(migrations[i].version, static_cast<int>(i + 1));
}

TEST(Store, UnopenablePathIsAStorageError) {
  TempDir dir;
  std::filesystem::create_directories(dir / "a-folder");
  try {
    Store store(dir / "a-folder");
    FAIL();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::storage);
  }
}

TEST(Store, ASecretIsMadeOnceKeptWithItsDatabaseAndOfItsOwn) {
  TempDir dir;
  std::string first;
  {
    Store store(dir / "a.db");
    first = store.secret("import_ids");
    EXPECT_EQ(first.size(), 32u);
    EXPECT_EQ(first.find_first_not_of("0123456789abcdef"), std::string::npos);
    EXPECT_EQ(store.secret("import_ids"), first);
    EXPECT_NE(store.secret("another"), first);
  }
  EXPECT_EQ(Store(dir / "a.db").secret("import_ids"), first) << "kept with the file";
  EXPECT_NE(Store(dir / "b.db").secret("import_ids"), first) << "each database has its own";
}

}  // namespace
}  // namespace hrisim::storage
