#pragma once
// Local motion of a crowd: every agent's new velocity from its preferred velocity, its neighbours and
// the nearest obstacle, computed for all agents before any is applied (order-independent).
// Two models, chosen per agent: ORCA (van den Berg et al. 2011, as in RVO2) and the social force
// model (Helbing & Molnár 1995 with Moussaïd et al. 2009's interaction term, as in pedsim).
// Robots are part of the crowd as agents whose velocity comes from their controller: humans always
// react to them, and under ORCA take full responsibility for avoiding them (robots do not reciprocate).
#include <algorithm>
#include <functional>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/math.hpp"
#include "core/thread_team.hpp"
#include "humans/spatial_grid.hpp"

namespace hrisim::humans {

enum class LocalAvoidance { orca, social_force };

/// ORCA parameters; defaults as IMHuS's ORCA setup and RVO2's examples.
struct OrcaParams {
  double neighbour_distance = 2.0;  ///< m, neighbours considered
  int max_neighbours = 5;           ///< closest ones kept
  double time_horizon = 2.0;        ///< s, agents avoid collisions within this time
  double obstacle_horizon = 1.0;    ///< s, same for static obstacles
};

/// Social force parameters; defaults are pedsim's (Moussaïd et al. 2009 for λ, γ, n, n′).
struct SocialForceParams {
  double desired_factor = 1.0;    ///< weight of the driving force
  double social_factor = 2.1;     ///< weight of the interaction with other agents
  double obstacle_factor = 10.0;  ///< weight of the obstacle repulsion
  double obstacle_sigma = 0.8;    ///< m, decay length of the obstacle force
  double relaxation_time = 0.5;   ///< s, time to adapt to the desired velocity
  double lambda = 2.0;            ///< weight of the velocity difference in the interaction direction
  double gamma = 0.35;            ///< interaction range per unit of interaction vector
  double n = 2.0;                 ///< angular interaction decay
  double n_prime = 3.0;           ///< velocity interaction decay
  double neighbour_distance = 4.0;  ///< m, neighbours considered (the force is negligible beyond)
};

/// The gap people keep from a robot's footprint, beyond touching, m: Hall's boundary between the
/// intimate and the personal zone (0.45 m), which subjects in a corridor found the least a passing
/// robot should leave (Pacchierotti, Christensen & Jensfelt 2006); docs/crowd.md gives the sources.
inline constexpr double kPersonalSpaceFromRobots = 0.45;
/// The gap people keep from each other beyond touching, m: walkers passing an obstacle kept 0.30 m
/// (Hackney, Vallis & Cinelli 2013).
inline constexpr double kPersonalSpaceFromPeople = 0.30;

/// Squeezing past a robot, or sharing a cabin or a queue with it, people still keep this much from its
/// footprint, m: at full stride an adult's feet reach this far beyond the 0.3 m disc that stands for
/// their body (measured on hrisim's walking body, tests/unit/humans/body_test.cpp).
inline constexpr double kLimbClearance = 0.25;

/// Margins people keep beyond touching, surface to surface. Where two are already closer (people
/// placed close together, a crowded scene) the gap they have is the one they keep: nobody is pushed
/// apart, nobody closes in.
struct PersonalSpace {
  double from_robots = kPersonalSpaceFromRobots;
  double from_people = kPersonalSpaceFromPeople;
};

/// Moussaïd, Helbing & Theraulaz's (2011) two heuristics, which reproduce the fundamental diagram:
/// - a walker heads, within its field of view, the way that brings it nearest its destination given
///   how far it could walk that way before touching someone (or something): it overtakes the slow;
/// - it walks no faster than the gap ahead that way (surface to surface) covered in `time_gap`: the
///   room needed per person grows with speed, the mechanism of Weidmann's diagram (the collision-free
///   speed model's V(s) = min(v0, s/T), Tordeux, Chraibi & Seyfried 2016).
/// A `time_gap` of 0 turns both off (hrisim's HRI default); the `calibrated` preset sets them
/// (docs/crowd-validation.md).
struct Headway {
  double time_gap = 0.0;      ///< s; Moussaïd et al.'s τ is 0.5 s
  double horizon = 4.0;       ///< m, how far ahead the ways are compared (their d_max, 10 m, is cut for speed)
  double field_of_view = 5.0 * std::numbers::pi / 12.0;  ///< rad, each side of the way wanted (their φ, 75°)
};
/// The ways compared within the field of view, each side of the way wanted.
inline constexpr int kHeadwayWaysEachSide = 5;

/// The settings of the crowd models, as a scenario's `locomotion` section gives them.
struct CrowdParams {
  OrcaParams orca;
  SocialForceParams social_force;
  PersonalSpace personal_space;
  Headway headway;
};

/// Named sets of crowd settings (`locomotion.preset`; docs/crowd-validation.md):
/// - hrisim: the defaults above, set for people around robots;
/// - calibrated: Headway on, no margin between people (the time gap is the room they keep), and the
///   social force's walls acting as near as Helbing et al.'s: its fundamental diagram follows
///   Weidmann's and a 1 m bottleneck passes what experiments measured;
/// - crowdnav: CrowdNav's crowd_sim (ORCA seeing 10 neighbours within 10 m, 5 s horizons, no margins).
enum class CrowdPreset { hrisim, calibrated, crowdnav };
/// The calibrated preset's time gap, s. Fitted in docs/crowd-validation.md: the fundamental diagram in
/// the periodic corridor wants 0.7–1 s, the flow through a 1 m bottleneck 0.7 s or less (a single file
/// passes at most one person per time gap); Tordeux et al.'s (2016) collision-free model used 1 s.
inline constexpr double kCalibratedTimeGap = 0.65;
/// The calibrated social force's wall repulsion: its decay length, m (Helbing, Farkas & Vicsek 2000
/// use 0.08 m; pedsim's 0.8 m pushes walkers in a 2 m corridor into one file down its middle and
/// halves a 1 m bottleneck's flow), and its weight (fitted to the bottleneck, pedsim's is 10).
inline constexpr double kCalibratedObstacleSigma = 0.1;
inline constexpr double kCalibratedObstacleFactor = 3.0;
CrowdParams crowd_preset(CrowdPreset preset);
/// The preset of that name (hrisim, calibrated, crowdnav), if there is one.
std::optional<CrowdPreset> crowd_preset_named(std::string_view name);

/// A person held up by others (slower than kHeldUpSpeedShare of where they want to go) gives up their
/// personal-space margins over this long, and takes them back over as long once walking freely, s.
inline constexpr double kSqueezeTime = 3.0;
inline constexpr double kHeldUpSpeedShare = 0.3;

/// The share of its margins (CrowdAgent::personal_space) a person keeps after a tick in which it wanted
/// `wanted_speed` and walked at `speed`: the squeeze.
inline double squeezed(double share, double wanted_speed, double speed, double dt) {
  const bool held_up = wanted_speed > 0.0 && speed < kHeldUpSpeedShare * wanted_speed;
  return std::clamp(share + (held_up ? -1.0 : 1.0) * dt / kSqueezeTime, 0.0, 1.0);
}

/// Helbing & Molnár's bound on speed relative to the preferred speed.
inline constexpr double kMaxSpeedFactor = 1.3;

struct CrowdAgent {
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  Vec2 preferred_velocity = Vec2::Zero();  ///< towards the next waypoint at the preferred speed; zero when arrived
  double radius = 0.3;
  double max_speed = 1.34 * kMaxSpeedFactor;
  LocalAvoidance avoidance = LocalAvoidance::orca;
  bool controlled = false;  ///< a robot: velocity given, not computed; others treat it as non-reciprocating
  bool replayed = false;  ///< a recorded person played back: velocity given, not computed; a person to the others, who avoid it alone
  double personal_space = 1.0;  ///< share of the PersonalSpace margins this agent keeps now
  int group = -1;  ///< members of one group keep no margin between them
  int place = -1;  ///< people sharing a place (a cabin, a queue) keep none either, nor from a robot sharing it
  bool robots_as_obstacles = false;  ///< HuNavSim's impassive: keeps from robots only what limbs need
};

/// One half-plane of permitted velocities: points left of the directed line (RVO2's Line).
struct OrcaLine {
  Vec2 point;
  Vec2 direction;
};

/// Candidate pairs of agents for the social force, as columns (a, b: slots of the spatial grid).
/// Differences of positions (within the range) and velocities need no more than single precision.
struct SocialPairs {
  std::vector<std::uint32_t> a, b;
  std::vector<float> dx, dy;    ///< b's position minus a's
  std::vector<float> dvx, dvy;  ///< a's velocity minus b's
  std::vector<float> fx, fy;    ///< the interaction force on a
  std::size_t kept = 0;         ///< pairs within range, at the front
  void resize(std::size_t size);
};

/// A crowd's loops are shared out over its threads (Crowd::set_threads) from this many people: below,
/// a tick's share is shorter than handing it over.
inline constexpr std::size_t kCrowdToShare = 256;

/// Nearest static or temporary obstacle point to p within `range`, if any.
using ObstacleQuery = std::function<std::optional<Vec2>(const Vec2& p, double range)>;

class Crowd {
 public:
  Crowd(OrcaParams orca = {}, SocialForceParams social_force = {}, PersonalSpace personal_space = {}, Headway headway = {});

