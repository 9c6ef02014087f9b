// The scenarios routes against the real server: list, get, upload (JSON, IMHuS XML, Pedsim XML,
// HuNavSim YAML),
// validate, and bad input that stores nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "storage/store.hpp"
#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

const std::string kJson = "Content-Type: application/json\r\n";
const std::string kXml = "Content-Type: application/xml\r\n";

class ScenariosApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { server_ = new TestServer(); }
  static void TearDownTestSuite() {
    delete server_;
    server_ = nullptr;
  }
  static std::uint16_t port() { return server_->port(); }
  static TestServer* server_;
};
TestServer* ScenariosApi::server_ = nullptr;

const char* kSmall = R"({"name": "tiny", "world": {"bounds": {"min": [0, 0], "max": [5, 5]}},
  "humans": [{"id": "ana", "start": {"x": 1, "y": 1}}],
  "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 4, "y": 4}}}]}]})";

TEST_F(ScenariosApi, BundledScenariosAreListedWithSummaries) {
  const json page = json_of(http(port(), "GET", "/api/v1/scenarios?limit=200"));
  std::map<std::string, json> by_id;
  for (const json& item : page["items"]) by_id[item["id"]] = item;
  ASSERT_TRUE(by_id.contains("elevator"));
  const json& elevator = by_id["elevator"];
  EXPECT_EQ(elevator["origin"], "bundled");
  EXPECT_EQ(elevator["humans"], 6);
  ASSERT_EQ(elevator["robots"].size(), 1u);
  EXPECT_EQ(elevator["robots"][0]["model"], "hsr");
  EXPECT_EQ(elevator["steps"], 6);
  EXPECT_GT(elevator["duration"].get<double>(), 0.0);
  const json native = json_of(http(port(), "GET", "/api/v1/scenarios/elevator"));
  EXPECT_EQ(native["name"], "elevator");
  EXPECT_EQ(native["robots"][0]["model"], "hsr");
}

TEST_F(ScenariosApi, PagesFollowTheCursor) {
  const json first = json_of(http(port(), "GET", "/api/v1/scenarios?limit=2"));
  ASSERT_EQ(first["items"].size(), 2u);
  ASSERT_TRUE(first["next_cursor"].is_string());
  const json second = json_of(http(port(), "GET", "/api/v1/scenarios?limit=2&cursor=" + first["next_cursor"].get<std::string>()));
  ASSERT_FALSE(second["items"].empty());
  EXPECT_GT(second["items"][0]["id"].get<std::string>(), first["items"][1]["id"].get<std::string>());
  for (const char* bad : {"0", "201", "x", "5x"}) {
    const HttpReply reply = http(port(), "GET", std::string("/api/v1/scenarios?limit=") + bad);
    EXPECT_EQ(reply.status, 400) << bad;
    EXPECT_EQ(json_of(reply)["error"]["details"]["parameter"], "limit");
  }
}

TEST_F(ScenariosApi, UploadStoresTheSourceAndServesTheNativeDocument) {
  const HttpReply created = http(port(), "POST", "/api/v1/scenarios", kSmall, kJson);
  ASSERT_EQ(created.status, 201) << created.body;
  const json summary = json_of(created)["summary"];
  const std::string id = summary["id"];
  EXPECT_EQ(id.size(), 33u) << "u and 128 random bits in hex";
  EXPECT_EQ(summary["origin"], "uploaded");
  EXPECT_EQ(summary["format"], "json");
  EXPECT_EQ(summary["humans"], 1);
  EXPECT_EQ(summary["sha256"].get<std::string>().size(), 64u);
  EXPECT_EQ(created.headers.at("location"), "/api/v1/scenarios/" + id);
  EXPECT_EQ(json_of(http(port(), "GET", "/api/v1/scenarios/" + id))["name"], "tiny");
  const json page = json_of(http(port(), "GET", "/api/v1/scenarios?limit=200"));
  EXPECT_TRUE(std::any_of(page["items"].begin(), page["items"].end(), [&](const json& item) { return item["id"] == id; }));
}

/// Uploads a Pedsim file by its content, validates it as Pedsim (valid) and as IMHuS (errors with lines);
/// returns the stored upload's summary.
json expect_pedsim_upload(std::uint16_t port, const std::string& pedsim) {
  const HttpReply by_content = http(port, "POST", "/api/v1/scenarios", pedsim, kXml);
  EXPECT_EQ(by_content.status, 201) << by_content.body;
  if (by_content.status != 201) return json();
  EXPECT_EQ(json_of(by_content)["summary"]["format"], "pedsim_xml");
  const HttpReply named = http(port, "POST", "/api/v1/scenarios/validate?format=pedsim", pedsim, kXml);
  EXPECT_TRUE(json_of(named)["valid"].get<bool>()) << named.body;
  const HttpReply wrong = http(port, "POST", "/api/v1/scenarios/validate?format=imhus", pedsim, kXml);
  EXPECT_FALSE(json_of(wrong)["valid"].get<bool>());
  EXPECT_TRUE(json_of(wrong)["errors"][0].contains("line")) << "XML errors name their line: " << wrong.body;
  return json_of(by_content)["summary"];
}

