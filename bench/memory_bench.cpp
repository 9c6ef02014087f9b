// Memory a session holds per tick as it runs: heap bytes in use (glibc's mallinfo2) after running a
// bundled scenario to its end, with its recording for the metrics and without, per tick and per hour
// of simulated time at the scenario's own time step (a realtime session's hour).
//   usage: memory_bench [path to the project's scenarios/=scenarios] [scenario…]
#include <malloc.h>

#include <cstdio>
#include <string>
#include <vector>

#include "episode/episode.hpp"
#include "scenario/load.hpp"

namespace {

std::size_t heap_in_use() { return mallinfo2().uordblks; }

/// Heap bytes gained per tick by an episode of the scenario run to its end, and its ticks.
std::pair<double, std::int64_t> bytes_per_tick(const std::shared_ptr<const hrisim::scenario::Model>& model, bool record) {
  hrisim::episode::Episode episode(model, 1, {std::nullopt, {}, record, {}});
  for (int i = 0; i < 10; ++i) episode.tick();  // past what the first ticks allocate once
  const std::size_t before = heap_in_use();
  const std::int64_t start = episode.session().state().tick;
  episode.run();
  const std::int64_t ticks = episode.session().state().tick - start;
  return {(static_cast<double>(heap_in_use()) - static_cast<double>(before)) / static_cast<double>(ticks), ticks};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string scenarios = argc > 1 ? argv[1] : "scenarios";
  std::vector<std::string> names;
  for (int i = 2; i < argc; ++i) names.emplace_back(argv[i]);
  if (names.empty()) names = {"elevator", "family_day", "crossing_navigation"};
  std::printf("memory_bench: heap bytes gained per tick, run to the scenario's end (seed 1)\n");
  std::printf("%-22s %8s %8s %14s %14s %16s\n", "scenario", "ticks", "dt (s)", "recording B", "without B", "recording MB/h");
  for (const std::string& name : names) {
    const auto loaded = hrisim::scenario::load_scenario_file(scenarios + "/" + name + ".json");
    if (!loaded.model) {
      std::fprintf(stderr, "%s does not load\n", name.c_str());
      return 1;
    }
    const auto [recorded, ticks] = bytes_per_tick(loaded.model, true);
    const double bare = bytes_per_tick(loaded.model, false).first;
    const double per_hour = recorded * 3600.0 / loaded.model->dt / 1e6;
    std::printf("%-22s %8lld %8.4f %14.1f %14.1f %16.1f\n", name.c_str(), static_cast<long long>(ticks), loaded.model->dt, recorded, bare,
                per_hour);
  }
  return 0;
}
