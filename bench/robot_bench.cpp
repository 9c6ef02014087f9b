// Whole-session speed with a robot: the bundled elevator scenario (six people, an HSR with its 40 Hz
// 1081-beam base laser, a 10 Hz people detector, odometry and bumper, driven by the built-in path
// follower) from start to its last step, and the same without the people detector; and ten people
// with an HSR: crossing_navigation's two streams of three made streams of five, its robot an HSR
// with the people detector, driven to the far corner by pure pursuit (the simulation's cost) and by
// DWA (the reference controller's own cost added). Prints steps per second and the real-time factor:
// median of several repetitions.
//   usage: robot_bench [repetitions=5] [path to the project's scenarios/=scenarios]
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "episode/episode.hpp"
#include "scenario/load.hpp"

namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

void measure(const std::string& label, const json& document, const std::string& scenarios, int repetitions) {
  const auto loaded = hrisim::scenario::load_scenario(document, {{scenarios}, {}});
  if (!loaded.model) {
    std::fprintf(stderr, "invalid scenario: %s %s\n", loaded.errors[0].pointer.c_str(), loaded.errors[0].message.c_str());
    std::exit(1);
  }
  std::vector<double> rates;
  std::int64_t ticks = 0;
  std::string termination;
  for (int r = 0; r < repetitions; ++r) {
    hrisim::episode::Episode episode(loaded.model, 1, {std::nullopt, {}, false, {}});
    const hrisim::sim::Session& session = episode.session();
    const auto start = Clock::now();
    episode.run();
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    ticks = session.state().tick;
    termination = hrisim::sim::to_string(session.state().termination);
    rates.push_back(ticks / seconds);
  }
  std::sort(rates.begin(), rates.end());
  const double median = rates[rates.size() / 2];
  std::printf("%-44s %6lld steps (%s): %8.0f steps/s  %7.1fx real time\n", label.c_str(), static_cast<long long>(ticks),
              termination.c_str(), median, median * loaded.model->dt);
}

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::atoi(argv[1]) : 5;
  const std::string scenarios = argc > 2 ? argv[2] : "scenarios";
  std::ifstream file(scenarios + "/elevator.json");
  if (!file) {
    std::fprintf(stderr, "no %s/elevator.json\n", scenarios.c_str());
    return 1;
  }
  const json elevator = json::parse(file);
  std::printf("robot_bench: dt = 1/60 s, one thread, median of %d repetitions\n", repetitions);
  measure("elevator, HSR with laser and people detector", elevator, scenarios, repetitions);
  json without_detector = elevator;
  for (json& robot : without_detector["robots"]) robot.erase("people_detector");
  measure("elevator, HSR with laser, no people detector", without_detector, scenarios, repetitions);
  std::ifstream crossing_file(scenarios + "/crossing_navigation.json");
  json crossing = json::parse(crossing_file);
  crossing["robots"][0]["model"] = "hsr";
  crossing["robots"][0]["people_detector"] = json::object();
  // Each stream's third walker gets two more beside it, 0.8 m further out, doing what it does.
  const std::vector<std::pair<std::string, std::array<double, 2>>> added{
      {"w3", {0.0, 0.8}}, {"w3", {0.0, -2.4}}, {"s3", {0.8, 0.0}}, {"s3", {-2.4, 0.0}}};
  int count = 0;
  for (const auto& [like, offset] : added) {
    const std::string id = like + "_" + std::to_string(++count);
    for (json human : crossing["humans"]) {
      if (human["id"] != like) continue;
      human["id"] = id;
      human["start"]["x"] = human["start"]["x"].get<double>() + offset[0];
      human["start"]["y"] = human["start"]["y"].get<double>() + offset[1];
      crossing["humans"].push_back(human);
      break;
    }
    for (json& step : crossing["steps"]) {
      json copies = json::array();
      for (const json& action : step["actions"]) {
        if (action.value("agent", "") != like) continue;
        json copy = action;
        copy["agent"] = id;
        copies.push_back(copy);
      }
      for (const json& copy : copies) step["actions"].push_back(copy);
    }
  }
  measure("crossing, 10 people + HSR, DWA", crossing, scenarios, repetitions);
  crossing["robots"][0]["controller"]["type"] = "goal";
  measure("crossing, 10 people + HSR, pure pursuit", crossing, scenarios, repetitions);
  return 0;
}
