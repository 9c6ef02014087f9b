#pragma once
// The fundamental diagram as pedestrian dynamics measures it: people walking one way along a straight
// corridor whose ends wrap (periodic boundaries), so the density is fixed and the same everywhere.
// It runs the crowd model exactly as the walking phase does (humans::Crowd, the squeeze, walls as the
// nearest obstacle point, nobody's centre nearer a wall than its radius); only the path is replaced
// by a preferred velocity straight along the corridor.
#include <cstdint>

#include "humans/locomotion.hpp"

namespace hrisim::humans {

/// A corridor of the size the literature's periodic measurements use, with RiMEA's bodies and
/// Weidmann's free speeds.
struct PeriodicCorridor {
  double length = 20.0;       ///< m, between the wrapping ends
  double width = 2.0;         ///< m, between the walls
  double radius = 0.2;        ///< m: RiMEA's body of 0.4 m (its verification tests' standard person)
  double speed_mean = 1.34;   ///< m/s, Weidmann's mean free speed
  double speed_spread = 0.26; ///< m/s, its standard deviation (Weidmann 1993)
  double dt = 1.0 / 60.0;     ///< s, hrisim's default tick
  double settle = 30.0;       ///< s walked before measuring, so the start's lattice is forgotten
  double measure = 30.0;      ///< s over which speeds are averaged
};

struct CorridorFigures {
  double density = 0.0;        ///< people/m²: the people over the corridor's area
  double speed = 0.0;          ///< m/s, mean speed along the corridor over people and ticks
  double specific_flow = 0.0;  ///< people/(m·s): density × speed
};

/// Walks `density` people/m² (rounded to whole people) round the corridor under `avoidance` and
/// measures them. The start (a jittered lattice) and the free speeds are drawn from `seed`.
CorridorFigures walk_periodic_corridor(const PeriodicCorridor& corridor, double density, LocalAvoidance avoidance,
                                       const CrowdParams& params, std::uint64_t seed);

/// The time gap of Seyfried et al.'s single-file walkers, s: the b of their fit d = a + b·v below. The
/// headway's V(s) = min(v0, s/T) is that fit with T = b (and a the body's length).
inline constexpr double kSeyfriedTimeGap = 1.06;

/// Seyfried et al.'s (2005) single-file experiment, as RiMEA test 16 takes it: a ring of 17.3 m that
/// no one can pass in, walkers of free speed 1.24 ± 0.15 m/s.
PeriodicCorridor seyfried_single_file();

/// Their fit of the space a walker takes in single file against speed, d = 0.36 m + 1.06 s · v, as a
/// speed at a line density (people/m), no faster than their mean free speed.
double seyfried_single_file_speed(double line_density);

/// Weidmann's (1993) fundamental diagram: speed at a density, m/s (Kladek's form with free speed
/// 1.34 m/s, γ = 1.913 m⁻², largest density 5.4 people/m²).
double weidmann_speed(double density);

}  // namespace hrisim::humans
