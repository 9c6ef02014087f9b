// Golden determinism: the state hash after 600 ticks of every bundled scenario, seeds 1–3, and of the
// elevator with the robot's scripted request, as tests/golden/state_hashes.json holds them. Two runs in
// one process agreeing says the simulation is deterministic; these say it still does what it did, so a
// change of trajectory cannot pass unnoticed. A deliberate change of behaviour updates the file with
//   HRISIM_UPDATE_GOLDEN=1 build/test/tests/sim_test --gtest_filter='Golden.*'
// and the commit says why the hashes changed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <functional>
#include <variant>
#include <nlohmann/json.hpp>

#include "episode/episode.hpp"
#include "scenario/load.hpp"
#include "sim/session.hpp"
#include "sim/walking.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

constexpr int kGoldenTicks = 600;
const std::string kGoldenFile = std::string(HRISIM_SOURCE_DIR) + "/tests/golden/state_hashes.json";
const char* const kScenarios[] = {"apartment",          "apartment_search",   "approach_human",     "approach_human_apartment", "conversation_group",
                                  "corridor_navigation", "corridor_passing",   "crossing_navigation",      "elevator",
                                  "family_day",          "follow_human",        "mirror_gesture",     "pair_walking",             "perpendicular_crossing",
                                  "pick_and_place",      "queue",               "tea_break"};

std::string hash_after_golden_ticks(const scenario::LoadResult& loaded, std::uint64_t seed, episode::Settings settings = {}) {
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  if (!loaded.model) return "";
  settings.record = false;
  episode::Episode run(loaded.model, seed, settings);
  for (int tick = 0; tick < kGoldenTicks && !run.over(); ++tick) run.tick();
  return run.session().state_hash_hex();
}

std::string hash_after_golden_ticks(const std::string& scenario, std::uint64_t seed, episode::Settings settings = {}) {
  return hash_after_golden_ticks(scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + scenario + ".json"), seed, settings);
}

/// Every golden case: "scenario/seed" (and the elevator's request) → its hash now.
json current_hashes() {
  json hashes = json::object();
  for (const char* scenario : kScenarios) {
    for (const std::uint64_t seed : {1u, 2u, 3u}) hashes[std::string(scenario) + "/" + std::to_string(seed)] = hash_after_golden_ticks(scenario, seed);
  }
  hashes["elevator/1 with call_elevator_floor2 asked at 2 s"] =
      hash_after_golden_ticks("elevator", 1, {std::nullopt, {{2.0, "call_elevator_floor2"}}, false, {}});
  return hashes;
}

TEST(Golden, StateHashesAfter600TicksOfEveryBundledScenario) {
  const json now = current_hashes();
  if (std::getenv("HRISIM_UPDATE_GOLDEN")) {
    std::ofstream(kGoldenFile) << now.dump(2) << '\n';
    GTEST_SKIP() << "wrote " << kGoldenFile;
  }
  std::ifstream file(kGoldenFile);
  ASSERT_TRUE(file) << "no " << kGoldenFile;
  const json golden = json::parse(file);
  EXPECT_EQ(golden.size(), now.size()) << "cases were added or removed: update the file";
  for (const auto& [name, hash] : now.items()) {
    EXPECT_EQ(golden.value(name, ""), hash) << name << ": the trajectory changed. If on purpose, update the hashes: "
                                            << "HRISIM_UPDATE_GOLDEN=1 build/test/tests/sim_test --gtest_filter='Golden.*'";
  }
}

