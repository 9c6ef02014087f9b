// Crowd simulation speed: whole session steps per second (choreography, planning, locomotion) for
// 10, 100, 1000 (and 10,000) humans, in an open room and on IMHuS's elevator map, with ORCA and with
// the social force model. Prints one line per case: median of several repetitions, and the hash of
// the final state (equal in every repetition, checked, and on every machine).
//   usage: humans_bench [repetitions=3] [path to shared/ for the elevator map=../shared] [case filter,
//          e.g. "open_room social_force 1000"]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "scenario/load.hpp"
#include "sim/session.hpp"

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

/// People per square metre in the open room.
constexpr double kRoomDensity = 0.25;

/// Social-force neighbourhood of the extra "social_force_2m" cases, m (the default is 4 m).
constexpr double kShortNeighbourhood = 2.0;

/// An open square room sized for the crowd (kRoomDensity overall); two groups start in strips at
/// opposite ends and swap sides, walk back, and do it again.
json open_room(int humans, const std::string& avoidance, double neighbour_distance = 0.0) {
  const double side = std::max(30.0, std::ceil(std::sqrt(humans / kRoomDensity)));
  json scenario{{"name", "open_room"},
                {"time_limit", 3000},
                {"locomotion", {{"avoidance", avoidance}}},
                {"world",
                 {{"bounds", {{"min", {-1, -1}}, {"max", {side + 1, side + 1}}}},
                  {"resolution", side > 100 ? 0.2 : 0.1},
                  {"walls", json::array({{{"from", {0, 0}}, {"to", {side, 0}}},
                                         {{"from", {side, 0}}, {"to", {side, side}}},
                                         {{"from", {side, side}}, {"to", {0, side}}},
                                         {{"from", {0, side}}, {"to", {0, 0}}}})}}},
                {"humans", json::array()},
                {"steps", json::array()}};
  for (const char* leg : {"swap", "back", "swap_again", "back_again"}) scenario["steps"].push_back({{"name", leg}, {"actions", json::array()}});
  // Each group fills a strip a quarter of the room wide at its end, evenly spaced.
  // Goals keep 1.5 m from the walls, beyond the 1.35 m where pedsim's wall force balances the drive.
  const double spacing = std::min(0.8 * side, std::sqrt(side / 4.0 * side / std::ceil(humans / 2.0)));
  const int per_column = std::max(1, static_cast<int>((side - 3.0) / spacing));
  if (neighbour_distance > 0.0) scenario["locomotion"]["social_force"] = {{"neighbour_distance", neighbour_distance}};
  for (int i = 0; i < humans; ++i) {
    const bool left = i % 2 == 0;
    const int k = i / 2;
    const double x = left ? 1.5 + spacing * (k / per_column) : side - 1.5 - spacing * (k / per_column);
    const double y = 1.5 + spacing * (k % per_column);
    const std::string id = "h" + std::to_string(i);
    scenario["humans"].push_back({{"id", id}, {"start", {{"x", x}, {"y", y}}}});
    scenario["steps"][0]["actions"].push_back(
        {{"agent", id}, {"goto", {{"pose", {{"x", side - x}, {"y", y}}}, {"radius", 0.5}}}});
    scenario["steps"][1]["actions"].push_back({{"agent", id}, {"goto", {{"pose", {{"x", x}, {"y", y}}}, {"radius", 0.5}}}});
    scenario["steps"][2]["actions"].push_back(scenario["steps"][0]["actions"].back());
    scenario["steps"][3]["actions"].push_back(scenario["steps"][1]["actions"].back());
  }
  return scenario;
}

/// IMHuS's elevator map with humans at random free places walking to other random free places.
json elevator(int humans, const std::string& avoidance, const std::string& map, const hrisim::scenario::Model& empty,
              double neighbour_distance = 0.0) {
  json scenario{{"name", "elevator_crowd"},
                {"time_limit", 3000},
                {"locomotion", {{"avoidance", avoidance}}},
                {"world", {{"map", map}}},
                {"humans", json::array()},
                {"steps", json::array()}};
  if (neighbour_distance > 0.0) scenario["locomotion"]["social_force"] = {{"neighbour_distance", neighbour_distance}};
  hrisim::core::Random random(42);
  auto free_point = [&] {
    for (;;) {
      const double x = random.uniform(-10, 10), y = random.uniform(-10, 10);
      if (empty.field.distance(empty.grid, {x, y}) > 1.5) return std::pair{x, y};
    }
  };
  // Several legs between random free places, so no one is done before the measurement ends.
  constexpr int kLegs = 6;
  for (int leg = 0; leg < kLegs; ++leg) scenario["steps"].push_back({{"name", "leg" + std::to_string(leg)}, {"actions", json::array()}});
  for (int i = 0; i < humans; ++i) {
    const auto [x, y] = free_point();
    const std::string id = "h" + std::to_string(i);
    scenario["humans"].push_back({{"id", id}, {"start", {{"x", x}, {"y", y}}}});
    for (int leg = 0; leg < kLegs; ++leg) {
      const auto [gx, gy] = free_point();
      scenario["steps"][leg]["actions"].push_back({{"agent", id}, {"goto", {{"pose", {{"x", gx}, {"y", gy}}}, {"radius", 0.5}}}});
    }
  }
  return scenario;
}

