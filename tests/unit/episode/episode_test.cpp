// The episode loop: rewards summed term by term into the episode's metrics, env steps and ticks giving
// the same episode, and snapshots restored bit for bit on every bundled scenario, physics included.
#include "episode/episode.hpp"

#include <gtest/gtest.h>

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
  const auto drive = [](sim::Session& session) { session.command_robot_twist(session.agent_id("robot"), {0.2, 0.1}); };
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
      original.give([a, at = person.position, heading = person.heading](sim::Session& session) {
        session.place_agent(session.agent_at(static_cast<int>(a)), {at.x(), at.y(), heading + 0.5});
      });
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

}  // namespace
}  // namespace hrisim::episode
