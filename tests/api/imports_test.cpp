// Imports of results databases from elsewhere (issue 40's audit): every reproduction refused cleanly —
// a 400 or 409 naming what is wrong, nothing stored, nothing written outside the data folder, no other
// owner affected, the server responsive throughout. Each test is named after its finding.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

const std::string kAlice = "alice-import-0123456789", kBob = "bob-import-0123456789ab";
std::string bearer(const std::string& secret) { return "Authorization: Bearer " + secret + "\r\n"; }

std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void exec(sqlite3* db, const std::string& sql) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message ? message : "?";
    sqlite3_free(message);
    throw std::runtime_error(sql.substr(0, 80) + ": " + text);
  }
}

class Imports : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    base_ = dir_->path() / "base.db";
    const CommandResult run = run_command(kHrisim + " run " + kScenarios + "/queue.json --seeds 1-2 --max-time 3 --db " + base_.string());
    ASSERT_EQ(run.exit_status, 0) << run.output;
    server_ = new TestServer({"--token", "alice:" + kAlice, "--token", "bob:" + kBob});
  }
  static void TearDownTestSuite() {
    delete server_;
    delete dir_;
  }

  /// The bytes of the base results file changed by `sql` (run with CHECK constraints and foreign keys
  /// off, as the sqlite3 command line lets anyone do), as one file.
  static std::string variant(const std::string& sql) {
    static int count = 0;
    const std::filesystem::path file = dir_->path() / ("variant-" + std::to_string(++count) + ".db");
    sqlite3* db = nullptr;
    sqlite3_open(base_.c_str(), &db);
    exec(db, "VACUUM INTO '" + file.string() + "'");
    sqlite3_close(db);
    sqlite3_open(file.c_str(), &db);
    exec(db, "PRAGMA ignore_check_constraints=ON; PRAGMA foreign_keys=OFF; PRAGMA journal_mode=DELETE;");
    if (!sql.empty()) exec(db, sql);
    sqlite3_close(db);
    return read_bytes(file);
  }

  static HttpReply import(const std::string& bytes, const std::string& secret = kAlice) {
    return http(server_->port(), "POST", "/api/v1/runs/import", bytes, "Content-Type: application/vnd.sqlite3\r\n" + bearer(secret));
  }

  static int runs_of(const std::string& secret) {
    const HttpReply reply = http(server_->port(), "GET", "/api/v1/runs?limit=100", "", bearer(secret));
    EXPECT_EQ(reply.status, 200) << reply.body;
    return reply.status == 200 ? static_cast<int>(json::parse(reply.body)["items"].size()) : -1;
  }

  /// The request is refused with `status`, its message holding `words`, nothing stored, the server alive.
  static void expect_refused(const HttpReply& reply, int status, const std::string& words) {
    EXPECT_EQ(reply.status, status) << reply.body;
    EXPECT_NE(reply.body.find(words), std::string::npos) << reply.body;
    EXPECT_EQ(http(server_->port(), "GET", "/healthz").status, 200);
  }

  static std::string scenario_id() {
    sqlite3* db = nullptr;
    sqlite3_open(base_.c_str(), &db);
    sqlite3_stmt* select = nullptr;
    sqlite3_prepare_v2(db, "SELECT id FROM scenarios", -1, &select, nullptr);
    sqlite3_step(select);
    std::string id = reinterpret_cast<const char*>(sqlite3_column_text(select, 0));
    sqlite3_finalize(select);
    sqlite3_close(db);
    return id;
  }

  static TempDir* dir_;
  static std::filesystem::path base_;
  static TestServer* server_;
};
TempDir* Imports::dir_ = nullptr;
std::filesystem::path Imports::base_;
TestServer* Imports::server_ = nullptr;