TEST(Golden, TheRoutinesFormerKeysGiveTheSameHashes) {
  // The bundled scenarios with routines, written with "tasks" and "task" as before: warned about, and
  // the very same simulation.
  std::ifstream file(kGoldenFile);
  ASSERT_TRUE(file) << "no " << kGoldenFile;
  const json golden = json::parse(file);
  const auto former = [](const std::string& scenario) {
    std::ifstream text(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + scenario + ".json");
    const json document = testing::with_former_keys(json::parse(text));
    EXPECT_FALSE(document.contains("routines")) << scenario;
    const scenario::LoadResult loaded = scenario::load_scenario(document, {{std::string(HRISIM_SOURCE_DIR) + "/scenarios"}, {}});
    EXPECT_FALSE(loaded.warnings.empty()) << scenario;
    return loaded;
  };
  for (const char* scenario : {"crossing_navigation", "elevator", "perpendicular_crossing", "queue"}) {
    EXPECT_EQ(hash_after_golden_ticks(former(scenario), 1), golden.value(std::string(scenario) + "/1", "")) << scenario;
  }
  EXPECT_EQ(hash_after_golden_ticks(former("elevator"), 1, {std::nullopt, {{2.0, "call_elevator_floor2"}}, false, {}}),
            golden.value("elevator/1 with call_elevator_floor2 asked at 2 s", ""));
}

TEST(StateHash, EveryMemberOfTheStateCounts) {
  // Members a hand-kept list once missed (goal, target_heading, hold), the events' content, the
  // planner's history, robots' sensor readings: each changes the hash.
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/elevator.json");
  ASSERT_TRUE(loaded.model);
  Session session(loaded.model, 1);
  for (int t = 0; t < 120; ++t) session.tick();
  const State& state = session.state();
  const std::uint64_t before = state_hash(state);
  const auto differs = [&](const char* what, const std::function<void(State&)>& change) {
    State changed = state;
    change(changed);
    EXPECT_NE(state_hash(changed), before) << what;
  };
  differs("goal", [](State& s) { s.agents[0].navigation.goal.x() += 1e-12; });
  differs("target_heading", [](State& s) { s.agents[0].attitude.target_heading = s.agents[0].attitude.target_heading.value_or(0.0) + 0.5; });
  differs("hold", [](State& s) { s.agents[0].navigation.hold = Vec2(1, 2); });
  differs("a body's planning clearance", [](State& s) { s.agents[0].navigation.fallback.body_clearance = kBodyHalfWidth; });
  differs("planned from a free cell", [](State& s) { s.agents[0].navigation.fallback.from_free_cell = true; });
  // A member of each group of an agent's state.
  differs("formation_offset", [](State& s) { s.agents[0].attitude.formation_offset.y() += 0.1; });
  differs("a reserved slot", [](State& s) { s.agents[0].reservation.slot = SlotIndex(s.agents[0].reservation.slot.value + 1); });
  differs("served", [](State& s) { s.agents[0].queueing.served = !s.agents[0].queueing.served; });
  differs("personal_space", [](State& s) { s.agents[0].reaction.personal_space -= 0.01; });
  differs("stay_until_tick", [](State& s) { s.agents[0].living.stay_until_tick += 1; });
  differs("step_phase", [](State& s) { s.agents[0].animation.step_phase += 0.1; });
  differs("seat_front", [](State& s) { s.agents[0].seating.front.x() += 0.1; });
  differs("reach phase", [](State& s) { s.agents[0].carrying.phase = ReachPhase::reaching; });
  differs("an event", [&](State& s) { emit(*loaded.model, s, "y", events::Entered{}); s.events.pop_back(); });
  const auto digest_after = [&](EventData data) {
    State changed = state;
    emit(*loaded.model, changed, "ana", std::move(data));
    return changed.events_digest;
  };
  EXPECT_NE(digest_after(events::Command{"walk 1 2"}), digest_after(events::Command{"walk 1 3"})) << "an event's text";
  EXPECT_NE(digest_after(events::Stuck{1, 2, 3, 4, 5, 6}), digest_after(events::Stuck{1, 2, 3, 4, 5, 6.5})) << "an event's number";
  EXPECT_NE(digest_after(events::PersonFound{"ada", std::nullopt, 1.0}), digest_after(events::PersonFound{"ada", "", 1.0}))
      << "in no room is not in a room named ''";
  EXPECT_NE(digest_after(events::AgentPlaced{1, 2, 3}), digest_after(events::ObjectPlaced{1, 2, 3})) << "two kinds of one name";
  differs("a laser reading", [](State& s) { s.robots.at(0).lasers.at(0).reading.ranges.at(0) += 1e-9; });
  differs("the time limit", [](State& s) { s.time_limit += 1.0; });
  EXPECT_EQ(state_hash(State(state)), before) << "a copy is the same state";
}

