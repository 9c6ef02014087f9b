#include "runs/shards.hpp"

#include <charconv>

#include "core/error.hpp"
#include "core/sha256.hpp"

namespace hrisim::runs {
namespace {

[[noreturn]] void refuse(const std::string& message) { throw core::Error(core::ErrorCode::bad_request, "--shard: " + message); }

std::optional<long long> whole(const std::string& text) {
  long long value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

Shard checked(long long index, long long count, const std::string& from) {
  if (count < 1 || count > kMaxShards) refuse(from + ": the count must be 1 to " + std::to_string(kMaxShards) + ", got " + std::to_string(count));
  if (index < 1 || index > count) refuse(from + ": the shard must be 1 to " + std::to_string(count) + ", got " + std::to_string(index));
  return {static_cast<int>(index), static_cast<int>(count)};
}

/// A scheduler's variable as a whole number; nullopt when it is not set.
std::optional<long long> variable(const VariableReader& environment, const char* name) {
  const auto text = environment(name);
  if (!text) return std::nullopt;
  const auto value = whole(*text);
  if (!value) refuse(std::string(name) + " is '" + *text + "', not a whole number");
  return value;
}

}  // namespace

Shard parse_shard(const std::string& text, const VariableReader& environment) {
  if (text == "auto") {
    if (const auto id = variable(environment, "SLURM_ARRAY_TASK_ID")) {
      const auto count = variable(environment, "SLURM_ARRAY_TASK_COUNT");
      if (!count) refuse("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not");
      return checked(*id - variable(environment, "SLURM_ARRAY_TASK_MIN").value_or(0) + 1, *count,
                     "Slurm's SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN + 1 of SLURM_ARRAY_TASK_COUNT");
    }
    struct Scheme {
      const char *index, *count;
      int offset;
      const char* what;
    };
    for (const Scheme& scheme : {Scheme{"CI_NODE_INDEX", "CI_NODE_TOTAL", 0, "GitLab's CI_NODE_INDEX of CI_NODE_TOTAL"},
                                 Scheme{"CIRCLE_NODE_INDEX", "CIRCLE_NODE_TOTAL", 1, "CircleCI's CIRCLE_NODE_INDEX + 1 of CIRCLE_NODE_TOTAL"},
                                 Scheme{"BUILDKITE_PARALLEL_JOB", "BUILDKITE_PARALLEL_JOB_COUNT", 1,
                                        "Buildkite's BUILDKITE_PARALLEL_JOB + 1 of BUILDKITE_PARALLEL_JOB_COUNT"}}) {
      if (const auto index = variable(environment, scheme.index)) {
        const auto count = variable(environment, scheme.count);
        if (!count) refuse(std::string(scheme.index) + " is set but " + scheme.count + " is not");
        return checked(*index + scheme.offset, *count, scheme.what);
      }
    }
    if (environment("JOB_COMPLETION_INDEX")) refuse("a Kubernetes Indexed Job gives no count: give it as auto/N (N: the Job's completions)");
    refuse("auto found no scheduler's index (SLURM_ARRAY_TASK_ID, CI_NODE_INDEX, CIRCLE_NODE_INDEX, BUILDKITE_PARALLEL_JOB, or "
           "JOB_COMPLETION_INDEX with auto/N): give K/N");
  }
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) refuse("expected K/N (e.g. 2/4), auto or auto/N, got '" + text + "'");
  const auto count = whole(text.substr(slash + 1));
  if (!count) refuse("expected K/N (e.g. 2/4), auto or auto/N, got '" + text + "'");
  if (text.substr(0, slash) == "auto") {
    const auto index = variable(environment, "JOB_COMPLETION_INDEX");
    if (!index) refuse("auto/N reads Kubernetes' JOB_COMPLETION_INDEX, which is not set");
    return checked(*index + 1, *count, "Kubernetes' JOB_COMPLETION_INDEX + 1 of " + std::to_string(*count));
  }
  const auto index = whole(text.substr(0, slash));
  if (!index) refuse("expected K/N (e.g. 2/4), auto or auto/N, got '" + text + "'");
  return checked(*index, *count, text);
}

std::vector<std::size_t> shard_positions(std::size_t total, const Shard& shard) {
  std::vector<std::size_t> positions;
  for (std::size_t i = static_cast<std::size_t>(shard.index - 1); i < total; i += static_cast<std::size_t>(shard.count)) positions.push_back(i);
  return positions;
}

std::string shard_run_id(const nlohmann::json& identity) { return "r" + core::sha256_hex(identity.dump()).substr(0, 32); }

}  // namespace hrisim::runs