TEST_F(Imports, AnImportWritesNoFileWhereItsPathsSay) {
  const std::filesystem::path target = dir_->path() / "WRITTEN_BY_IMPORT.txt";
  const int before = runs_of(kAlice);
  for (const std::string& path : {target.string(), std::string("../../WRITTEN_BY_IMPORT.txt"), std::string("maps/../../x.txt")}) {
    expect_refused(import(variant("INSERT INTO scenario_files VALUES ('" + scenario_id() + "', '" + path + "', CAST('hello' AS BLOB))")), 400,
                   "has a file whose path is wrong");
  }
  // A scenario id that is a path: the folder its files would go to.
  for (const std::string& id : {std::string("../../x"), std::string("/etc")}) {
    expect_refused(import(variant("UPDATE scenarios SET id = '" + id + "'; UPDATE runs SET scenario_id = '" + id + "'; UPDATE episodes SET scenario_id = '" + id +
                                  "'; INSERT INTO scenario_files VALUES ('" + id + "', 'f.txt', CAST('hello' AS BLOB))")),
                   400, "names a scenario by an id hrisim does not make");
  }
  EXPECT_FALSE(std::filesystem::exists(target));
  EXPECT_EQ(runs_of(kAlice), before) << "nothing stored";
}

TEST_F(Imports, JsonNestedSixtyThousandDeepIsRefusedNotACrash) {
  const std::string deep = std::string(60000, '[') + std::string(60000, ']');
  expect_refused(import(variant("UPDATE runs SET config = '" + deep + "'")), 400, "nested deeper than 64 levels");
  expect_refused(import(variant("UPDATE events SET data = '" + deep + "'")), 400, "nested deeper than 64 levels");
}

TEST_F(Imports, AViewInTheFileIsRefusedAtOnceAndTheServerStaysResponsive) {
  const auto start = std::chrono::steady_clock::now();
  expect_refused(import(variant("DROP TABLE events; CREATE VIEW events AS WITH RECURSIVE c(n) AS (SELECT 0 UNION ALL SELECT n+1 FROM c) "
                                "SELECT 'x' AS episode_id, n AS seq, 0 AS tick, 0.0 AS time, 'k' AS kind, '' AS subject, '{}' AS data FROM c")),
                 400, "its view 'events' is not in hrisim's schema");
  expect_refused(import(variant("CREATE TRIGGER t AFTER INSERT ON runs BEGIN SELECT 1; END")), 400, "its trigger 't'");
  // Today's code hung until killed; a generous bound keeps the test from passing by waiting.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
}

TEST_F(Imports, TextThatExpandsToMegabytesIsRefused) {
  expect_refused(import(variant("UPDATE runs SET name = printf('%.*c', 3000000, 'x')")), 400, "/name: name must be text of at most 200 bytes");
  expect_refused(import(variant("UPDATE runs SET notes = 'a' || char(0) || 'b'")), 400, "without NUL");
}

TEST_F(Imports, ScenariosCannotBePlantedUnderAContentIdOrAnotherOwner) {
  // The CLI's scenario record is named by its content: other content under that id is refused.
  expect_refused(import(variant("UPDATE scenarios SET source = source || ' '")), 400, "has a sha256 that is not its content's");
  expect_refused(import(variant("UPDATE scenarios SET source = source || ' ', sha256 = lower(hex(randomblob(32)))")), 400, "sha256");
  // An upload's record of alice's, imported by bob: it becomes bob's, never alice's.
  const std::string upload = "u0123456789abcdef0123456789abcdef";
  const std::string as_upload = "UPDATE scenarios SET id = '" + upload + "', owner = 'alice'; UPDATE runs SET scenario_id = '" + upload +
                                "', id = 'r00000000000000000000000000000001'; UPDATE episodes SET scenario_id = '" + upload +
                                "', run_id = 'r00000000000000000000000000000001', id = 'e' || lower(hex(substr(id, 2, 16))); UPDATE metric_values SET episode_id = 'e' || lower(hex(substr(episode_id, 2, 16))); "
                                "UPDATE events SET episode_id = 'e' || lower(hex(substr(episode_id, 2, 16))); UPDATE trajectory_samples SET episode_id = 'e' || lower(hex(substr(episode_id, 2, 16))); "
                                "UPDATE metric_series SET episode_id = 'e' || lower(hex(substr(episode_id, 2, 16)));";
  const HttpReply imported = import(variant(as_upload), kBob);
  ASSERT_EQ(imported.status, 200) << imported.body;
  const HttpReply alices = http(server_->port(), "GET", "/api/v1/scenarios/" + upload, "", bearer(kAlice));
  EXPECT_EQ(alices.status, 404) << "not in alice's catalogue: " << alices.body;
  EXPECT_EQ(http(server_->port(), "GET", "/api/v1/scenarios/" + upload, "", bearer(kBob)).status, 200) << "bob's";
}

