// Sound in a session: a person who says something is heard by a robot's microphones, which point
// to her within 10 degrees; a wall between costs the named attenuation; walking people's footfalls are
// heard and standing ones make none; clips and the `say` command; the same seed, the same bits; and
// what the scenario's sound settings refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>

#include "scenario/load.hpp"
#include "sim/session.hpp"
#include "sim/sounds.hpp"
#include "support/commands.hpp"
#include "support/scenarios.hpp"
#include "support/temp_dir.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// The HSR at (3.5, 5) facing +x, listening; Ada at `ada` says something for 3 s from the start.
json talking(const json& ada, const json& microphones = json::object(), const json& walls = json::array()) {
  json document = testing::room_scenario(json::object());
  document["dt"] = 0.05;
  document["world"]["obstacles"] = json::array();
  for (const json& wall : walls) document["world"]["walls"].push_back(wall);
  document["humans"] = json::array({{{"id", "ada"}, {"start", ada}}});
  document["robots"] = json::array({{{"id", "hsr"}, {"model", "hsr"}, {"start", {{"x", 3.5}, {"y", 5}, {"theta", 0}}}, {"microphones", microphones}}});
  document["steps"] = json::array({{{"name", "talk"}, {"actions", json::array({{{"agent", "ada"}, {"say", {{"duration", 3}}}}})}}});
  return document;
}

const RobotRuntime::Hearing& hearing_of(const Session& session) { return *session.robot_runtime(session.agent_id("hsr"))->hearing; }

double energy(const sensors::AudioBlock& block) {
  double sum = 0.0;
  for (const float sample : block.data) sum += static_cast<double>(sample) * sample;
  return sum;
}

TEST(Sounds, ASpeakerIsLocatedWithinTenDegrees) {
  for (const double degrees : {30.0, 120.0, -100.0, 170.0}) {
    const double angle = degrees * std::numbers::pi / 180.0;
    const auto model = testing::load_valid(talking({{"x", 3.5 + 3 * std::cos(angle)}, {"y", 5 + 3 * std::sin(angle)}}));
    Session session(model, 1);
    for (int tick = 0; tick < 30; ++tick) session.tick();  // 1.5 s: the direction's window is 0.26 s
    const RobotRuntime& hsr = *session.robot_runtime(session.agent_id("hsr"));
    ASSERT_TRUE(hsr.hearing->reading) << degrees << "°: she is speaking";
    const Eigen::Isometry3d link = hsr.microphones_pose();
    EXPECT_EQ(hsr.hearing->microphones.array().link, "head_tilt_link");
    const Eigen::Vector3d heard = link.rotation() * Eigen::Vector3d(std::cos(hsr.hearing->reading->azimuth), std::sin(hsr.hearing->reading->azimuth), 0);
    const Vec2 to_her = session.state().agents[session.agent_id("ada").index].position - Vec2(link.translation().x(), link.translation().y());
    const double error = std::abs(core::wrap_angle(std::atan2(heard.y(), heard.x()) - std::atan2(to_her.y(), to_her.x())));
    EXPECT_LT(error, 10.0 * std::numbers::pi / 180.0) << "speaker at " << degrees << "°";
    EXPECT_EQ(hsr.hearing->block.channels, 4);
    EXPECT_EQ(hsr.hearing->block.samples, 800) << "16 kHz × 0.05 s";
  }
}

TEST(Sounds, AWallBetweenCostsItsAttenuation) {
  // Silent microphones and a still robot: what is heard is her voice alone, the same with and without
  // the wall but for the wall's factor.
  const json quiet = {{"self_noise", 0}, {"motor_noise", 0}};
  const json ada = {{"x", 7}, {"y", 5}};
  Session open(testing::load_valid(talking(ada, quiet)), 1);
  Session walled(testing::load_valid(talking(ada, quiet, json::array({{{"from", {5, 0.5}}, {"to", {5, 9.5}}}}))), 1);
  double open_energy = 0.0, walled_energy = 0.0;
  for (int tick = 0; tick < 40; ++tick) {
    open.tick();
    walled.tick();
    open_energy += energy(hearing_of(open).block);
    walled_energy += energy(hearing_of(walled).block);
  }
  ASSERT_GT(open_energy, 0.0);
  EXPECT_NEAR(std::sqrt(walled_energy / open_energy), sensors::kWallAttenuation, 1e-4 * sensors::kWallAttenuation);
  EXPECT_EQ(walls_between(open.model(), open.state(), {3.5, 5, 1}, {7, 5, 1.5}), 0);
  EXPECT_EQ(walls_between(walled.model(), walled.state(), {3.5, 5, 1}, {7, 5, 1.5}), 1);
}

TEST(Sounds, WalkersFootfallsAreHeardAndStandingPeopleMakeNone) {
  const json quiet = {{"self_noise", 0}, {"motor_noise", 0}};
  json document = talking({{"x", 6}, {"y", 2}}, quiet);
  document["steps"] = json::array();  // she stands, silent
  Session standing(testing::load_valid(document), 1);
  for (int tick = 0; tick < 40; ++tick) standing.tick();
  EXPECT_TRUE(standing.state().sounds.empty());
  EXPECT_EQ(energy(hearing_of(standing).block), 0.0);

  document["steps"] = json::array({{{"name", "walk"}, {"actions", json::array({{{"agent", "ada"}, {"goto", {{"pose", {{"x", 6}, {"y", 8}}}}}}})}}});
  Session walking(testing::load_valid(document), 1);
  int footsteps = 0;
  double heard = 0.0;
  for (int tick = 0; tick < 60; ++tick) {
    const std::size_t before = walking.state().sounds.size();
    walking.tick();
    for (std::size_t s = before; s < walking.state().sounds.size(); ++s) footsteps += walking.state().sounds[s].kind() == sensors::SoundKind::footstep;
    heard += energy(hearing_of(walking).block);
  }
  EXPECT_GE(footsteps, 4) << "about two steps a second over 3 s, once she is up to speed";
  EXPECT_GT(heard, 0.0);
}

