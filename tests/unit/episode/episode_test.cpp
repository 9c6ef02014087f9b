// The episode loop: rewards summed term by term into the episode's metrics, env steps and ticks giving
// the same episode, and snapshots restored bit for bit on every bundled scenario, physics included.
#include "episode/episode.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "metrics/episode_metrics.hpp"
#include "scenario/load.hpp"

namespace hrisim::episode {
namespace {

std::shared_ptr<const scenario::Model> bundled(const std::string& name) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + name + ".json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << name << ": " << e.pointer << ": " << e.message;
  return loaded.model;
}

std::optional<double> metric(const std::vector<metrics::MetricValue>& values, const std::string& key) {
  for (const metrics::MetricValue& value : values) {
    if (value.key == key) return value.value;
  }
  ADD_FAILURE() << "no metric " << key;
  return std::nullopt;
}

TEST(Episode, RewardsAreSummedIntoTheEpisodesMetricsTermByTerm) {
  Episode run(bundled("approach_human"), 5);
  double sum = 0.0;
  for (int step = 0; step < 40 && !run.over(); ++step) sum += run.step(std::vector<double>{0.3, 0.1});
  EXPECT_EQ(run.env_steps(), 40);
  EXPECT_DOUBLE_EQ(run.total_reward(), sum);
  const auto values = metrics::compute_episode_metrics(run.recording("running"));
  EXPECT_DOUBLE_EQ(*metric(values, "episode_reward"), sum);
  const double terms = *metric(values, "reward_distance") + *metric(values, "reward_collision_human") + *metric(values, "reward_collision_obstacle");
  EXPECT_NEAR(terms, sum, 1e-12);
  EXPECT_FALSE(metric(values, "reward_lifting")) << "approach_human's reward has no lifting term";
  // The series holds the rewards summed so far, its last value the episode's.
  const auto series = metrics::compute_series(run.recording("running"));
  const auto reward = std::find_if(series.begin(), series.end(), [](const metrics::Series& s) { return s.name == "episode_reward"; });
  ASSERT_NE(reward, series.end());
  EXPECT_DOUBLE_EQ(*reward->values.back(), sum);
}

TEST(Episode, AScenarioWithoutABenchmarkTaskHasNoReward) {
  Episode run(bundled("queue"), 1);
  run.step(std::nullopt, 100);
  const auto values = metrics::compute_episode_metrics(run.recording("running"));
  EXPECT_FALSE(metric(values, "episode_reward"));
  EXPECT_FALSE(metric(values, "reward_distance"));
}

TEST(Episode, EnvStepsAndClockTicksGiveTheSameEpisode) {
  // follow_human: a step is 10 ticks, and the person gets her next leg at the start of a step.
  const auto model = bundled("follow_human");
  Episode stepped(model, 6), ticked(model, 6);
  stepped.step(std::nullopt, 150);
  for (int t = 0; t < 1500; ++t) ticked.tick();
  EXPECT_EQ(stepped.session().state().tick, ticked.session().state().tick);
  EXPECT_EQ(stepped.session().state_hash(), ticked.session().state_hash());
  EXPECT_EQ(stepped.total_reward(), ticked.total_reward());
}

TEST(Episode, ABadActionChangesNothing) {
  Episode run(bundled("approach_human"), 1);
  const std::uint64_t before = run.session().state_hash();
  EXPECT_THROW(run.step(std::vector<double>{0.1}), core::Error);
  EXPECT_THROW(run.step(std::vector<double>{0.1, std::nan("")}), core::Error);
  EXPECT_EQ(run.session().state_hash(), before);
  EXPECT_EQ(run.snapshot().log.size(), 0u) << "nothing was kept in the input log";
}

TEST(Episode, RewindingGivesTheStateOfThatTickWithItsInputs) {
  // The elevator with the HSR: ticks, a velocity command at tick 120, more ticks.
  const auto model = bundled("elevator");
  Episode original(model, 3);
  std::vector<std::uint64_t> hashes;  // at each tick
  const Input drive = inputs::RobotTwist{model->find_agent("robot"), {0.2, 0.1}};
  for (int t = 0; t < 240; ++t) {
    if (t == 120) original.give(drive);
    hashes.push_back(original.session().state_hash());
    original.tick();
  }
  for (const std::int64_t tick : {0, 60, 119, 120, 121, 200}) {
    const std::unique_ptr<Episode> rewound = original.rewind(tick);
    EXPECT_EQ(rewound->session().state().tick, tick);
    EXPECT_EQ(rewound->session().state_hash(), hashes[static_cast<std::size_t>(tick)]) << "tick " << tick;
  }
  // The rewound episode goes on as the original did.
  const std::unique_ptr<Episode> rewound = original.rewind(100);
  for (int t = 100; t < 240; ++t) {
    if (t == 120) rewound->give(drive);
    rewound->tick();
  }
  EXPECT_EQ(rewound->session().state_hash(), original.session().state_hash());
}

TEST(Episode, RewindingATaskStopsAtTheEndOfTheEnvStepThatReachesTheTick) {
  // follow_human: a step is 10 ticks.
  const auto model = bundled("follow_human");
  Episode original(model, 6);
  original.step(std::vector<double>{0.2, 0.0}, 3);
  original.step(std::vector<double>{0.1, 0.3}, 4);
  Episode expected(model, 6);
  expected.step(std::vector<double>{0.2, 0.0}, 3);
  expected.step(std::vector<double>{0.1, 0.3}, 2);
  const std::unique_ptr<Episode> rewound = original.rewind(45);
  EXPECT_EQ(rewound->session().state().tick, 50);
  EXPECT_EQ(rewound->session().state_hash(), expected.session().state_hash());
  EXPECT_EQ(rewound->total_reward(), expected.total_reward());
}

class Snapshots : public ::testing::TestWithParam<std::string> {};

TEST_P(Snapshots, RestoringThenSteppingIsBitIdenticalToSteppingTheOriginal) {
  const auto model = bundled(GetParam());
  ASSERT_TRUE(model);
  for (const std::uint64_t seed : {1u, 2u}) {
    Episode original(model, seed);
    for (int t = 0; t < 200; ++t) original.tick();
    // An input from outside, kept in the log: a person placed elsewhere, when there is one to place.
    for (std::size_t a = 0; a < model->agents.size(); ++a) {
      if (model->agents[a].kind != scenario::AgentKind::human) continue;
      const sim::AgentState& person = original.session().state().agents[a];
      original.give(inputs::PlaceAgent{static_cast<int>(a), {person.position.x(), person.position.y(), person.heading + 0.5}});
      break;
    }
    if (original.environment()) original.step(std::nullopt, 3);
    const Episode::Snapshot snapshot = original.snapshot();
    for (int t = 0; t < 300; ++t) original.tick();

    const std::unique_ptr<Episode> restored = original.restore(snapshot);
    EXPECT_EQ(restored->session().state().tick, snapshot.tick);
    EXPECT_EQ(restored->session().state_hash(), snapshot.state_hash);
    for (int t = 0; t < 300; ++t) restored->tick();
    EXPECT_EQ(restored->session().state_hash(), original.session().state_hash()) << GetParam() << " seed " << seed;
    EXPECT_EQ(restored->session().state().events.size(), original.session().state().events.size());
  }
}

INSTANTIATE_TEST_SUITE_P(Bundled, Snapshots,
                         ::testing::Values("apartment", "approach_human", "approach_human_apartment", "conversation_group", "corridor_passing",
                                           "elevator", "follow_human", "mirror_gesture", "pair_walking", "perpendicular_crossing",
                                           "pick_and_place", "queue"));

TEST(Snapshots, StepsWithoutANewActionJoinTheLastRunAndEveryEntryKeepsItsTick) {
  const auto model = bundled("elevator");
  Episode original(model, 5);
  original.step(std::vector<double>{0.2, 0.1});
  for (int i = 0; i < 50; ++i) original.step();  // a client stepping one at a time, as the browser does
  original.give(inputs::RobotTwist{model->find_agent("robot"), {0.1, -0.2}});
  for (int i = 0; i < 10; ++i) original.step();
  original.step(std::vector<double>{0.0, 0.3}, 5);
  const Episode::Snapshot snapshot = original.snapshot();
  ASSERT_EQ(snapshot.log.size(), 4u) << "a run of steps, the command, a run of steps, the run with a new action";
  EXPECT_EQ(snapshot.log[0].count, 51);
  EXPECT_EQ(snapshot.log[1].tick, 51);
  EXPECT_EQ(snapshot.log[2].tick, 51);
  EXPECT_EQ(snapshot.log[3].tick, 61);
  EXPECT_EQ(original.restore(snapshot)->session().state_hash(), snapshot.state_hash);

  // A log that says an input came at another tick is refused there: as the snapshot's own, the
  // simulation was not deterministic (internal); as a file from elsewhere, the file is the suspect.
  Episode::Snapshot moved = snapshot;
  moved.log[1].tick = 50;
  try {
    original.restore(moved, true);
    ADD_FAILURE() << "restored a log with a moved input";
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::conflict);
    EXPECT_EQ(e.details().value("input", -1), 1);
  }
  EXPECT_THROW(original.restore(moved), core::Error);