TEST_F(Imports, AConfigOfTheWrongTypesIsRefusedAndListingsKeepWorking) {
  expect_refused(import(variant("UPDATE runs SET config = json_set(config, '$.seeds', 'x')")), 400, "has no list of 1 to 100000 seeds");
  expect_refused(import(variant("UPDATE runs SET config = json_set(config, '$.seeds', json('[1,1]'))")), 400, "lists seed 1 twice");
  expect_refused(import(variant("UPDATE runs SET config = json_set(config, '$.seeds', json('[-1,2]'))")), 400, "not a whole number");
  expect_refused(import(variant("UPDATE runs SET config = json_set(config, '$.gates', json('[\"nonsense >\"]'))")), 400, "has a gate that does not parse");
  expect_refused(import(variant("UPDATE episodes SET run_id = 'r/../../x'; UPDATE runs SET id = 'r/../../x'")), 400, "has an id that is not 'r'");
  EXPECT_GE(runs_of(kAlice), 0);
}

TEST_F(Imports, AConfigTheApiWouldNotTakeIsRefusedWithItsPointer) {
  // Configs of the right types that POST /api/v1/runs would refuse: each is compiled against its
  // scenario as a request is, and refused naming the run and the field.
  const int before = runs_of(kAlice);
  expect_refused(import(variant("UPDATE runs SET config = json_set(config, '$.effective_controller', json('{\"type\": \"goal\", \"goal\": {\"location\": \"nowhere\"}}'))")),
                 400, "unknown location 'nowhere'");
  expect_refused(import(variant("UPDATE runs SET config = json_set(config, '$.max_time', 1e12)")), 400, "max_time");
  expect_refused(import(variant("UPDATE runs SET config = json_set(config, '$.requests', json('[{\"time\": 1, \"routine\": \"nope\"}]'))")), 400,
                 "the scenario has no task 'nope'");
  const HttpReply refused = import(variant("UPDATE runs SET config = json_set(config, '$.max_time', 1e12)"));
  const json error = json::parse(refused.body)["error"];
  EXPECT_NE(error["message"].get<std::string>().find("config is not one the API would take"), std::string::npos) << refused.body;
  EXPECT_EQ(error["details"]["pointer"], "/max_time") << refused.body;
  EXPECT_EQ(runs_of(kAlice), before) << "nothing stored";
}

TEST_F(Imports, ManyDistinctConfigurationsAreRefusedBeforeTheyAreCompiled) {
  // Each distinct configuration is compiled against its scenario; an import may not ask for more than
  // 64 compiles (64 more runs of the base run, each with its own max_time, make 65).
  const std::string runs = "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 64) "
                           "INSERT INTO runs (id, scenario_id, controller, config, status, created_at, finished_at, owner, name, tags, notes) "
                           "SELECT printf('r%032x', i), scenario_id, controller, json_set(config, '$.max_time', 1 + i / 100.0), status, created_at, "
                           "finished_at, owner, name, tags, notes FROM runs, n";
  const int before = runs_of(kAlice);
  expect_refused(import(variant(runs)), 400, "more than 64 distinct run configurations");
  EXPECT_EQ(runs_of(kAlice), before) << "nothing stored";
  // The same 65 runs of one configuration are one compile, and are imported.
  const std::string same = "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 64) "
                           "INSERT INTO runs (id, scenario_id, controller, config, status, created_at, finished_at, owner, name, tags, notes) "
                           "SELECT printf('r%032x', i + 1000), scenario_id, controller, config, status, created_at, finished_at, owner, name, tags, notes FROM runs, n";
  const HttpReply imported = import(variant(same));
  EXPECT_EQ(imported.status, 200) << imported.body;
}