// hrisim's own Pedsim passage (tests/fixtures/pedsim/passage.xml): a source of six walkers and a robot.
TEST_F(ScenariosApi, XmlUploadsAreImportedByContentOrFormat) {
  const std::string pedsim = file_text(std::string(HRISIM_SOURCE_DIR) + "/tests/fixtures/pedsim/passage.xml");
  ASSERT_FALSE(pedsim.empty());
  json summary = expect_pedsim_upload(port(), pedsim);
  EXPECT_EQ(summary["humans"], 6 * 60) << "its source adds six every 5 s of the 300";
  ASSERT_EQ(summary["robots"].size(), 1u);
  EXPECT_EQ(summary["robots"][0]["id"], "robot_0");
}

// Pedsim's published corridor (../shared/external/SOURCES.md), read in place when ../shared is beside the project.
TEST_F(ScenariosApi, PublishedPedsimCorridorUploads) {
  const std::filesystem::path corridor = std::filesystem::path(HRISIM_SOURCE_DIR) / "../shared/external/pedsim/corridor.xml";
  if (!std::filesystem::exists(corridor)) {
    GTEST_SKIP() << "no ../shared/external/pedsim/corridor.xml beside the project: the project's own fixture "
                    "tests/fixtures/pedsim/passage.xml covers this path (ScenariosApi.XmlUploadsAreImportedByContentOrFormat)";
  }
  json summary = expect_pedsim_upload(port(), file_text(corridor.string()));
  EXPECT_EQ(summary["humans"], 8 * 60) << "its source adds eight every 5 s of the 300";
}

// hrisim's own HuNavSim agents file (tests/fixtures/hunav/lobby_agents.yaml) bundled with the map its
// `map: lobby` names (maps/lobby.yaml in the bundle), and on its own (open ground, with a warning).
TEST_F(ScenariosApi, HunavAgentsFilesUploadWithTheMapTheyName) {
  const std::string fixtures = std::string(HRISIM_SOURCE_DIR) + "/tests/fixtures/";
  const std::string agents = file_text(fixtures + "hunav/lobby_agents.yaml");
  ASSERT_FALSE(agents.empty());
  const json bundle{{"scenario", agents},
                    {"files", {{"maps/lobby.yaml", file_text(fixtures + "maps/lobby.yaml")},
                               {"maps/lobby.pgm", {{"base64", base64(file_text(fixtures + "maps/lobby.pgm"))}}}}}};
  const HttpReply uploaded = http(port(), "POST", "/api/v1/scenarios", bundle.dump(), kJson);
  ASSERT_EQ(uploaded.status, 201) << uploaded.body;
  const json summary = json_of(uploaded)["summary"];
  EXPECT_EQ(summary["format"], "hunav_yaml");
  EXPECT_EQ(summary["humans"], 5);
  const json document = json_of(http(port(), "GET", "/api/v1/scenarios/" + summary["id"].get<std::string>()));
  EXPECT_TRUE(document["world"].contains("map")) << document["world"];
  EXPECT_EQ(document["humans"][1]["behaviour"]["type"], "scared");

  const HttpReply named = http(port(), "POST", "/api/v1/scenarios/validate?format=hunav", bundle.dump(), kJson);
  EXPECT_TRUE(json_of(named)["valid"].get<bool>()) << "?format= names the bundle's scenario's format: " << named.body;

  const HttpReply alone = http(port(), "POST", "/api/v1/scenarios/validate", agents, "Content-Type: application/yaml\r\n");
  EXPECT_TRUE(json_of(alone)["valid"].get<bool>()) << alone.body;
  EXPECT_NE(alone.body.find("no map for world 'lobby'"), std::string::npos) << alone.body;
  const HttpReply broken = http(port(), "POST", "/api/v1/scenarios/validate?format=hunav", "hunav_loader:\n  ros__parameters:\n    agents: [x]\n",
                                "Content-Type: application/yaml\r\n");
  EXPECT_FALSE(json_of(broken)["valid"].get<bool>());
  EXPECT_EQ(json_of(broken)["errors"][0]["line"], 3) << broken.body;
}