  // A file may ask for more ticks than the episode has: they end at its end, not after 2^63 turns.
  Episode::Snapshot endless = snapshot;
  endless.log.push_back({Episode::Snapshot::Entry::Kind::ticks, snapshot.tick, std::nullopt, std::nullopt, std::numeric_limits<std::int64_t>::max()});
  EXPECT_THROW(original.restore(endless, true), core::Error) << "the end's state is not the snapshot's";
}

/// A bundled scenario kept going for `seconds` (at 60 Hz): its first person waits that long at the end,
/// and its time limit (a task's episode length) is that long, so that a seek can be tried deep into an
/// episode.
std::shared_ptr<const scenario::Model> kept_going(const std::string& name, double seconds) {
  std::ifstream file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + name + ".json");
  nlohmann::json document = nlohmann::json::parse(file);
  if (document.contains("task")) {
    document["task"]["max_episode_length"] = static_cast<int>(seconds * 60);  // a task's episode ends by its length
  } else {
    document["time_limit"] = seconds;
    const std::string person = document["humans"][0]["id"];
    document["steps"].push_back({{"name", "linger"}, {"actions", nlohmann::json::array({{{"agent", person}, {"wait", {{"duration", seconds}}}}})}});
  }
  const auto loaded = scenario::load_scenario(document, {{std::string(HRISIM_SOURCE_DIR) + "/scenarios"}, {}});
  for (const auto& e : loaded.errors) ADD_FAILURE() << name << ": " << e.pointer << ": " << e.message;
  return loaded.model;
}