struct Measurement {
  double steps_per_second;
  std::uint64_t final_hash;  ///< the same on every machine and in every repetition: determinism
};

Measurement measure_once(const std::shared_ptr<const hrisim::scenario::Model>& model, int steps, unsigned threads) {
  hrisim::sim::Session session(model, 1);
  session.set_crowd_threads(threads);
  for (int i = 0; i < 30; ++i) session.tick();  // first plans
  const auto start = Clock::now();
  for (int i = 0; i < steps; ++i) session.tick();
  if (session.state().finished) std::fprintf(stderr, "warning: the crowd finished its choreography during the measurement\n");
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return {steps / seconds, session.state_hash()};
}

/// Only cases whose "place avoidance humans" contains this run (all when empty).
std::string only;

/// The bench's own crowds and the user's map: up to 10,000 people, the map wherever it lies.
hrisim::scenario::LoadOptions bench_options() {
  hrisim::scenario::LoadOptions options;
  options.limits.max_people = 20000;
  options.limits.confine_files = false;
  return options;
}

void measure(const std::string& place, const std::string& avoidance, int humans, const json& document, int repetitions) {
  // A trailing space on both sides, so "1000" does not also select 10000.
  const std::string key = place + " " + avoidance + " " + std::to_string(humans) + " ";
  if (!only.empty() && key.find(only + " ") == std::string::npos) return;
  const auto loaded = hrisim::scenario::load_scenario(document, bench_options());
  if (!loaded.model) {
    std::fprintf(stderr, "invalid bench scenario: %s %s\n", loaded.errors[0].pointer.c_str(), loaded.errors[0].message.c_str());
    std::exit(1);
  }
  const int steps = std::clamp(200000 / humans, 60, 3000);
  std::uint64_t final_hash = 0;
  // Crowds of a thousand and more also on two threads, which must end in the one thread's state.
  for (const unsigned threads : humans >= 1000 ? std::vector<unsigned>{1, 2} : std::vector<unsigned>{1}) {
    std::vector<double> rates;
    for (int r = 0; r < repetitions; ++r) {
      const Measurement measurement = measure_once(loaded.model, steps, threads);
      if ((r > 0 || threads > 1) && measurement.final_hash != final_hash) {
        std::fprintf(stderr, "%s on %u threads: ended in a different state: not deterministic\n", key.c_str(), threads);
        std::exit(1);
      }
      final_hash = measurement.final_hash;
      rates.push_back(measurement.steps_per_second);
    }
    std::sort(rates.begin(), rates.end());
    const double median = rates[rates.size() / 2];
    std::printf("%-10s %-15s %6d humans, %u thread%s: %10.0f steps/s  %8.1fx real time  %6.2f M agent-steps/s  state %016llx\n",
                place.c_str(), avoidance.c_str(), humans, threads, threads > 1 ? "s" : " ", median, median * loaded.model->dt,
                median * humans / 1e6, static_cast<unsigned long long>(final_hash));
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::atoi(argv[1]) : 3;
  const std::string shared = argc > 2 ? argv[2] : "../shared";
  // Absolute: a scenario's relative map paths are looked up next to the scenario, not the working directory.
  const std::string map = std::filesystem::absolute(shared + "/external/imhus/elevator_map/elevator.yaml").string();
  if (argc > 3) only = argv[3];
  std::printf("humans_bench: dt = 1/60 s, median of %d repetitions\n", repetitions);
  for (const std::string avoidance : {"orca", "social_force"}) {
    for (int humans : {10, 100, 1000}) measure("open_room", avoidance, humans, open_room(humans, avoidance), repetitions);
  }
  measure("open_room", "social_force", 10000, open_room(10000, "social_force"), repetitions);
  for (int humans : {100, 1000, 10000}) {
    measure("open_room", "social_force_2m", humans, open_room(humans, "social_force", kShortNeighbourhood), repetitions);
  }
  const auto empty = hrisim::scenario::load_scenario(
      json{{"name", "map"}, {"world", {{"map", map}}}, {"steps", json::array()}}, bench_options());
  if (!empty.model) {
    std::printf("elevator map not loaded from %s (%s): skipping the elevator cases\n", map.c_str(),
                empty.errors.front().message.c_str());
    return 0;
  }
  for (const std::string avoidance : {"orca", "social_force"}) {
    for (int humans : {10, 100, 1000}) {
      measure("elevator", avoidance, humans, elevator(humans, avoidance, map, *empty.model), repetitions);
    }
  }
  // The crush (2.7 people/m²) with the neighbourhood cut to 2 m: about three rings of neighbours.
  measure("elevator", "social_force_2m", 1000, elevator(1000, "social_force", map, *empty.model, kShortNeighbourhood), repetitions);
  return 0;
}
