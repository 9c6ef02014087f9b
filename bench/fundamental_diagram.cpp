// The fundamental diagram of hrisim's crowd models, measured in a periodic corridor (humans::
// walk_periodic_corridor) beside Weidmann's: speed and specific flow at each density, both models.
//   usage: fundamental_diagram [preset: hrisim|calibrated|crowdnav = calibrated] [seeds = 3]
//          [time gap, s = the preset's] [margin from people, m = the preset's] [obstacle_sigma, m = the preset's]
// Prints one line per model and density (the mean over the seeds), then each model's mean absolute
// error against Weidmann over 0.5–4 people/m²; then the same in single file (RiMEA test 16: Seyfried et
// al.'s ring, 15–38 walkers) against Seyfried's fit.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "humans/periodic_corridor.hpp"

int main(int argc, char** argv) {
  using namespace hrisim::humans;
  const std::string preset = argc > 1 ? argv[1] : "calibrated";
  const int seeds = argc > 2 ? std::atoi(argv[2]) : 3;
  const std::optional<CrowdPreset> named = crowd_preset_named(preset);
  if (!named) {
    std::fprintf(stderr, "fundamental_diagram: no preset '%s' (hrisim, calibrated, crowdnav)\n", preset.c_str());
    return 2;
  }
  CrowdParams params = crowd_preset(*named);
  if (argc > 3) params.headway.time_gap = std::atof(argv[3]);
  if (argc > 4) params.personal_space.from_people = std::atof(argv[4]);
  if (argc > 5) params.social_force.obstacle_sigma = std::atof(argv[5]);
  std::printf("preset %s, %d seeds, corridor 20 m x 2 m (periodic), bodies 0.4 m, time gap %.2f s, margin from people %.2f m\n",
              preset.c_str(), seeds, params.headway.time_gap, params.personal_space.from_people);
  std::printf("%-12s %8s %8s %9s %8s\n", "model", "density", "speed", "weidmann", "flow");
  for (const auto& [name, avoidance] : {std::pair{"orca", LocalAvoidance::orca}, std::pair{"social_force", LocalAvoidance::social_force}}) {
    double error = 0.0;
    int points = 0;
    for (double density : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0}) {
      double speed = 0.0, measured = 0.0;
      for (int seed = 1; seed <= seeds; ++seed) {
        const CorridorFigures figures = walk_periodic_corridor({}, density, avoidance, params, static_cast<std::uint64_t>(seed));
        speed += figures.speed / seeds;
        measured = figures.density;
      }
      const double weidmann = weidmann_speed(measured);
      error += std::abs(speed - weidmann);
      ++points;
      std::printf("%-12s %8.2f %8.3f %9.3f %8.3f\n", name, measured, speed, weidmann, measured * speed);
    }
    std::printf("%-12s mean absolute error %.3f m/s\n", name, error / points);
  }
  const PeriodicCorridor ring = seyfried_single_file();
  std::printf("single file: ring %.1f m x %.1f m (periodic), free speeds %.2f +- %.2f m/s\n", ring.length, ring.width, ring.speed_mean,
              ring.speed_spread);
  std::printf("%-12s %8s %8s %9s\n", "model", "people/m", "speed", "seyfried");
  for (const auto& [name, avoidance] : {std::pair{"orca", LocalAvoidance::orca}, std::pair{"social_force", LocalAvoidance::social_force}}) {
    double error = 0.0;
    int points = 0;
    for (const int walkers : {15, 20, 25, 30, 34, 38}) {
      const double line_density = walkers / ring.length;
      double speed = 0.0;
      for (int seed = 1; seed <= seeds; ++seed) {
        speed += walk_periodic_corridor(ring, line_density / ring.width, avoidance, params, static_cast<std::uint64_t>(seed)).speed / seeds;
      }
      const double seyfried = seyfried_single_file_speed(line_density);
      error += std::abs(speed - seyfried);
      ++points;
      std::printf("%-12s %8.2f %8.3f %9.3f\n", name, line_density, speed, seyfried);
    }
    std::printf("%-12s single file, mean absolute error %.3f m/s\n", name, error / points);
  }
}