/// A live session's settings: recorded, with checkpoints every `every` simulated seconds.
Settings with_checkpoints(double every, std::size_t max_bytes = kMaxCheckpointBytes) {
  Settings settings;
  settings.checkpoints = {every, max_bytes, nullptr};
  return settings;
}

/// The ticks a seek one tick back at tick 20,000 of bundled scenario `name` (kept going, with a live
/// session's checkpoints) simulates again; it must land on the state the episode had there.
std::int64_t ticks_again_one_tick_back_at_20000(const std::string& name) {
  const auto model = kept_going(name, 400.0);
  Episode original(model, 1, with_checkpoints(kCheckpointInterval));
  original.step(std::nullopt, 19'999);
  const std::uint64_t at_19999 = original.session().state_hash();
  original.step(std::nullopt, 1);
  EXPECT_EQ(original.session().state().tick, 20'000) << name;
  EXPECT_GT(original.checkpoints(), 0u) << name;
  const std::unique_ptr<Episode> back = original.rewind(19'999);
  EXPECT_EQ(back->session().state().tick, 19'999) << name;
  EXPECT_EQ(back->session().state_hash(), at_19999) << name;
  return back->ticks_simulated_again();
}

TEST(Seek, OneTickBackAtTick20000CostsABoundedStretch) {
  // From the checkpoint before it: at most an interval, and a little more where Bullet's cached
  // contacts put one off (not from tick 0, as before checkpoints).
  const std::int64_t interval = std::llround(kCheckpointInterval / scenario::kDefaultDt);  // the elevator's dt
  EXPECT_LE(ticks_again_one_tick_back_at_20000("elevator"), 2 * interval);
}

TEST(Seek, OneTickBackWithMovableObjectsCostsAtMostTheRebuildInterval) {
  // tea_break's cups are carried and put down; before the world was built again from the state at
  // fixed ticks, a world with objects was never copied and a seek re-simulated from tick 0.
  EXPECT_LE(ticks_again_one_tick_back_at_20000("tea_break"), std::llround(sim::kPhysicsRebuildInterval / scenario::kDefaultDt));
}

TEST(Snapshots, OneOfTheEpisodesOwnPastComesBackFromTheCheckpointBeforeIt) {
  // Before checkpoints served restores, a snapshot at tick 20,000 was simulated again from tick 0.
  const auto model = kept_going("elevator", 400.0);
  Episode original(model, 1, with_checkpoints(kCheckpointInterval));
  original.step(std::nullopt, 19'000);
  original.give(inputs::RobotTwist{model->find_agent("robot"), {0.1, 0.2}});
  original.step(std::nullopt, 1'000);
  const Episode::Snapshot snapshot = original.snapshot();
  original.step(std::nullopt, 700);
  const std::uint64_t later = original.session().state_hash();

  std::unique_ptr<Episode> back = original.restore(snapshot);
  EXPECT_EQ(back->session().state_hash(), snapshot.state_hash);
  const std::int64_t interval = std::llround(kCheckpointInterval / scenario::kDefaultDt);
  EXPECT_GT(back->ticks_simulated_again(), 0) << "from a checkpoint";
  EXPECT_LE(back->ticks_simulated_again(), interval);
  back->step(std::nullopt, 700);
  EXPECT_EQ(back->session().state_hash(), later) << "and goes on as the original did";

  // Back before the snapshot and on with another input: the snapshot is of another branch now, and is
  // simulated again from its log, as exactly.
  std::unique_ptr<Episode> branch = back->rewind(18'000);
  branch->give(inputs::RobotTwist{model->find_agent("robot"), {-0.1, 0.0}});
  branch->step(std::nullopt, 100);
  std::unique_ptr<Episode> again = branch->restore(snapshot);
  EXPECT_EQ(again->session().state_hash(), snapshot.state_hash);
  EXPECT_EQ(again->ticks_simulated_again(), 0) << "a fresh episode by the log, not a rewind";
}

/// Every tick's state hash along an episode driven by clock ticks with an input at tick 250 (the first person
/// placed), so that a seek goes back across an input.
struct Path {
  std::vector<std::uint64_t> hashes;  ///< at each tick, before it
  static void drive(Episode& episode, std::int64_t from, std::int64_t to, Path* path = nullptr) {
    const sim::Session& session = episode.session();
    for (std::int64_t t = from; t < to && !episode.over(); ++t) {
      if (t == 250 && t > from) {  // a rewind to tick 250 has it already
        const sim::AgentState& person = session.state().agents[first_person(session.model())];
        episode.give(inputs::PlaceAgent{first_person(session.model()), {person.position.x(), person.position.y(), person.heading + 0.5}});
      }
      if (path) path->hashes.push_back(session.state_hash());
      episode.tick();
    }
  }
  static int first_person(const scenario::Model& model) {
    for (std::size_t a = 0; a < model.agents.size(); ++a) {
      if (model.agents[a].kind == scenario::AgentKind::human) return static_cast<int>(a);
    }
    return -1;
  }
};

class Checkpoints : public ::testing::TestWithParam<std::string> {};

TEST_P(Checkpoints, SeekingBackAndForthIsBitIdenticalToTheOriginalPass) {
  const auto model = kept_going(GetParam(), 60.0);
  ASSERT_TRUE(model);
  ASSERT_GE(Path::first_person(*model), 0);
  const std::int64_t end = 1'600;  // hashes up to it; seeks go back to tick 1,400 at most
  Path path;
  Episode original(model, 2, with_checkpoints(1.0));
  Path::drive(original, 0, end, &path);
  ASSERT_EQ(original.session().state().tick, end) << "the scenario ended early";
  // Asked for one a second; a session with a physics world is copied only where the world was built
  // again from the state (every sim::kPhysicsRebuildInterval), as only there a copy is exact.
  const auto rebuilds = static_cast<std::size_t>(end / std::llround(sim::kPhysicsRebuildInterval / model->dt));
  EXPECT_GE(original.checkpoints(), rebuilds) << GetParam() << ": at least each rebuild's (one a second without a physics world)";
  // Taking checkpoints changes nothing: a pass without them is the same.
  Episode plain(model, 2);
  Path::drive(plain, 0, end);
  EXPECT_EQ(plain.session().state_hash(), original.session().state_hash());

  std::unique_ptr<Episode> now = original.rewind(end);
  EXPECT_EQ(now->session().state_hash(), original.session().state_hash());
  for (const std::int64_t tick : {1'400, 1'399, 900, 333, 250, 61, 0}) {
    now = now->rewind(tick);
    EXPECT_EQ(now->session().state().tick, tick);
    EXPECT_EQ(now->session().state_hash(), path.hashes[static_cast<std::size_t>(tick)]) << GetParam() << " back to tick " << tick;
    // Forth again, with the same inputs: the original pass, and its recording.
    Episode fresh(model, 2);
    Path::drive(fresh, 0, tick + 100);
    Path::drive(*now, tick, tick + 100);
    EXPECT_EQ(now->session().state_hash(), path.hashes[static_cast<std::size_t>(tick + 100)]) << GetParam() << " forth from tick " << tick;
    EXPECT_EQ(now->recording("running").samples.size(), fresh.recording("running").samples.size());
    EXPECT_EQ(now->session().state().events.size(), fresh.session().state().events.size());
  }
  if (original.checkpoints() > 0) {
    EXPECT_LT(original.rewind(1'399)->ticks_simulated_again(), 1'399) << "a seek back starts from a checkpoint";
  }
}

TEST_P(Checkpoints, ASeekAfterARestoreEqualsAFreshRun) {
  const auto model = kept_going(GetParam(), 60.0);
  ASSERT_TRUE(model);
  Path path;
  Episode original(model, 3, with_checkpoints(1.0));
  Path::drive(original, 0, 500, &path);
  const Episode::Snapshot snapshot = original.snapshot();
  Path::drive(original, 500, 1'200, &path);
  // A seek back, then playing on for longer than a checkpoint interval: the original pass again. Bullet's
  // world copied at any tick but a rebuild's once went apart 695 ticks after its checkpoint.
  const std::unique_ptr<Episode> seek = original.rewind(500);
  Path played;
  Path::drive(*seek, 500, 1'200, &played);
  ASSERT_EQ(played.hashes.size(), 700u);
  for (std::size_t i = 0; i < played.hashes.size(); ++i) {
    ASSERT_EQ(played.hashes[i], path.hashes[500 + i]) << GetParam() << ": played on from a seek back, tick " << 500 + i;
  }
  std::unique_ptr<Episode> restored = original.restore(snapshot);
  Path::drive(*restored, 500, 1'200);
  EXPECT_EQ(restored->session().state_hash(), original.session().state_hash());
  const std::unique_ptr<Episode> back = restored->rewind(800);
  EXPECT_EQ(back->session().state_hash(), path.hashes[800]) << GetParam();
  if (original.checkpoints() > 0) {
    EXPECT_LT(back->ticks_simulated_again(), 800) << "the restored episode took checkpoints of its own";
  }
}

INSTANTIATE_TEST_SUITE_P(Bundled, Checkpoints,
                         ::testing::Values("elevator", "queue", "apartment", "corridor_passing", "conversation_group", "follow_human",
                                           "approach_human", "pair_walking", "tea_break"));

TEST(Checkpoints, OverTheirBudgetEveryOtherGoesAndSeeksStayExact) {
  const auto model = kept_going("queue", 120.0);
  Episode probe(model, 1, with_checkpoints(1.0));
  probe.step(std::nullopt, 60);
  ASSERT_EQ(probe.checkpoints(), 1u);
  const std::size_t one = probe.checkpoint_bytes();

  Path path;
  Episode original(model, 1, with_checkpoints(1.0, 6 * one));
  Path::drive(original, 0, 3'000, &path);
  EXPECT_LE(original.checkpoint_bytes(), 6 * one);
  EXPECT_GE(original.checkpoints(), 2u);
  EXPECT_LE(original.checkpoints(), 6u);
  const std::unique_ptr<Episode> back = original.rewind(2'999);
  EXPECT_EQ(back->session().state_hash(), path.hashes[2'999]);
  // 50 intervals in 6 places: thinned to every 16th at most, so at most 16 intervals to simulate again.
  EXPECT_LE(back->ticks_simulated_again(), 16 * 60);
}

/// Each env step's reward and Gymnasium info along an episode.
struct Outcomes {
  std::vector<double> rewards;
  std::vector<nlohmann::json> infos;
  void step(Episode& episode, const std::optional<std::vector<double>>& action) {
    rewards.push_back(episode.step(action));
    infos.push_back(episode.environment()->info(episode.session()));
  }
};

TEST(Checkpoints, ATaskGoesOnFromOneWithTheOriginalsRewardsAndInfo) {
  // follow_human: the walking style and the person's legs come from the task's random stream, and each
  // step's distance reward from the gap after the last one — the task's state, which the checkpoint
  // (a copy of the session) carries, while the task itself is shared.
  const auto model = kept_going("follow_human", 60.0);
  const auto action = [](int step) { return std::vector<double>{0.2 * std::sin(0.1 * step), 0.3 * std::cos(0.07 * step)}; };
  Episode original(model, 4, with_checkpoints(1.0));
  Outcomes outcomes;
  for (int step = 0; step < 180; ++step) outcomes.step(original, action(step));
  ASSERT_FALSE(original.over());
  // Tick 600 ends the 60th env step, and the physics world was built again from the state there: a
  // checkpoint's own tick, reached without simulating again.
  const std::unique_ptr<Episode> back = original.rewind(600);
  ASSERT_EQ(back->session().state().tick, 600);
  EXPECT_EQ(back->ticks_simulated_again(), 0) << "the checkpoint's state alone";
  EXPECT_EQ(back->environment()->task(), original.environment()->task()) << "one task, shared";
  EXPECT_EQ(back->environment()->info(back->session()), outcomes.infos[59]) << "the last step's measures, walking style included";
  Outcomes again;
  for (int step = 60; step < 180; ++step) again.step(*back, action(step));
  for (std::size_t i = 0; i < again.rewards.size(); ++i) {
    EXPECT_EQ(again.rewards[i], outcomes.rewards[60 + i]) << "step " << 60 + i;
    EXPECT_EQ(again.infos[i], outcomes.infos[60 + i]) << "step " << 60 + i;
  }
  EXPECT_EQ(back->session().state_hash(), original.session().state_hash());
}

TEST(Checkpoints, APickAndPlaceStepWithoutAnActionLastsAsLongAsTheLastOneBeforeTheCheckpoint) {
  // The last step's length (8 ticks for the gripper, 120 for the arm) is the task's state: after 4 arm
  // steps and 15 gripper steps (tick 600, where the world is built again and a checkpoint taken), a
  // step without an action lasts 8 ticks, in the original and from the checkpoint alike.
  const auto model = kept_going("pick_and_place", 20.0);
  const std::vector<double> arm = {-1, 0, 0.1, -0.2, 0, -0.5, 0, 0};
  const std::vector<double> gripper = {1, 1, 0, 0, 0, 0, 0, 0};
  Episode original(model, 2, with_checkpoints(1.0));
  Outcomes outcomes;
  for (int step = 0; step < 4; ++step) outcomes.step(original, arm);
  for (int step = 0; step < 15; ++step) outcomes.step(original, gripper);
  ASSERT_EQ(original.session().state().tick, 600);
  ASSERT_GE(original.checkpoints(), 1u);
  for (int step = 0; step < 3; ++step) outcomes.step(original, std::nullopt);
  EXPECT_EQ(original.session().state().tick, 624) << "three steps of 8 ticks";

  const std::unique_ptr<Episode> back = original.rewind(600);
  EXPECT_EQ(back->ticks_simulated_again(), 0) << "the checkpoint's state alone";
  EXPECT_EQ(back->environment()->step_ticks(back->session()), 8);
  Outcomes again;
  for (int step = 0; step < 3; ++step) again.step(*back, std::nullopt);
  EXPECT_EQ(back->session().state().tick, 624);
  EXPECT_EQ(again.rewards, std::vector<double>(outcomes.rewards.end() - 3, outcomes.rewards.end()));
  EXPECT_EQ(again.infos, std::vector<nlohmann::json>(outcomes.infos.end() - 3, outcomes.infos.end()));
  EXPECT_EQ(back->session().state_hash(), original.session().state_hash());
}

}  // namespace
}  // namespace hrisim::episode
