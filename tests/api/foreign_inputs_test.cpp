// Foreign inputs bounded by what they expand to, and slow clients (issue 40): each finding reproduced
// against the real server by the request that showed it, then the refusal asserted — a 4xx naming
// what is wrong and where, nothing stored, the server responsive.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "test_server.hpp"

namespace hrisim::testing {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

json json_of(const HttpReply& reply) { return json::parse(reply.body); }

const char* const kHealth = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";

/// A small native scenario on open ground.
json open_ground() {
  return {{"name", "probe"},
          {"world", {{"bounds", {{"min", {0.0, 0.0}}, {"max", {4.0, 3.0}}}}}},
          {"humans", {{{"id", "ana"}, {"start", {{"x", 1.0}, {"y", 1.0}, {"theta", 0.0}}}}}},
          {"steps", json::array()}};
}

std::size_t uploads(const TestServer& server) {
  std::size_t count = 0;
  for (const json& item : json_of(http(server.port(), "GET", "/api/v1/scenarios?limit=200"))["items"]) count += item["origin"] == "uploaded";
  return count;
}

// Finding 9: slowloris from 4 addresses (64 connections each, the per-address maximum) took every
// connection, and /healthz answered 503 for 75 s.
TEST(ForeignInputs, SlowlorisFromFourAddressesDoesNotTakeHealthDown) {
  TestServer server({"--header-timeout", "2"});
  std::vector<std::unique_ptr<RawConnection>> slow;
  for (int address = 2; address <= 5; ++address) {
    for (int i = 0; i < 64; ++i) {
      slow.push_back(std::make_unique<RawConnection>(server.port(), std::chrono::milliseconds(100), "127.0.0." + std::to_string(address)));
      slow.back()->send("GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\n");  // never finished
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto asked = Clock::now();
  RawConnection health(server.port(), std::chrono::seconds(5), "127.0.0.9");
  health.send(kHealth);
  EXPECT_EQ(health.read_reply().status, 200) << "a connection waiting for its header gives its place up";
  EXPECT_LT(Clock::now() - asked, std::chrono::seconds(1));
  // The header deadline closes the rest, well before the 30 s read timeout.
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  std::size_t open = 0;
  for (const auto& connection : slow) open += !connection->closed_by_peer();
  EXPECT_EQ(open, 0u) << "connections still open 2.5 s past the 2 s header deadline";
}

TEST(ForeignInputs, TheHeaderDeadlineIsApartFromTheBodys) {
  TestServer server({"--header-timeout", "1", "--read-timeout", "30"});
  // A header trickled a byte every 200 ms is cut at 1 s, though the read timeout is 30 s.
  RawConnection trickle(server.port(), std::chrono::milliseconds(200));
  const std::string header = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
  const auto started = Clock::now();
  bool closed = false;
  for (std::size_t i = 0; !closed && Clock::now() - started < std::chrono::seconds(5); ++i) {
    closed = !trickle.send(std::string(1, header[i % header.size()]));
    if (!closed) closed = trickle.closed_by_peer();
  }
  EXPECT_TRUE(closed);
  EXPECT_LT(Clock::now() - started, std::chrono::seconds(3));
  // A whole header at once, then a body 1.5 s later: the body has the read timeout's 30 s.
  RawConnection patient(server.port());
  patient.send("POST /api/v1/scenarios/validate HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nContent-Length: 2\r\n\r\n");
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  patient.send("{}");
  EXPECT_EQ(patient.read_reply().status, 200);
}

// Finding 10: a bundle holding both `d` and `d/f` answered 500 and left `…partial-…` folders.
TEST(ForeignInputs, ABundleWithAFileInsideAnotherIs400AndLeavesNoFolders) {
  TestServer server;
  const json bundle = {{"scenario", open_ground()}, {"files", {{"d", "x"}, {"d/f", "y"}, {"e/g/h", "z"}, {"e/g", "w"}}}};
  for (const char* route : {"/api/v1/scenarios", "/api/v1/scenarios/validate"}) {
    const HttpReply reply = http(server.port(), "POST", route, bundle.dump());
    EXPECT_EQ(reply.status, 400) << route << ": " << reply.body;
    EXPECT_EQ(json_of(reply)["error"]["details"]["pointer"], "/files/d~1f") << reply.body;
    EXPECT_NE(json_of(reply)["error"]["message"].get<std::string>().find("'d' cannot be a folder holding 'd/f'"), std::string::npos) << reply.body;
  }
  EXPECT_EQ(uploads(server), 0u);
  const std::string mine = "hrisim-files-" + std::to_string(server.pid()) + "-";
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::temp_directory_path())) {
    if (!entry.path().filename().string().starts_with(mine)) continue;
    for (const auto& inside : std::filesystem::recursive_directory_iterator(entry.path())) {
      EXPECT_EQ(inside.path().string().find(".partial-"), std::string::npos) << inside.path();
    }
  }
  EXPECT_EQ(http(server.port(), "GET", "/healthz").status, 200);
}

/// A mono 16-bit WAV file's bytes at `rate` Hz, of `samples` silent samples.
std::string wav(std::uint32_t rate, std::uint32_t samples) {
  std::string bytes;
  const auto put = [&bytes](std::uint32_t value, int size) {
    for (int i = 0; i < size; ++i) bytes.push_back(static_cast<char>((value >> (8 * i)) & 0xFF));
  };
  bytes += "RIFF";
  put(36 + 2 * samples, 4);
  bytes += "WAVEfmt ";
  put(16, 4), put(1, 2), put(1, 2), put(rate, 4), put(rate * 2, 4), put(2, 2), put(16, 2);
  bytes += "data";
  put(2 * samples, 4);
  return bytes + std::string(2 * samples, '\0');
}

// Finding 8: a clip whose header said 1 Hz was resampled to 16 kHz: 40 KB → 198 s and 1.2 GB.
TEST(ForeignInputs, AClipWhoseHeaderSays1HzIsRefusedAtItsClip) {
  TestServer server;
  json scenario = open_ground();
  scenario["clips"] = {{"hello", "hello.wav"}};
  const json bundle = {{"scenario", scenario}, {"files", {{"hello.wav", {{"base64", base64(wav(1, 20000))}}}}}};
  const auto started = Clock::now();
  const HttpReply reply = http(server.port(), "POST", "/api/v1/scenarios", bundle.dump());
  EXPECT_LT(Clock::now() - started, std::chrono::seconds(5));
  ASSERT_EQ(reply.status, 400) << reply.body;
  const json errors = json_of(reply)["error"]["details"]["errors"];
  ASSERT_EQ(errors.size(), 1u) << reply.body;
  EXPECT_EQ(errors[0]["pointer"], "/clips/hello");
  EXPECT_NE(errors[0]["message"].get<std::string>().find("WAV: the sample rate is 1 Hz; clips are read at 8000 to 192000 Hz"), std::string::npos) << reply.body;
  EXPECT_EQ(uploads(server), 0u);
  // The same silence at 8 kHz is a clip.
  const json fine = {{"scenario", scenario}, {"files", {{"hello.wav", {{"base64", base64(wav(8000, 8000))}}}}}};
  EXPECT_EQ(http(server.port(), "POST", "/api/v1/scenarios", fine.dump()).status, 201);
}

// Finding 7: a 64 KB HuNavSim file aliasing one 10,000-goal list into 100 agents took 56 s and 1.7 GB.
TEST(ForeignInputs, AYamlAliasBombIsRefusedAtItsLineAndNothingIsStored) {
  TestServer server;
  std::string yaml = "hunav_loader:\n  ros__parameters:\n    agents: [a0";
  for (int i = 1; i < 100; ++i) yaml += ", a" + std::to_string(i);
  yaml += "]\n    a0: &agent\n      init_pose: {x: 1, y: 1}\n      g: {x: 2, y: 2}\n      goals: [g";
  for (int g = 1; g < 10000; ++g) yaml += ", g";
  yaml += "]\n";
  for (int i = 1; i < 100; ++i) yaml += "    a" + std::to_string(i) + ": *agent\n";
  const auto started = Clock::now();
  const HttpReply reply = http(server.port(), "POST", "/api/v1/scenarios", yaml, "Content-Type: application/yaml\r\n");
  EXPECT_LT(Clock::now() - started, std::chrono::seconds(5));
  ASSERT_EQ(reply.status, 400) << reply.body;
  const json errors = json_of(reply)["error"]["details"]["errors"];
  ASSERT_EQ(errors.size(), 1u) << reply.body;
  EXPECT_GE(errors[0]["line"].get<int>(), 8) << reply.body;
  EXPECT_NE(errors[0]["message"].get<std::string>().find("the YAML expands to more than 200000 nodes"), std::string::npos) << reply.body;
  EXPECT_EQ(uploads(server), 0u);
}

}  // namespace
}  // namespace hrisim::testing