TEST(StateHash, TheBenchmarkTasksBookkeepingCounts) {
  // Two states alike but for the task's part differ: a checkpoint that lost the task's gap, random
  // stream or last reward would not pass for the episode it was taken of.
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/follow_human.json");
  ASSERT_TRUE(loaded.model);
  episode::Episode run(loaded.model, 1, {std::nullopt, {}, false, {}});
  run.step(std::vector<double>{0.2, 0.1}, 5);
  const State& state = run.session().state();
  ASSERT_TRUE(std::holds_alternative<NavigationTaskState>(state.task.kind_state));
  ASSERT_FALSE(state.task.last_reward_terms.empty());
  const std::uint64_t before = state_hash(state);
  const auto hash_with = [&](const std::function<void(State&)>& change) {
    State changed = state;
    change(changed);
    return state_hash(changed);
  };
  const auto navigation = [](State& s) -> NavigationTaskState& { return std::get<NavigationTaskState>(s.task.kind_state); };
  EXPECT_NE(hash_with([&](State& s) { navigation(s).gap += 1e-12; }), before) << "the gap";
  EXPECT_NE(hash_with([&](State& s) { navigation(s).random.next_u64(); }), before) << "the task's random stream";
  EXPECT_NE(hash_with([&](State& s) { navigation(s).walking_style += "!"; }), before) << "the walking style";
  EXPECT_NE(hash_with([](State& s) { s.task.touched_this_step.push_back("table"); }), before) << "touched during the step";
  EXPECT_NE(hash_with([](State& s) { s.task.touched_last_step.push_back("table"); }), before) << "touched during the last step";
  EXPECT_NE(hash_with([](State& s) { s.task.last_reward_terms.front().second += 1e-12; }), before) << "a reward term";
  EXPECT_NE(hash_with([](State& s) { s.task.last_reward_terms.front().first += "!"; }), before) << "a reward term's name";
  EXPECT_NE(hash_with([](State& s) { s.task.terminated = !s.task.terminated; }), before) << "the task's ending";
  // Another kind of task, or none: the variant's index counts, and so does every member of each kind.
  const std::uint64_t none = hash_with([](State& s) { s.task.kind_state = std::monostate{}; });
  const std::uint64_t pick = hash_with([](State& s) { s.task.kind_state = PickAndPlaceState{}; });
  EXPECT_NE(none, before);
  EXPECT_NE(pick, none) << "an empty alternative is not a default one";
  const auto pick_with = [&](const std::function<void(PickAndPlaceState&)>& change) {
    return hash_with([&](State& s) { change(s.task.kind_state.emplace<PickAndPlaceState>()); });
  };
  EXPECT_NE(pick_with([](PickAndPlaceState& p) { p.initial_height = 0.7; }), pick) << "initial_height";
  EXPECT_NE(pick_with([](PickAndPlaceState& p) { p.step_ticks = 8; }), pick) << "step_ticks";
  EXPECT_NE(pick_with([](PickAndPlaceState& p) { p.gripper_object_distance = 0.1; }), pick) << "gripper_object_distance";
  EXPECT_NE(pick_with([](PickAndPlaceState& p) { p.object_target_distance = 0.1; }), pick) << "object_target_distance";
  EXPECT_NE(pick_with([](PickAndPlaceState& p) { p.held = true; }), pick) << "held";
  const std::uint64_t mirror = hash_with([](State& s) { s.task.kind_state.emplace<MirrorGestureState>(); });
  EXPECT_NE(mirror, pick);
  EXPECT_NE(hash_with([](State& s) { s.task.kind_state.emplace<MirrorGestureState>().human_side = PointingSide::left; }), mirror) << "human_side";
  EXPECT_NE(hash_with([](State& s) { s.task.kind_state.emplace<MirrorGestureState>().robot_side = PointingSide::left; }), mirror) << "robot_side";
  EXPECT_NE(hash_with([](State& s) { s.task.kind_state.emplace<MirrorGestureState>().random.next_u64(); }), mirror) << "mirror's random";
}

}  // namespace
}  // namespace hrisim::sim
