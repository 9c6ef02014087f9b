// Storage throughput: how fast complete episodes (metrics, events, trajectory) are committed and
// read back. Prints one line per figure; median of several repetitions.
//   usage: storage_bench [episodes=50] [agents=7] [samples_per_agent=600] [repetitions=5]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include "storage/store.hpp"

namespace {

using Clock = std::chrono::steady_clock;

hrisim::storage::EpisodeRecord make_episode(int index, int agents, int samples) {
  hrisim::storage::EpisodeRecord episode;
  episode.id = "episode-" + std::to_string(index);
  episode.scenario_id = "bench";
  episode.seed = static_cast<std::uint64_t>(index);
  episode.controller = "bench";
  episode.status = "succeeded";
  episode.termination_reason = "time_limit";
  episode.ticks = samples;
  episode.sim_time = samples / 10.0;
  for (int m = 0; m < 30; ++m) episode.metrics.push_back({"metric_" + std::to_string(m), m * 0.5, std::nullopt});
  for (int e = 0; e < 20; ++e) episode.events.push_back({e, e / 10.0, "step_boundary", "step", {{"step", e}}});
  for (int a = 0; a < agents; ++a) {
    for (int t = 0; t < samples; ++t) {
      episode.trajectory.push_back({"agent_" + std::to_string(a), t, 0.01 * t, 0.02 * a, 0.001 * t});
    }
  }
  return episode;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const int episodes = argc > 1 ? std::atoi(argv[1]) : 50;
  const int agents = argc > 2 ? std::atoi(argv[2]) : 7;
  const int samples = argc > 3 ? std::atoi(argv[3]) : 600;
  const int repetitions = argc > 4 ? std::atoi(argv[4]) : 5;
  const auto dir = std::filesystem::temp_directory_path() / ("hrisim-bench-" + std::to_string(::getpid()));

  std::vector<double> write_rates, read_rates;
  for (int r = 0; r < repetitions; ++r) {
    std::filesystem::remove_all(dir);
    hrisim::storage::Store store(dir / "bench.db");
    store.put_scenario({"bench", "bench", "json", "{}", "", "", "", "", {}});
    std::vector<hrisim::storage::EpisodeRecord> batch;
    for (int i = 0; i < episodes; ++i) batch.push_back(make_episode(i, agents, samples));

    auto start = Clock::now();
    for (const auto& episode : batch) store.write_episode(episode);
    write_rates.push_back(episodes / std::chrono::duration<double>(Clock::now() - start).count());

    start = Clock::now();
    for (const auto& episode : batch) {
      if (!store.episode(episode.id)) return 1;
    }
    read_rates.push_back(episodes / std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::filesystem::remove_all(dir);

  const double rows = agents * samples + 30 + 20;
  std::printf("storage_bench: %d episodes x (%d agents x %d samples + 30 metrics + 20 events), %d repetitions\n",
              episodes, agents, samples, repetitions);
  std::printf("write_episode: %.1f episodes/s (median), %.0f rows/s\n", median(write_rates), median(write_rates) * rows);
  std::printf("read episode:  %.1f episodes/s (median), %.0f rows/s\n", median(read_rates), median(read_rates) * rows);
  return 0;
}
