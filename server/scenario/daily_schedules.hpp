#pragma once
// Daily schedules (seed 000, SimVis3D's HRI extension): "probabilities of presence of a human being at
// different locations ... based on time". A scenario clock maps simulated time to a time of day; a
// person's schedule gives, per hour, the probability of being in each room; the person draws a room
// from the hour's row, walks to one of its spots, lives there by the room's activity model, and draws
// again when the stay is over. ("Routine" is kept for IMHuS's compound tasks.)
#include <array>
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/json_schema.hpp"
#include "scenario/activity_models.hpp"

namespace hrisim::scenario {

inline constexpr int kHoursPerDay = 24;
inline constexpr double kSecondsPerHour = 3600.0;
inline constexpr double kSecondsPerDay = kHoursPerDay * kSecondsPerHour;

/// Maps simulated time to a time of day: `start` seconds after midnight at t = 0, running `speed`
/// times faster than simulated time (60: a simulated second is a minute of the day).
struct Clock {
  double start = 0.0;  ///< s after midnight
  double speed = 1.0;
  /// A start drawn per session, uniformly in [start, latest_start] (equal: a fixed start), s.
  double latest_start = 0.0;
};

/// Seconds after midnight (in [0, 86400)) at simulated time `time`.
double time_of_day(const Clock& clock, double time);
/// Days since the clock started at simulated time `time` (0 on the first day).
int day_of(const Clock& clock, double time);
/// "HH:MM:SS" of a time of day.
std::string format_time_of_day(double seconds);

/// A room people can be in: the spots where they stand or sit in it (locations, each held by one
/// person at a time) and where a robot looks into it from (`lookout`, a location, or -1).
struct Room {
  std::string name;
  std::vector<int> spots;
  int lookout = -1;
};

struct DailySchedule {
  std::string name;
  double min_stay = 0.0;  ///< clock seconds a stay lasts at least (drawn uniformly)...
  double max_stay = 0.0;  ///< ...and at most; a stay also ends with its hour
  std::vector<int> activities;  ///< per room: the activity model lived by there, or -1 (standing still)
  std::array<std::vector<double>, kHoursPerDay> presence;  ///< per hour: the probability of each room

  /// The room with the highest presence probability first, at hour `hour` (ties: the room's order).
  std::vector<int> rooms_by_presence(int hour) const;
};

/// The default stay, in minutes of the clock: long enough to do something in a room, short enough to
/// move about within an hour.
inline constexpr double kDefaultMinStayMinutes = 10.0;
inline constexpr double kDefaultMaxStayMinutes = 30.0;

/// Reads "clock" (already checked against the schema); errors carry JSON pointers.
Clock read_clock(const nlohmann::json& clock, std::vector<core::ValidationError>& errors);

/// Reads "rooms": every spot and lookout is a location.
std::vector<Room> read_rooms(const nlohmann::json& rooms, const std::map<std::string, int>& locations,
                             std::vector<core::ValidationError>& errors);

/// Reads "daily_schedules" with their meaning: every hour of the day covered once, each hour's row
/// adding up to 1, rooms and activity models that exist, and models that keep a person in the room
/// (no walks).
std::vector<DailySchedule> read_daily_schedules(const nlohmann::json& schedules, const std::vector<Room>& rooms,
                                                const std::vector<ActivityModel>& models,
                                                std::vector<core::ValidationError>& errors);

}  // namespace hrisim::scenario
