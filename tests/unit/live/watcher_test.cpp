// A front end's watch on a session (live::Watcher), as a socket other than the session WebSocket uses
// it: it keeps the session counted as watched, shows each event once, everything again after a
// restart, and notices a busy or ended session.
#include "live/watcher.hpp"

#include <gtest/gtest.h>

#include "scenario/load.hpp"

namespace hrisim::live {
namespace {

std::shared_ptr<LiveSession> elevator_session(Registry& registry) {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/elevator.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  NewSession asked;
  asked.scenario = "elevator";
  asked.model = loaded.model;
  asked.seed = 1;
  return registry.create(std::move(asked));
}

struct Shown {
  bool restarted = false;
  std::size_t events = 0;
  std::int64_t tick = -1;
};

Shown show(Watcher& watcher, Watcher::Outcome expected) {
  Shown shown;
  EXPECT_EQ(watcher.show_news([&](const Watcher::News& news) {
    shown = {news.restarted, news.events.size(), news.session.session().state().tick};
  }), expected);
  return shown;
}

TEST(Watcher, ShowsEachEventOnceAndEverythingAgainAfterARestart) {
  auto registry = std::make_shared<Registry>(SessionLimits{});
  const std::shared_ptr<LiveSession> live = elevator_session(*registry);
  Watcher watcher(registry, *live);
  EXPECT_EQ(live->clients->load(), 1) << "a watcher counts as a client";

  const Shown first = show(watcher, Watcher::Outcome::shown);
  EXPECT_EQ(first.tick, 0);
  EXPECT_EQ(first.events, live->session().state().events.size()) << "the events so far, at the first look";
  show(watcher, Watcher::Outcome::unchanged);

  const std::size_t before = live->session().state().events.size();
  for (int t = 0; t < 600; ++t) live->episode->tick();
  const std::size_t after = live->session().state().events.size();
  ASSERT_GT(after, before) << "the elevator's first 10 s have events";
  const Shown next = show(watcher, Watcher::Outcome::shown);
  EXPECT_EQ(next.tick, 600);
  EXPECT_EQ(next.events, after - before) << "only the new ones";
  EXPECT_FALSE(next.restarted);

  live->start(live->session().shared_model());
  ++live->generation;
  const Shown again = show(watcher, Watcher::Outcome::shown);
  EXPECT_TRUE(again.restarted);
  EXPECT_EQ(again.tick, 0);
  EXPECT_EQ(again.events, live->session().state().events.size());

  {
    std::lock_guard busy(live->mutex);
    show(watcher, Watcher::Outcome::busy);
  }
  registry->remove(live->id, core::Caller{"", true});
  show(watcher, Watcher::Outcome::gone);
  EXPECT_FALSE(watcher.session_live());
}

TEST(Watcher, ASessionIsWatchedWhileAWatcherLives) {
  auto registry = std::make_shared<Registry>(SessionLimits{});
  const std::shared_ptr<LiveSession> live = elevator_session(*registry);
  {
    Watcher one(registry, *live), two(registry, *live);
    EXPECT_EQ(live->clients->load(), 2);
  }
  EXPECT_EQ(live->clients->load(), 0);
}

}  // namespace
}  // namespace hrisim::live