  /// New velocities for all agents (controlled agents keep theirs). Each agent's is computed from
  /// this tick's inputs alone, so the agents are shared out over the crowd's threads (set_threads)
  /// with the same result bit for bit.
  void compute_velocities(std::span<const CrowdAgent> agents, const ObstacleQuery& obstacles, double dt,
                          std::vector<Vec2>& velocities);

  /// For each agent of the last compute_velocities, how far its position is from the nearest obstacle
  /// point its model looked for (the query's range when none is nearer; 0 for a controlled agent,
  /// whose model looks for none). A step shorter than this minus the agent's radius stays clear.
  const std::vector<double>& obstacle_distances() const { return obstacle_distances_; }

  /// Threads, the caller's included, that compute the velocities (1 by default: no helper thread).
  void set_threads(unsigned threads);

  const OrcaParams& orca() const { return orca_; }
  const SocialForceParams& social_force() const { return social_force_; }
  const PersonalSpace& personal_space() const { return personal_space_; }
  const Headway& headway() const { return headway_; }

 private:
  /// The margin agent i keeps from agent j this tick (see PersonalSpace).
  double margin(const CrowdAgent& agent, const CrowdAgent& other) const;
  /// What one thread's agents need while their velocities are computed.
  struct Scratch {
    std::vector<OrcaLine> lines;
    std::vector<std::pair<double, std::uint32_t>> neighbours;
  };
  /// The agent's preferred velocity turned and slowed as Headway says.
  Vec2 within_headway(std::size_t i, std::span<const CrowdAgent> agents, const ObstacleQuery& obstacles, Scratch& scratch) const;
  /// A social-force agent's velocity with the part that would take it into a neighbour's margin removed.
  Vec2 keep_personal_space(std::size_t i, std::span<const CrowdAgent> agents, Vec2 velocity, double dt, Scratch& scratch) const;
  Vec2 orca_velocity(std::size_t i, std::span<const CrowdAgent> agents, const Vec2& preferred, const ObstacleQuery& obstacles,
                     double dt, Scratch& scratch, double& obstacle_distance) const;
  /// The interaction forces of the social force model on every agent that uses it, into social_.
  void add_social_forces(std::span<const CrowdAgent> agents);
  Vec2 social_force_velocity(std::size_t i, std::span<const CrowdAgent> agents, const Vec2& preferred, const ObstacleQuery& obstacles,
                             double dt, Scratch& scratch, double& obstacle_distance) const;

