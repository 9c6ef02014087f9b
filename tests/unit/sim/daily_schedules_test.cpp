// People living by daily schedules: the family of the bundled family_day scenario over a simulated
// week is in each room as often as their presence tables say (Pearson's chi-squared per person), a
// stay ends with its hour, nobody walks off while seated, and the same seed gives the same day.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>

#include "scenario/load.hpp"
#include "sim/activities.hpp"
#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

json family_day(double days) {
  std::ifstream file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/family_day.json");
  json document = json::parse(file);
  document["time_limit"] = days * scenario::kSecondsPerDay / document["clock"]["speed"].get<double>();
  return document;
}

/// The chi-squared value exceeded one time in a thousand with `df` degrees of freedom (Wilson and
/// Hilferty's approximation, within 1 % above 10 degrees of freedom).
double chi2_one_in_a_thousand(double df) {
  const double z = 3.0902;  // the standard normal's 99.9th percentile
  const double a = 2.0 / (9.0 * df);
  return df * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

TEST(DailySchedules, AWeeksPresenceMatchesTheFamilysTables) {
  // Where each person is at hh:15 and hh:45 of the clock: stays last at most 30 minutes and end with
  // their hour, so each sample is the room of its own draw from the hour's row.
  const auto model = testing::load_valid(family_day(7));
  ASSERT_TRUE(model);
  Session session(model, 2024);
  const scenario::Clock clock = session_clock(*model, session.state());
  struct Tally {
    std::map<std::vector<double>, std::vector<double>> by_row;  ///< a table row → how often in each room
    int samples = 0, at_a_spot = 0;
  };
  std::vector<Tally> tallies(model->agents.size());
  const auto sample_of = [&](double time) { return static_cast<long long>(std::floor((clock.start + clock.speed * time - 900.0) / 1800.0)); };
  long long last_sample = sample_of(0.0);
  while (!session.state().finished) {
    session.tick();
    const long long sample = sample_of(session.time());
    if (sample == last_sample) continue;
    last_sample = sample;
    const int hour = static_cast<int>(scenario::time_of_day(clock, session.time()) / scenario::kSecondsPerHour);
    for (std::size_t person = 0; person < model->agents.size(); ++person) {
      const scenario::AgentDef& def = model->agents[person];
      if (def.daily_schedule < 0) continue;
      const AgentState& self = session.state().agents[person];
      ASSERT_TRUE(self.living.room.valid());
      const std::vector<double>& row = model->daily_schedules[def.daily_schedule].presence[hour];
      auto& counts = tallies[person].by_row[row];
      counts.resize(row.size());
      counts[self.living.room.value] += 1;
      tallies[person].samples += 1;
      // At a spot of the room of their stay (not yet gone from the last room's, not still on the way).
      const auto& spots = model->rooms[self.living.room.value].spots;
      const bool reserved_here = std::find(spots.begin(), spots.end(), self.reservation.location.value) != spots.end();
      if (reserved_here && (self.position - model->locations[self.reservation.location.value].pose.position()).norm() < 0.5) tallies[person].at_a_spot += 1;
    }
  }
  for (std::size_t person = 0; person < model->agents.size(); ++person) {
    if (model->agents[person].daily_schedule < 0) continue;
    const Tally& tally = tallies[person];
    EXPECT_EQ(tally.samples, 7 * 48) << model->agents[person].id;
    double chi2 = 0, df = 0;
    for (const auto& [row, counts] : tally.by_row) {
      double n = 0;
      for (const double count : counts) n += count;
      for (std::size_t room = 0; room < row.size(); ++room) {
        if (row[room] == 0.0) {
          EXPECT_EQ(counts[room], 0) << model->agents[person].id << " in " << model->rooms[room].name << " at an hour with no chance of it";
          continue;
        }
        const double expected = row[room] * n;
        chi2 += (counts[room] - expected) * (counts[room] - expected) / expected;
        df += 1;
      }
      df -= 1;
    }
    std::printf("%s: chi-squared %.1f with %.0f degrees of freedom (one in a thousand above %.1f); at a spot in %d of %d samples\n",
                model->agents[person].id.c_str(), chi2, df, chi2_one_in_a_thousand(df), tally.at_a_spot, tally.samples);
    EXPECT_LT(chi2, chi2_one_in_a_thousand(df)) << model->agents[person].id << ": chi-squared " << chi2 << " with " << df << " degrees of freedom";
    // Walking from room to room takes minutes of a 60x clock; most of the time people are where they went.
    EXPECT_GT(tally.at_a_spot, tally.samples / 2) << model->agents[person].id << " was at a spot in " << tally.at_a_spot << " of " << tally.samples;
  }
}

TEST(DailySchedules, StaysEndWithTheirHourAndNobodyWalksOffSeated) {
  const auto model = testing::load_valid(family_day(1));
  ASSERT_TRUE(model);
  Session session(model, 7);
  std::vector<std::int64_t> released(model->agents.size(), -1);
  int stood_up_to_leave = 0, stays = 0;
  while (!session.state().finished) {
    const std::size_t events_before = session.state().events.size();
    session.tick();
    for (std::size_t e = events_before; e < session.state().events.size(); ++e) {
      const Event& event = session.state().events[e];
      if (!event.is<sim::events::StayStarted>()) continue;
      stays += 1;
      // "until" is at most the next full hour of the clock.
      const double now = scenario::time_of_day(session_clock(*model, session.state()), event.time);
      const std::string until = event.as<events::StayStarted>()->until;
      const double until_seconds = std::stoi(until.substr(0, 2)) * 3600.0 + std::stoi(until.substr(3, 2)) * 60.0 + std::stoi(until.substr(6, 2));
      const double next_hour = (std::floor(now / 3600.0) + 1.0) * 3600.0;
      EXPECT_LE(until_seconds == 0.0 ? scenario::kSecondsPerDay : until_seconds, next_hour + 1.0) << event.subject << " at " << event.time;
    }
    for (std::size_t person = 0; person < model->agents.size(); ++person) {
      const AgentState& self = session.state().agents[person];
      if (self.animation.motion_released_tick >= 0 && released[person] != self.animation.motion_released_tick) {
        EXPECT_EQ(scenario::posture_at(*self.animation.motion, self.animation.motion->duration()), scenario::Posture::standing)
            << model->agents[person].id << " walked off '" << self.animation.motion->name() << "' at " << session.time();
        if (self.animation.motion->name() == "stand_up") stood_up_to_leave += 1;
      }
      released[person] = self.animation.motion_released_tick;
    }
  }
  EXPECT_GT(stays, 100);
  EXPECT_GT(stood_up_to_leave, 5) << "people sit in most rooms, and stand up when it is time to go";
}

TEST(DailySchedules, TheSameSeedGivesTheSameDay) {
  const auto model = testing::load_valid(family_day(0.25));
  ASSERT_TRUE(model);
  Session first(model, 3), second(model, 3), other(model, 4);
  while (!first.state().finished) {
    first.tick();
    second.tick();
    other.tick();
  }
  EXPECT_EQ(first.state_hash(), second.state_hash());
  EXPECT_NE(first.state_hash(), other.state_hash());
}

TEST(DailySchedules, AClockStartGivenAsARangeIsDrawnPerSession) {
  json document = family_day(0.1);
  document["clock"]["start"] = {"08:00", "20:00"};
  const auto model = testing::load_valid(document);
  ASSERT_TRUE(model);
  std::set<double> starts;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const Session session(model, seed);
    const double start = session.state().clock_start;
    EXPECT_GE(start, 8 * 3600.0);
    EXPECT_LE(start, 20 * 3600.0);
    EXPECT_EQ(start, Session(model, seed).state().clock_start) << "the same seed, the same start";
    starts.insert(start);
  }
  EXPECT_EQ(starts.size(), 20u);
}

}  // namespace
}  // namespace hrisim::sim
