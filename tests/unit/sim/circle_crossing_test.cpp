// CrowdNav's circle crossing (crowd_sim's circle_crossing, Chen et al. 2019): five ORCA people on a
// circle of radius 4 m cross to its far side while a robot (ARTOS: 0.3 m, 1 m/s, as CrowdNav's) drives
// ORCA from (0, -4) to (0, 4). With CrowdNav's own crowd settings (ORCA seeing 10 neighbours within 10
// m, 5 s horizons, no margins) the robot reaches its goal without touching anyone, as CrowdNav's README
// has it for an ORCA robot the people see (issue 42, item 6).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include "core/random.hpp"
#include "humans/locomotion.hpp"
#include "scenario/load.hpp"
#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

constexpr double kCircleRadius = 4.0;  ///< crowd_sim's circle_radius, m
constexpr int kPeople = 5;             ///< crowd_sim's human_num
constexpr double kRadius = 0.3;        ///< crowd_sim's human and robot radius, m
constexpr double kDiscomfort = 0.2;    ///< crowd_sim's discomfort_dist: starts and goals this far apart beyond touching, m
constexpr double kTimeLimit = 25.0;    ///< crowd_sim's time_limit, s

/// The circle crossing of one seed, drawn as crowd_sim draws it: each person at a uniform angle on the
/// circle, moved by up to ±v_pref/2 in x and y, going to the antipode of that start; drawn again when
/// their start or goal is nearer anyone's start or goal than two radii and the discomfort distance —
/// the robot's by kLimbClearance rather: a person's feet reach that far beyond their disc, and
/// CrowdNav's bodies, discs, have none (a person drawn 0.2 m from the robot's disc touched it with
/// the first step).
json circle_crossing(unsigned seed) {
  core::Random random(seed);
  const auto unit = [&random] { return random.uniform(); };
  std::vector<Vec2> starts{{0.0, -kCircleRadius}}, goals{{0.0, kCircleRadius}};  // the robot's
  json document = json::parse(R"({"name": "circle_crossing", "time_limit": 25,
    "world": {"bounds": {"min": [-7, -7], "max": [7, 7]}},
    "locomotion": {"avoidance": "orca", "preset": "crowdnav"},
    "robots": [{"id": "robot", "model": "artos", "start": {"x": 0, "y": -4, "theta": 1.5708},
                "controller": {"type": "orca", "goal": {"pose": {"x": 0, "y": 4}, "radius": 0.2}}}],
    "humans": [], "steps": [{"name": "cross", "actions": []}]})");
  for (int i = 0; i < kPeople; ++i) {
    Vec2 start;
    for (bool clear = false; !clear;) {
      const double angle = unit() * 2.0 * std::numbers::pi;
      start = kCircleRadius * Vec2(std::cos(angle), std::sin(angle)) + Vec2(unit() - 0.5, unit() - 0.5);
      clear = true;
      for (std::size_t k = 0; k < starts.size(); ++k) {
        const double apart = 2 * kRadius + (k == 0 ? humans::kLimbClearance : kDiscomfort);
        clear = clear && (start - starts[k]).norm() >= apart && (start - goals[k]).norm() >= apart;
      }
    }
    starts.push_back(start);
    goals.push_back(-start);
    const std::string id = "h" + std::to_string(i);
    document["humans"].push_back({{"id", id}, {"radius", kRadius}, {"preferred_speed", 1.0}, {"start", {{"x", start.x()}, {"y", start.y()}}}});
    document["steps"][0]["actions"].push_back({{"agent", id}, {"goto", {{"pose", {{"x", -start.x()}, {"y", -start.y()}}}}}});
  }
  return document;
}

struct Episode {
  bool reached = false;
  int contacts = 0;  ///< contact_start events of the robot with a person
};

Episode cross(const std::shared_ptr<const scenario::Model>& model, unsigned seed) {
  Session session(model, seed);
  Episode episode;
  std::size_t seen = 0;
  while (!episode.reached && session.time() < kTimeLimit) {
    session.tick();
    for (; seen < session.state().events.size(); ++seen) {
      const Event& event = session.state().events[seen];
      episode.reached |= event.is<events::RobotGoalReached>();
      if (const auto* contact = event.as<events::ContactStart>()) episode.contacts += contact->with.starts_with("h");
    }
  }
  return episode;
}

/// Seeds run, and the share of them the robot must reach its goal in within the time limit: ORCA
/// among ORCA people can still deadlock until the time runs out (3 seeds of the 50 do), which
/// CrowdNav counts as a timeout, not a collision.
constexpr unsigned kSeeds = 50;
constexpr double kSuccessShare = 0.9;

TEST(CircleCrossing, AnOrcaRobotAmongOrcaPeopleWhoSeeItSucceedsWithoutContact) {
  int successes = 0, contacts = 0;
  for (unsigned seed = 0; seed < kSeeds; ++seed) {
    const Episode episode = cross(testing::load_valid(circle_crossing(seed)), seed);
    successes += episode.reached && episode.contacts == 0;
    contacts += episode.contacts;
  }
  std::printf("circle crossing, CrowdNav's crowd: %d of %u successes, %d contacts\n", successes, kSeeds, contacts);
  EXPECT_EQ(contacts, 0);
  EXPECT_GE(successes, kSuccessShare * kSeeds);
}

// The bundled scenario (one fixed draw), under each setting of its switch: the robot gets across
// without touching anyone.
TEST(CircleCrossing, TheBundledScenarioGetsTheRobotAcrossUnderEveryCrowdPreset) {
  std::ifstream file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/circle_crossing.json");
  json document = json::parse(file);
  ASSERT_EQ(document["locomotion"]["preset"], "crowdnav") << "CrowdNav's crowd, as its name says";
  for (const char* preset : {"crowdnav", "hrisim", "calibrated"}) {
    document["locomotion"]["preset"] = preset;
    const Episode episode = cross(testing::load_valid(document), 1);
    EXPECT_TRUE(episode.reached) << preset;
    EXPECT_EQ(episode.contacts, 0) << preset;
  }
}

}  // namespace
}  // namespace hrisim::sim