TEST_F(ScenariosApi, ValidateReportsEveryErrorAndStoresNothing) {
  const json before = json_of(http(port(), "GET", "/api/v1/scenarios?limit=200"));
  json broken = json::parse(kSmall);
  broken["humans"][0]["start"] = {{"x", 9}, {"y", 9}};  // outside the map
  broken["steps"][0]["actions"][0]["agent"] = "bob";    // unknown agent
  const json report = json_of(http(port(), "POST", "/api/v1/scenarios/validate", broken.dump(), kJson));
  EXPECT_FALSE(report["valid"].get<bool>());
  std::set<std::string> pointers;
  for (const json& error : report["errors"]) pointers.insert(error["pointer"]);
  EXPECT_TRUE(pointers.contains("/humans/0/start"));
  EXPECT_TRUE(pointers.contains("/steps/0/actions/0/agent"));
  const HttpReply refused = http(port(), "POST", "/api/v1/scenarios", broken.dump(), kJson);
  EXPECT_EQ(refused.status, 400);
  EXPECT_EQ(json_of(refused)["error"]["details"]["errors"].size(), report["errors"].size());
  const HttpReply malformed = http(port(), "POST", "/api/v1/scenarios", "{\"name\": \"x\",\n  oops}", kJson);
  EXPECT_EQ(malformed.status, 400);
  EXPECT_NE(json_of(malformed)["error"]["details"]["errors"][0]["message"].get<std::string>().find("line 2"), std::string::npos);
  const HttpReply unknown_format = http(port(), "POST", "/api/v1/scenarios?format=yaml", kSmall, kJson);
  EXPECT_EQ(unknown_format.status, 400);
  EXPECT_EQ(http(port(), "GET", "/api/v1/scenarios/u0000").status, 404);
  const json after = json_of(http(port(), "GET", "/api/v1/scenarios?limit=200"));
  EXPECT_EQ(after["items"].size(), before["items"].size()) << "nothing stored";
}

}  // namespace
}  // namespace hrisim::testing

namespace hrisim::testing {
namespace {

/// A thousand malformed bodies and queries, generated from a fixed seed: each gets a JSON answer
/// below 500, the server stays healthy, nothing is stored, and the database is sound afterwards.
TEST(ScenariosApiFuzz, MalformedRequestsStoreNothingAndBreakNothing) {
  TestServer server;
  const std::uint16_t port = server.port();
  const std::size_t listed = json_of(http(port, "GET", "/api/v1/scenarios?limit=200"))["items"].size();
  std::mt19937_64 random(20261122);
  const std::string valid = json::parse(kSmall).dump();
  auto pick = [&](std::size_t n) { return static_cast<std::size_t>(random() % n); };
  int statuses_below_500 = 0;
  for (int i = 0; i < 1000; ++i) {
    std::string body, headers = kJson, target = i % 2 == 0 ? "/api/v1/scenarios" : "/api/v1/scenarios/validate";
    switch (i % 8) {
      case 0:  // truncated
        body = valid.substr(0, pick(valid.size()));
        break;
      case 1:  // random bytes, control characters and invalid UTF-8 included
        for (std::size_t k = 0, n = 1 + pick(300); k < n; ++k) body += static_cast<char>(random() & 0xFF);
        break;
      case 2:  // nested far too deep
        body = std::string(1000 + pick(50000), '[') + std::string(10, ']');
        break;
      case 3: {  // a valid document with one value of the wrong type
        json document = json::parse(valid);
        const json wrong[] = {5, "fast", json::array(), nullptr, 1e308, -1, json::object(), "🙂"};
        const char* keys[] = {"name", "dt", "humans", "steps", "world", "time_limit"};
        document[keys[pick(6)]] = wrong[pick(8)];
        body = document.dump();
        break;
      }
      case 4: {  // an agent that does not exist, or a place off the map
        json document = json::parse(valid);
        document["steps"][0]["actions"][0]["agent"] = "ghost" + std::to_string(i);
        document["humans"][0]["start"]["x"] = random() % 2 ? 1e9 : -1e9;
        body = document.dump();
        break;
      }
      case 5:  // XML that is broken or not a scenario
        headers = kXml;
        body = std::string("<?xml version=\"1.0\"?>\n<scenario><agent x=\"") + std::to_string(i) + (i % 3 ? "\"/>" : "");
        break;
      case 6:  // a format nobody knows
        target += "?format=" + std::string(1 + pick(5), static_cast<char>('a' + pick(26)));
        body = valid;
        break;
      case 7:  // JSON that is not an object
        body = json::array({valid, i}).dump();
        break;
    }
    const HttpReply reply = http(port, "POST", target, body, headers);
    ASSERT_LT(reply.status, 500) << "request " << i << ": " << reply.body;
    ASSERT_NE(reply.status, 201) << "request " << i << " was stored";
    EXPECT_NO_THROW(json_of(reply)) << "request " << i;
    ++statuses_below_500;
  }
  EXPECT_EQ(statuses_below_500, 1000);
  EXPECT_EQ(http(port, "GET", "/healthz").status, 200);
  EXPECT_EQ(json_of(http(port, "GET", "/api/v1/scenarios?limit=200"))["items"].size(), listed) << "nothing stored";
  ASSERT_EQ(server.terminate(std::chrono::seconds(10)), 0);
  storage::Store store(server.database());
  EXPECT_EQ(store.integrity_check(), "ok");
  EXPECT_EQ(store.counts().scenarios, 0);
}

}  // namespace
}  // namespace hrisim::testing
