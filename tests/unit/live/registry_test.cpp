// The live-session service on its own, as a front end other than http would use it: sessions
// created within the limit, seen only by their owner (or an admin), realtime ones stepped by the
// registry's ticker, restores and seeks admitted one at a time per owner.
#include "live/registry.hpp"

#include <gtest/gtest.h>

#include <thread>

#include "core/error.hpp"
#include "scenario/load.hpp"

namespace hrisim::live {
namespace {

std::shared_ptr<const scenario::Model> queue_scenario() {
  const auto loaded = scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/queue.json");
  for (const auto& e : loaded.errors) ADD_FAILURE() << e.pointer << ": " << e.message;
  return loaded.model;
}

NewSession new_session(const std::string& owner, Mode mode = Mode::lockstep) {
  NewSession asked;
  asked.scenario = "queue";
  asked.model = queue_scenario();
  asked.seed = 1;
  asked.mode = mode;
  asked.owner = owner;
  return asked;
}

core::ErrorCode code_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const core::Error& e) {
    return e.code();
  }
  ADD_FAILURE() << "no error";
  return core::ErrorCode::internal;
}

TEST(Registry, CreatesWithinTheLimitAndShowsASessionOnlyToItsOwner) {
  Registry registry(SessionLimits{2});
  const core::Caller alice{"alice", false}, bob{"bob", false}, admin{"", true};
  const std::shared_ptr<LiveSession> first = registry.create(new_session("alice"));
  registry.create(new_session("bob"));
  EXPECT_EQ(code_of([&] { registry.create(new_session("alice")); }), core::ErrorCode::unavailable);
  EXPECT_EQ(registry.find(first->id, alice), first);
  EXPECT_EQ(code_of([&] { registry.find(first->id, bob); }), core::ErrorCode::not_found) << "another owner's is absent";
  EXPECT_EQ(registry.all(alice).size(), 1u);
  EXPECT_EQ(registry.all(admin).size(), 2u);
  EXPECT_EQ(code_of([&] { registry.remove(first->id, bob); }), core::ErrorCode::not_found);
  registry.remove(first->id, alice);
  EXPECT_FALSE(registry.contains(first->id));
  EXPECT_NE(registry.create(new_session("alice")), nullptr) << "its place is free again";
}

TEST(Registry, ARealtimeSessionIsSteppedByTheTickerALockstepOneIsNot) {
  Registry registry(SessionLimits{});
  const std::shared_ptr<LiveSession> realtime = registry.create(new_session("", Mode::realtime));
  const std::shared_ptr<LiveSession> lockstep = registry.create(new_session(""));
  std::int64_t ticks = 0;
  for (int wait = 0; wait < 100 && ticks == 0; ++wait) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::lock_guard lock(realtime->mutex);
    ticks = realtime->session().state().tick;
  }
  EXPECT_GT(ticks, 0) << "the ticker steps a realtime session by the wall clock";
  std::lock_guard lock(lockstep->mutex);
  EXPECT_EQ(lockstep->session().state().tick, 0) << "a lockstep one waits for its clients";
}

TEST(Registry, OneRestoreOrSeekAtATimePerOwner) {
  Registry registry(SessionLimits{});
  std::shared_ptr<void> place = registry.admit_simulation("alice");
  EXPECT_EQ(code_of([&] { registry.admit_simulation("alice"); }), core::ErrorCode::unavailable);
  EXPECT_NO_THROW(registry.admit_simulation("bob")) << "another owner's is admitted";
  place.reset();
  EXPECT_NO_THROW(registry.admit_simulation("alice")) << "given back when the handle goes";
}

TEST(Mode, NamesReadBackAndNothingElseIsAMode) {
  for (const Mode mode : {Mode::lockstep, Mode::realtime}) EXPECT_EQ(parse_mode(to_string(mode)), mode);
  EXPECT_FALSE(parse_mode("Realtime"));
  EXPECT_FALSE(parse_mode(""));
}

}  // namespace
}  // namespace hrisim::live
