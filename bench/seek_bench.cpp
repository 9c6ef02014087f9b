// Seeking back: the CPU time of a seek one tick back at a given tick, on a bundled scenario (the
// elevator by default; tea_break has movable objects) kept going (a last step in which its first
// person waits, a time limit past the tick), as a live session runs it (recorded, with checkpoints
// every kCheckpointInterval). Prints the median of several repetitions and the ticks simulated again.
//   usage: seek_bench [repetitions=5] [path to the project's scenarios/=scenarios] [tick=100000] [scenario=elevator]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <malloc.h>
#include <fstream>
#include <string>
#include <vector>

#include "episode/episode.hpp"
#include "scenario/load.hpp"

namespace {

using nlohmann::json;

double cpu_seconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

/// Bytes allocated on the heap now (glibc).
std::size_t heap_bytes() { return mallinfo2().uordblks; }

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::atoi(argv[1]) : 5;
  const std::string scenarios = argc > 2 ? argv[2] : "scenarios";
  const std::int64_t tick = argc > 3 ? std::atoll(argv[3]) : 100'000;
  const std::string name = argc > 4 ? argv[4] : "elevator";
  std::ifstream file(scenarios + "/" + name + ".json");
  if (!file) {
    std::fprintf(stderr, "no %s/%s.json\n", scenarios.c_str(), name.c_str());
    return 1;
  }
  json document = json::parse(file);
  const double seconds = static_cast<double>(tick) / 60.0 + 60.0;
  document["time_limit"] = seconds;
  const json person = document["humans"][0]["id"];
  document["steps"].push_back({{"name", "linger"}, {"actions", json::array({{{"agent", person}, {"wait", {{"duration", seconds}}}}})}});
  const auto loaded = hrisim::scenario::load_scenario(document, {{scenarios}, {}});
  if (!loaded.model) {
    std::fprintf(stderr, "invalid scenario: %s %s\n", loaded.errors[0].pointer.c_str(), loaded.errors[0].message.c_str());
    return 1;
  }
  // A live session's settings: recorded, with checkpoints.
  hrisim::episode::Settings settings;
  settings.checkpoints.every = hrisim::episode::kCheckpointInterval;
  const std::size_t heap_before = heap_bytes();
  auto episode = std::make_unique<hrisim::episode::Episode>(loaded.model, 1, settings);
  const double start = cpu_seconds();
  episode->step(std::nullopt, tick);
  const double forward = cpu_seconds() - start;
  // The checkpoints' heap: an episode with them less one without.
  const std::size_t heap_with = heap_bytes() - heap_before;
  std::size_t heap_without = 0;
  {
    hrisim::episode::Episode plain(loaded.model, 1);
    plain.step(std::nullopt, tick);
    heap_without = heap_bytes() - heap_before - heap_with;
  }
  if (episode->session().state().tick != tick) {
    std::fprintf(stderr, "the episode ended at tick %lld\n", static_cast<long long>(episode->session().state().tick));
    return 1;
  }
  std::vector<double> costs;
  std::int64_t simulated_again = 0;
  for (int r = 0; r < repetitions; ++r) {
    const double before = cpu_seconds();
    std::unique_ptr<hrisim::episode::Episode> back = episode->rewind(tick - 1);
    costs.push_back(cpu_seconds() - before);
    simulated_again = back->ticks_simulated_again();
  }
  std::sort(costs.begin(), costs.end());
  std::printf("seek_bench: %s kept going, stepped to tick %lld in %.2f s CPU, %zu checkpoints (estimated %zu KiB, on the heap %lld KiB)\n",
              name.c_str(), static_cast<long long>(tick), forward, episode->checkpoints(), episode->checkpoint_bytes() / 1024,
              (static_cast<long long>(heap_with) - static_cast<long long>(heap_without)) / 1024);
  std::printf("seek one tick back (to %lld): median %.4f s CPU of %d, %lld ticks simulated again\n", static_cast<long long>(tick - 1),
              costs[costs.size() / 2], repetitions, static_cast<long long>(simulated_again));
  return 0;
}