TEST_F(Imports, AFileDamagedWhereQuickCheckDoesNotLookIsRefusedNot500) {
  // fuzz_import's finding: metric_values' rows out of their key's order pass quick_check, and the
  // private copy then lacked a table; reading it was a storage error, answered 500.
  const std::string damaged = read_bytes(std::string(HRISIM_SOURCE_DIR) + "/fuzz/corpus/import/crash-a-copy-without-a-table.db");
  const int before = runs_of(kAlice);
  expect_refused(import(damaged), 400, "the uploaded database cannot be read");
  EXPECT_EQ(runs_of(kAlice), before) << "nothing stored";
}

TEST_F(Imports, ARunIdImportedFirstByAnotherOwnerDoesNotBlockTheOwnersImport) {
  const std::string base = variant("");
  const HttpReply bobs = import(base, kBob);
  ASSERT_EQ(bobs.status, 200) << bobs.body;
  const HttpReply alices = import(base, kAlice);
  ASSERT_EQ(alices.status, 200) << alices.body;
  const json bob_run = json::parse(bobs.body)["runs"][0], alice_run = json::parse(alices.body)["runs"][0];
  EXPECT_EQ(bob_run["source_id"], alice_run["source_id"]);
  EXPECT_NE(bob_run["id"], alice_run["id"]) << "each owner's run is their own";
  EXPECT_EQ(http(server_->port(), "GET", "/api/v1/runs/" + alice_run["id"].get<std::string>(), "", bearer(kAlice)).status, 200);
  EXPECT_EQ(import(base, kAlice).status, 200) << "again: nothing more";
  // A conflict with alice's own run says it differs, and shows nothing of the run on the server.
  const HttpReply conflict = import(variant("UPDATE runs SET config = json_set(config, '$.gates', json('[\"collisions.max <= 7\"]'))"), kAlice);
  EXPECT_EQ(conflict.status, 409) << conflict.body;
  EXPECT_NE(conflict.body.find("another in this server's"), std::string::npos) << conflict.body;
  EXPECT_EQ(conflict.body.find("[]"), std::string::npos) << "the server's gates are not echoed: " << conflict.body;
}

TEST_F(Imports, AnEpisodeIdAnotherRunHoldsIsAConflictWithoutSqlitesWords) {
  ASSERT_EQ(import(variant(""), kAlice).status, 200);
  const HttpReply reply = import(variant("UPDATE runs SET id = 'r11111111111111111111111111111111'; UPDATE episodes SET run_id = 'r11111111111111111111111111111111'"), kAlice);
  EXPECT_EQ(reply.status, 409) << reply.body;
  EXPECT_EQ(reply.body.find("UNIQUE"), std::string::npos) << reply.body;
}

TEST(Merge, OpensItsInputsWithoutChangingThem) {
  TempDir dir;
  const std::filesystem::path shard = dir.path() / "shard.db", into = dir.path() / "into.db";
  ASSERT_EQ(run_command(kHrisim + " run " + kScenarios + "/queue.json --seeds 1 --max-time 2 --db " + shard.string()).exit_status, 0);
  // As a shard's file arrives: one file, no log beside it.
  sqlite3* db = nullptr;
  sqlite3_open(shard.c_str(), &db);
  exec(db, "PRAGMA journal_mode=DELETE");
  sqlite3_close(db);
  const std::string before = read_bytes(shard);
  const CommandResult merge = run_command(kHrisim + " merge " + shard.string() + " --into " + into.string());
  ASSERT_EQ(merge.exit_status, 0) << merge.output;
  EXPECT_EQ(read_bytes(shard), before) << "the input is not migrated nor switched to WAL";
  EXPECT_FALSE(std::filesystem::exists(shard.string() + "-wal"));
  EXPECT_FALSE(std::filesystem::exists(shard.string() + "-shm"));
}

}  // namespace
}  // namespace hrisim::testing