TEST(Sounds, TheSameSeedGivesTheSameBits) {
  const auto model = testing::load_valid(talking({{"x", 5}, {"y", 7}}));
  Session first(model, 3), second(model, 3);
  for (int tick = 0; tick < 30; ++tick) {
    first.tick();
    second.tick();
  }
  EXPECT_EQ(first.state_hash(), second.state_hash());
  EXPECT_EQ(std::memcmp(hearing_of(first).block.data.data(), hearing_of(second).block.data.data(), 4 * hearing_of(first).block.data.size()), 0);
  Session other(model, 4);
  for (int tick = 0; tick < 30; ++tick) other.tick();
  EXPECT_NE(other.state_hash(), first.state_hash()) << "the microphones' noise is the seed's";
}

/// A 0.5 s 440 Hz tone at 8 kHz, PCM16 mono.
std::string tone_wav() {
  constexpr int kRate = 8000, kSamples = 4000;
  std::string wav(44 + 2 * kSamples, '\0');
  const auto put32 = [&](std::size_t at, std::uint32_t v) { std::memcpy(&wav[at], &v, 4); };
  const auto put16 = [&](std::size_t at, std::uint16_t v) { std::memcpy(&wav[at], &v, 2); };
  std::memcpy(&wav[0], "RIFF", 4);
  put32(4, static_cast<std::uint32_t>(wav.size() - 8));
  std::memcpy(&wav[8], "WAVEfmt ", 8);
  put32(16, 16);
  put16(20, 1);
  put16(22, 1);
  put32(24, kRate);
  put32(28, 2 * kRate);
  put16(32, 2);
  put16(34, 16);
  std::memcpy(&wav[36], "data", 4);
  put32(40, 2 * kSamples);
  for (int k = 0; k < kSamples; ++k) put16(44 + 2 * k, static_cast<std::uint16_t>(static_cast<std::int16_t>(8000 * std::sin(2 * std::numbers::pi * 440 * k / kRate))));
  return wav;
}

TEST(Sounds, APersonSaysAClipAndTheSayCommandWorks) {
  testing::TempDir dir;
  std::ofstream(dir / "hello.wav", std::ios::binary) << tone_wav();
  json document = talking({{"x", 5}, {"y", 5}});
  document["clips"] = {{"hello", (dir / "hello.wav").string()}};
  document["steps"][0]["actions"][0]["say"] = {{"clip", "hello"}};
  const auto model = testing::load_valid(document);
  ASSERT_TRUE(model);
  EXPECT_EQ(model->clips.at(0).second->sample_rate, sensors::kSampleRate) << "resampled on loading";
  EXPECT_DOUBLE_EQ(model->steps[0].actions[0].value, 0.5) << "the clip's length";
  Session session(model, 1);
  session.tick();
  ASSERT_EQ(session.state().sounds.size(), 1u);
  EXPECT_EQ(session.state().sounds[0].kind(), sensors::SoundKind::clip);
  for (int tick = 0; tick < 10; ++tick) session.tick();
  EXPECT_EQ(session.state().current_step, 1) << "the say action lasts the clip's 0.5 s";

  testing::command(session, "ada", "say 1.5");
  testing::command(session, "ada", "say hello");
  EXPECT_EQ(session.state().commanded.back().kind, scenario::Action::Kind::say);
  EXPECT_THROW(testing::command(session, "ada", "say goodbye"), core::Error);
  EXPECT_THROW(testing::command(session, "ada", "say -2"), core::Error);
  EXPECT_THROW(testing::command(session, "ada", "say"), core::Error);
}

TEST(Sounds, WhatTheSoundSettingsRefuse) {
  json document = talking({{"x", 5}, {"y", 5}});
  document["robots"][0]["model"] = "artos";
  EXPECT_EQ(testing::error_at(document, "/robots/0/microphones"), "robot model 'artos' has no microphones (hsr and roman have)");
  document = talking({{"x", 5}, {"y", 5}});
  document["steps"][0]["actions"][0]["say"] = {{"clip", "hello"}};
  EXPECT_EQ(testing::error_at(document, "/steps/0/actions/0/say/clip"), "unknown clip 'hello' (none in 'clips')");
  document["clips"] = {{"hello", "/nowhere/hello.wav"}};
  EXPECT_NE(testing::error_at(document, "/clips/hello").find("not found"), std::string::npos);
  testing::TempDir dir;
  std::ofstream(dir / "bad.wav", std::ios::binary) << "RIFF0000WAVEjunk";
  document["clips"] = {{"hello", (dir / "bad.wav").string()}};
  EXPECT_NE(testing::error_at(document, "/clips/hello").find("WAV"), std::string::npos);
  document = talking({{"x", 5}, {"y", 5}});
  document["steps"][0]["actions"][0]["say"] = {{"duration", -1}};
  EXPECT_FALSE(scenario::load_scenario(document, {}).errors.empty()) << "a duration is > 0";
}

}  // namespace
}  // namespace hrisim::sim