  OrcaParams orca_;
  SocialForceParams social_force_;
  PersonalSpace personal_space_;
  Headway headway_;
  SpatialGrid grid_;
  std::vector<Vec2> positions_;
  std::vector<Vec2> social_;  ///< per agent this step: the sum of its interaction forces
  std::vector<double> obstacle_distances_;
  // Scratch of add_social_forces, in the grid's slot order.
  std::vector<Vec2> slot_velocities_;
  std::vector<SocialPairs> social_pairs_;  ///< one per thread: its slots' pairs within range first, then room to spare
  std::vector<Vec2> slot_social_;  ///< social_ in slot order
  std::vector<Scratch> scratch_;        ///< one per thread
  std::unique_ptr<core::ThreadTeam> team_;  ///< null: one thread
};

/// The ORCA half-plane induced by one neighbour (RVO2's Agent::computeNewVelocity) for an agent at
/// `position` moving at `velocity`: `responsibility` is its share of the avoidance (0.5 when the other
/// avoids too, 1 when it does not). A neighbour of radius 0 that stands still is an obstacle point.
OrcaLine orca_line(const Vec2& position, const Vec2& velocity, double radius, const Vec2& other_position,
                   const Vec2& other_velocity, double other_radius, double time_horizon, double dt,
                   double responsibility);

/// The social force model's interaction force on an agent from another `offset` away (the other's
/// position minus its own), with `velocity_difference` its velocity minus the other's.
Vec2 interaction_force(const SocialForceParams& params, const Vec2& offset, const Vec2& velocity_difference);

/// The social force model's repulsion from the nearest obstacle point on a body of `radius` at
/// `position` (pedsim's exponential, decay length obstacle_sigma), unweighted; zero at the point itself.
Vec2 obstacle_force(const SocialForceParams& params, const Vec2& position, double radius, const Vec2& obstacle);

/// RVO2's linear programs: the velocity closest to `preferred` (within `max_speed`) satisfying the
/// lines, the first `obstacle_lines` of which are hard; when infeasible, the velocity that violates
/// the soft lines least.
Vec2 solve_orca(const std::vector<OrcaLine>& lines, std::size_t obstacle_lines, double max_speed,
                const Vec2& preferred);

}  // namespace hrisim::humans
