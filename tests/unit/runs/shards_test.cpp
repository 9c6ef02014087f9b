#include "runs/shards.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "core/error.hpp"

namespace hrisim::runs {
namespace {

/// An environment of these variables only.
VariableReader with(std::map<std::string, std::string> variables) {
  return [variables = std::move(variables)](const char* name) -> std::optional<std::string> {
    const auto found = variables.find(name);
    return found == variables.end() ? std::nullopt : std::optional(found->second);
  };
}

std::string refusal(const std::string& text, const VariableReader& environment) {
  try {
    parse_shard(text, environment);
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::bad_request);
    return e.what();
  }
  ADD_FAILURE() << text << " was accepted";
  return "";
}

TEST(Shards, KOfNIsReadAndCheckedWithoutTheEnvironment) {
  const Shard shard = parse_shard("2/4", with({{"SLURM_ARRAY_TASK_ID", "0"}}));
  EXPECT_EQ(shard.index, 2);
  EXPECT_EQ(shard.count, 4);
  EXPECT_EQ(parse_shard("1/1", with({})).count, 1);
  EXPECT_NE(refusal("0/4", with({})).find("the shard must be 1 to 4, got 0"), std::string::npos);
  EXPECT_NE(refusal("5/4", with({})).find("the shard must be 1 to 4, got 5"), std::string::npos);
  EXPECT_NE(refusal("1/0", with({})).find("the count must be 1 to"), std::string::npos);
  EXPECT_NE(refusal("-1/4", with({})).find("the shard must be 1 to 4, got -1"), std::string::npos);
  for (const char* malformed : {"2", "2/", "/4", "a/b", "2/4/8", "2/4x"}) {
    EXPECT_NE(refusal(malformed, with({})).find("expected K/N"), std::string::npos) << malformed;
  }
}

TEST(Shards, AutoReadsEachSchedulersIndexAndCount) {
  // Slurm: --array=0-3 or --array=5-8 are both four tasks, the first being shard 1.
  EXPECT_EQ(parse_shard("auto", with({{"SLURM_ARRAY_TASK_ID", "2"}, {"SLURM_ARRAY_TASK_COUNT", "4"}, {"SLURM_ARRAY_TASK_MIN", "0"}})).index, 3);
  const Shard slurm = parse_shard("auto", with({{"SLURM_ARRAY_TASK_ID", "5"}, {"SLURM_ARRAY_TASK_COUNT", "4"}, {"SLURM_ARRAY_TASK_MIN", "5"}}));
  EXPECT_EQ(slurm.index, 1);
  EXPECT_EQ(slurm.count, 4);
  const Shard gitlab = parse_shard("auto", with({{"CI_NODE_INDEX", "3"}, {"CI_NODE_TOTAL", "3"}}));
  EXPECT_EQ(gitlab.index, 3);
  EXPECT_EQ(parse_shard("auto", with({{"CIRCLE_NODE_INDEX", "0"}, {"CIRCLE_NODE_TOTAL", "2"}})).index, 1);
  EXPECT_EQ(parse_shard("auto", with({{"BUILDKITE_PARALLEL_JOB", "1"}, {"BUILDKITE_PARALLEL_JOB_COUNT", "2"}})).index, 2);
  // Kubernetes' Indexed Job gives the index from 0; the count is the Job's completions, given.
  const Shard kubernetes = parse_shard("auto/8", with({{"JOB_COMPLETION_INDEX", "7"}}));
  EXPECT_EQ(kubernetes.index, 8);
  EXPECT_EQ(kubernetes.count, 8);
}

TEST(Shards, AutoSaysWhatIsMissingOrWrong) {
  EXPECT_NE(refusal("auto", with({})).find("auto found no scheduler's index"), std::string::npos);
  EXPECT_NE(refusal("auto", with({{"JOB_COMPLETION_INDEX", "1"}})).find("give it as auto/N"), std::string::npos);
  EXPECT_NE(refusal("auto/4", with({})).find("JOB_COMPLETION_INDEX, which is not set"), std::string::npos);
  EXPECT_NE(refusal("auto", with({{"SLURM_ARRAY_TASK_ID", "1"}})).find("SLURM_ARRAY_TASK_COUNT is not"), std::string::npos);
  EXPECT_NE(refusal("auto", with({{"SLURM_ARRAY_TASK_ID", "x"}, {"SLURM_ARRAY_TASK_COUNT", "4"}})).find("SLURM_ARRAY_TASK_ID is 'x'"),
            std::string::npos);
  EXPECT_NE(refusal("auto/4", with({{"JOB_COMPLETION_INDEX", "4"}})).find("the shard must be 1 to 4, got 5"), std::string::npos);
}

TEST(Shards, PartsAreDisjointCoverEverythingAndDifferInSizeByOneAtMost) {
  for (const std::size_t total : {0u, 1u, 7u, 1000u}) {
    for (const int count : {1, 3, 4, 9}) {
      std::set<std::size_t> seen;
      std::size_t smallest = total, largest = 0;
      for (int index = 1; index <= count; ++index) {
        const std::vector<std::size_t> part = shard_positions(total, {index, count});
        smallest = std::min(smallest, part.size());
        largest = std::max(largest, part.size());
        for (const std::size_t position : part) EXPECT_TRUE(seen.insert(position).second) << "position " << position << " twice";
      }
      EXPECT_EQ(seen.size(), total);
      EXPECT_LE(largest - smallest, 1u) << total << " in " << count;
    }
  }
  EXPECT_EQ(shard_positions(10, {2, 4}), (std::vector<std::size_t>{1, 5, 9}));
}

TEST(Shards, TheRunIdIsWhatTheRunIsOnEveryMachine) {
  const nlohmann::json identity = {{"scenario", "queue"}, {"seeds", {1, 2, 3}}, {"shards", 2}};
  const std::string id = shard_run_id(identity);
  EXPECT_EQ(id.size(), 33u);
  EXPECT_EQ(id.front(), 'r');
  EXPECT_EQ(shard_run_id(nlohmann::json::parse(identity.dump())), id);
  nlohmann::json other = identity;
  other["shards"] = 3;
  EXPECT_NE(shard_run_id(other), id);
}

}  // namespace
}  // namespace hrisim::runs
