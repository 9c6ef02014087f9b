#include "scenario/daily_schedules.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <numeric>

namespace hrisim::scenario {
namespace {

using nlohmann::json;
using Errors = std::vector<core::ValidationError>;

/// A row of presence probabilities may be off by rounding in the file's decimals, not more.
constexpr double kPresenceSumTolerance = 1e-6;

/// "HH:MM" or "HH:MM:SS" as seconds after midnight.
std::optional<double> parse_time_of_day(const std::string& text) {
  int hours = 0, minutes = 0, seconds = 0, consumed = 0;
  const bool long_form = std::sscanf(text.c_str(), "%2d:%2d:%2d%n", &hours, &minutes, &seconds, &consumed) == 3 &&
                         consumed == static_cast<int>(text.size());
  if (!long_form) {
    seconds = 0;
    consumed = 0;
    if (std::sscanf(text.c_str(), "%2d:%2d%n", &hours, &minutes, &consumed) != 2 || consumed != static_cast<int>(text.size())) return std::nullopt;
  }
  if (hours < 0 || hours > 23 || minutes < 0 || minutes > 59 || seconds < 0 || seconds > 59) return std::nullopt;
  return hours * kSecondsPerHour + minutes * 60.0 + seconds;
}

int find(const std::vector<Room>& rooms, const std::string& name) {
  for (std::size_t r = 0; r < rooms.size(); ++r) {
    if (rooms[r].name == name) return static_cast<int>(r);
  }
  return -1;
}

std::string room_names(const std::vector<Room>& rooms) {
  std::string names;
  for (const Room& room : rooms) names += (names.empty() ? "" : ", ") + room.name;
  return names.empty() ? "none (declare them in 'rooms')" : names;
}

class ScheduleReader {
 public:
  ScheduleReader(std::string pointer, const std::vector<Room>& rooms, const std::vector<ActivityModel>& models, Errors& errors)
      : pointer_(std::move(pointer)), rooms_(rooms), models_(models), errors_(errors) {}

  DailySchedule read(const std::string& name, const json& entry) {
    DailySchedule schedule;
    schedule.name = name;
    const json stay = entry.value("stay", json::array({kDefaultMinStayMinutes, kDefaultMaxStayMinutes}));
    schedule.min_stay = 60.0 * (stay.is_array() ? stay[0].get<double>() : stay.get<double>());
    schedule.max_stay = 60.0 * (stay.is_array() ? stay[1].get<double>() : stay.get<double>());
    if (schedule.max_stay < schedule.min_stay) error("/stay", "the longest stay is shorter than the shortest");
    if (schedule.min_stay <= 0.0) error("/stay", "a stay lasts more than 0 minutes");
    schedule.activities.assign(rooms_.size(), -1);
    const json activities = entry.value("activities", json::object());
    for (const auto& [room_name, model_name] : activities.items()) {
      const std::string at = "/activities/" + core::pointer_token(room_name);
      const int room = room_at(room_name, at);
      const int model = model_at(model_name.get<std::string>(), at);
      if (room >= 0 && model >= 0) schedule.activities[room] = model;
    }
    read_presence(schedule, entry.at("presence"));
    return schedule;
  }

 private:
  void error(const std::string& at, const std::string& message) { errors_.push_back({pointer_ + at, message}); }

  int room_at(const std::string& name, const std::string& at) {
    const int room = find(rooms_, name);
    if (room < 0) error(at, "unknown room '" + name + "'; the scenario's rooms are " + room_names(rooms_));
    return room;
  }

  int model_at(const std::string& name, const std::string& at) {
    for (std::size_t m = 0; m < models_.size(); ++m) {
      if (models_[m].name != name) continue;
      for (const Activity& activity : models_[m].activities) {
        if (activity.kind == Activity::Kind::walk) {
          error(at, "activity model '" + name + "' walks ('" + activity.name + "'): a room's model keeps the person in the room");
          return -1;
        }
      }
      return static_cast<int>(m);
    }
    error(at, "unknown activity model '" + name + "'");
    return -1;
  }

