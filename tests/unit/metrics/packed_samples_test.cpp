// Packed samples: every value back bit for bit (NaN, infinities and −0 included), people coming,
// going and changing places, groups and touched obstacles; blocks of fixed size; kept until a tick;
// and compact.
#include "metrics/packed_samples.hpp"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>

namespace hrisim::metrics {
namespace {

std::uint64_t bits(double value) { return std::bit_cast<std::uint64_t>(value); }

void expect_same_body(const Body& a, const Body& b, const std::string& where) {
  EXPECT_EQ(a.agent, b.agent) << where;
  EXPECT_EQ(a.touching_robot, b.touching_robot) << where;
  EXPECT_EQ(bits(a.position.x()), bits(b.position.x())) << where;
  EXPECT_EQ(bits(a.position.y()), bits(b.position.y())) << where;
  EXPECT_EQ(bits(a.velocity.x()), bits(b.velocity.x())) << where;
  EXPECT_EQ(bits(a.velocity.y()), bits(b.velocity.y())) << where;
  EXPECT_EQ(bits(a.heading), bits(b.heading)) << where;
  EXPECT_EQ(bits(a.radius), bits(b.radius)) << where;
}

void expect_same(const std::vector<Sample>& packed, const std::vector<Sample>& original) {
  ASSERT_EQ(packed.size(), original.size());
  for (std::size_t s = 0; s < packed.size(); ++s) {
    const Sample &a = packed[s], &b = original[s];
    const std::string where = "sample " + std::to_string(s);
    EXPECT_EQ(a.tick, b.tick) << where;
    EXPECT_EQ(bits(a.reward), bits(b.reward)) << where;
    EXPECT_EQ(bits(a.obstacle_distance), bits(b.obstacle_distance)) << where;
    expect_same_body(a.robot, b.robot, where + " robot");
    ASSERT_EQ(a.humans.size(), b.humans.size()) << where;
    for (std::size_t h = 0; h < a.humans.size(); ++h) expect_same_body(a.humans[h], b.humans[h], where + " human " + std::to_string(h));
    EXPECT_EQ(a.touched_obstacles, b.touched_obstacles) << where;
    EXPECT_EQ(a.groups, b.groups) << where;
  }
}

Body walker(int agent, double t) {
  return {agent, {std::cos(0.3 * t + agent), 2.0 * agent + 0.01 * t}, {-0.3 * std::sin(0.3 * t + agent), 1.3}, 0.1 * t, 0.25, false};
}

TEST(PackedSamples, GiveBackEveryValueBitForBitAsPeopleComeGoAndChangePlaces) {
  std::vector<Sample> samples;
  const double odd[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), -0.0,
                        -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::denorm_min(), 1e300};
  for (int t = 0; t < 300; ++t) {
    Sample sample;
    sample.tick = 5 + 3 * t;  // not every tick recorded
    sample.reward = t % 7 == 0 ? odd[(t / 7) % 6] : 0.01 * t;
    sample.obstacle_distance = t % 11 == 0 ? odd[(t / 11) % 6] : 1.0 / (1 + t);
    sample.robot = walker(0, t);
    sample.robot.touching_robot = t % 5 == 0;
    // Agent 1 always; 2 leaves at 100; 3 comes at 50; from 200 the order turns round.
    for (const int agent : {1, 2, 3}) {
      if ((agent == 2 && t >= 100) || (agent == 3 && t < 50)) continue;
      Body body = walker(agent, t);
      if (agent == 1 && t > 120 && t < 140) body.velocity = {0.0, 0.0};  // standing still
      body.touching_robot = agent == 3 && t % 3 == 0;
      sample.humans.push_back(body);
    }
    if (t >= 200) std::reverse(sample.humans.begin(), sample.humans.end());
    if (t % 40 == 10) sample.touched_obstacles = {"map", "table – ⌀ 1.2 m"};
    if (t >= 60 && t < 90) sample.groups = {{0, 1}};
    if (t >= 90 && t < 95) sample.groups = {{1, 0}, {0}};
    samples.push_back(sample);
  }
  PackedSamples packed;
  for (const Sample& sample : samples) packed.append(sample);
  EXPECT_EQ(packed.size(), samples.size());
  EXPECT_EQ(packed.back().tick, samples.back().tick);
  expect_same(packed.unpack(), samples);
}

TEST(PackedSamples, ASampleLargerThanABlockGetsABlockOfItsOwnAndTheNextBlockFollows) {
  std::vector<Sample> samples;
  for (int t = 0; t < 3; ++t) {
    Sample sample;
    sample.tick = t;
    for (int agent = 1; agent <= 3000; ++agent) sample.humans.push_back(walker(agent, t));
    samples.push_back(sample);
  }
  PackedSamples packed;
  for (const Sample& sample : samples) packed.append(sample);
  EXPECT_GT(packed.bytes(), 3 * PackedSamples::kBlockBytes) << "3,000 people take more than a block a sample";
  expect_same(packed.unpack(), samples);
}

TEST(PackedSamples, KeptUntilATickTheyAreAsIfWhatFollowedHadNeverBeenAppended) {
  // A seek back: the samples after its tick go, and the new branch is appended after those kept.
  const auto sample_at = [](int t, int branch) {
    Sample sample;
    sample.tick = t;
    sample.robot = walker(0, t + branch);
    for (int agent = 1; agent <= 2000; ++agent) sample.humans.push_back(walker(agent, t * (branch + 1)));  // blocks fill
    if (t % 30 == 0) sample.groups = {{1, 2}};
    return sample;
  };
  PackedSamples packed;
  for (int t = 0; t < 200; ++t) packed.append(sample_at(t, 0));
  std::vector<Sample> expected;
  packed.keep_until(120, [&](const Sample& kept) { expected.push_back(kept); });
  ASSERT_EQ(expected.size(), 121u);
  EXPECT_EQ(packed.size(), 121u);
  EXPECT_EQ(packed.back().tick, 120);
  for (int t = 121; t < 160; ++t) {
    packed.append(sample_at(t, 1));
    expected.push_back(sample_at(t, 1));
  }
  std::vector<Sample> first_branch;
  for (int t = 0; t <= 120; ++t) first_branch.push_back(sample_at(t, 0));
  expect_same(std::vector<Sample>(expected.begin(), expected.begin() + 121), first_branch);
  expect_same(packed.unpack(), expected);
}

TEST(PackedSamples, WalkingPeopleTakeUnderHalfTheirUnpackedSizeAndStandingOnesAFewBytes) {
  PackedSamples walking, standing;
  constexpr int kTicks = 20000, kPeople = 6;
  for (int t = 0; t < kTicks; ++t) {
    Sample moving, still;
    moving.tick = still.tick = t;
    moving.robot = walker(0, t / 60.0);
    still.robot = walker(0, 0.0);
    for (int agent = 1; agent <= kPeople; ++agent) {
      moving.humans.push_back(walker(agent, t / 60.0));
      still.humans.push_back(walker(agent, 0.0));
    }
    walking.append(moving);
    standing.append(still);
  }
  const double unpacked = sizeof(Sample) + kPeople * sizeof(Body);
  EXPECT_LT(static_cast<double>(walking.bytes()) / kTicks, unpacked / 2) << walking.bytes() / kTicks << " B a sample";
  // Per body: its agent, a flag and three bytes of counts; each sample a few bytes more.
  EXPECT_LT(static_cast<double>(standing.bytes()) / kTicks, (kPeople + 1) * 5 + 12) << standing.bytes() / kTicks << " B a sample";
}

}  // namespace
}  // namespace hrisim::metrics