  void read_presence(DailySchedule& schedule, const json& periods) {
    std::array<int, kHoursPerDay> covered_by{};
    covered_by.fill(-1);
    for (std::size_t p = 0; p < periods.size(); ++p) {
      const std::string at = "/presence/" + std::to_string(p);
      const int from = periods[p]["hours"][0], to = periods[p]["hours"][1];
      if (from >= to) {
        error(at + "/hours", "the period ends (hour " + std::to_string(to) + ") before it begins (hour " + std::to_string(from) + ")");
        continue;
      }
      std::vector<double> row(rooms_.size(), 0.0);
      for (const auto& [room_name, probability] : periods[p]["rooms"].items()) {
        const int room = room_at(room_name, at + "/rooms/" + core::pointer_token(room_name));
        if (room >= 0) row[room] = probability.get<double>();
      }
      const double sum = std::accumulate(row.begin(), row.end(), 0.0);
      if (std::abs(sum - 1.0) > kPresenceSumTolerance) {
        char text[64];
        std::snprintf(text, sizeof text, "%.6g", sum);
        error(at + "/rooms", std::string("the probabilities add up to ") + text + ", not 1");
      }
      for (int hour = from; hour < to; ++hour) {
        if (covered_by[hour] >= 0) {
          error(at + "/hours", "hour " + std::to_string(hour) + " is already covered by period " + std::to_string(covered_by[hour]));
          continue;
        }
        covered_by[hour] = static_cast<int>(p);
        schedule.presence[hour] = row;
      }
    }
    for (int hour = 0; hour < kHoursPerDay; ++hour) {
      if (covered_by[hour] < 0) error("/presence", "hour " + std::to_string(hour) + " (" + std::to_string(hour) + ":00–" + std::to_string(hour + 1) + ":00) is in no period: cover the whole day");
    }
  }

  std::string pointer_;
  const std::vector<Room>& rooms_;
  const std::vector<ActivityModel>& models_;
  Errors& errors_;
};

}  // namespace

double time_of_day(const Clock& clock, double time) {
  const double seconds = std::fmod(clock.start + clock.speed * time, kSecondsPerDay);
  return seconds < 0.0 ? seconds + kSecondsPerDay : seconds;
}

int day_of(const Clock& clock, double time) { return static_cast<int>(std::floor((clock.start + clock.speed * time) / kSecondsPerDay)); }

std::string format_time_of_day(double seconds) {
  const long whole = static_cast<long>(std::floor(seconds));
  char text[16];
  std::snprintf(text, sizeof text, "%02ld:%02ld:%02ld", (whole / 3600) % 24, (whole / 60) % 60, whole % 60);
  return text;
}

std::vector<int> DailySchedule::rooms_by_presence(int hour) const {
  const std::vector<double>& row = presence[static_cast<std::size_t>(hour)];
  std::vector<int> order(row.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return row[a] > row[b]; });
  return order;
}

Clock read_clock(const nlohmann::json& clock, Errors& errors) {
  Clock result;
  result.speed = clock.value("speed", 1.0);
  const json start = clock.value("start", json("00:00"));
  const auto read = [&](const json& text, const std::string& at) {
    const auto seconds = parse_time_of_day(text.get<std::string>());
    if (!seconds) errors.push_back({at, "'" + text.get<std::string>() + "' is not a time of day: write HH:MM or HH:MM:SS (00:00 to 23:59:59)"});
    return seconds.value_or(0.0);
  };
  if (start.is_array()) {
    result.start = read(start[0], "/clock/start/0");
    result.latest_start = read(start[1], "/clock/start/1");
    if (result.latest_start < result.start) errors.push_back({"/clock/start", "the latest start is earlier than the earliest: the clock does not run over midnight here"});
  } else {
    result.start = result.latest_start = read(start, "/clock/start");
  }
  return result;
}

std::vector<Room> read_rooms(const nlohmann::json& rooms, const std::map<std::string, int>& locations, Errors& errors) {
  std::vector<Room> result;
  for (const auto& [name, entry] : rooms.items()) {
    const std::string pointer = "/rooms/" + core::pointer_token(name);
    Room room;
    room.name = name;
    const json& spots = entry.at("spots");
    for (std::size_t s = 0; s < spots.size(); ++s) {
      const std::string spot = spots[s];
      if (!locations.contains(spot)) {
        errors.push_back({pointer + "/spots/" + std::to_string(s), "unknown location '" + spot + "'"});
        continue;
      }
      room.spots.push_back(locations.at(spot));
    }
    if (entry.contains("lookout")) {
      const std::string lookout = entry["lookout"];
      if (!locations.contains(lookout)) {
        errors.push_back({pointer + "/lookout", "unknown location '" + lookout + "'"});
      } else {
        room.lookout = locations.at(lookout);
      }
    }
    result.push_back(std::move(room));
  }
  return result;
}

std::vector<DailySchedule> read_daily_schedules(const nlohmann::json& schedules, const std::vector<Room>& rooms,
                                                const std::vector<ActivityModel>& models, Errors& errors) {
  std::vector<DailySchedule> result;
  for (const auto& [name, entry] : schedules.items()) {
    ScheduleReader reader("/daily_schedules/" + core::pointer_token(name), rooms, models, errors);
    result.push_back(reader.read(name, entry));
  }
  return result;
}

}  // namespace hrisim::scenario
