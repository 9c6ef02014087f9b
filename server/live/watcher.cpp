#include "live/watcher.hpp"

#include <mutex>

namespace hrisim::live {

Watcher::Watcher(std::shared_ptr<Registry> registry, const LiveSession& live)
    : registry_(std::move(registry)), id_(live.id), clients_(live.clients), shown_generation_(live.generation) {
  ++*clients_;
}

Watcher::~Watcher() {
  --*clients_;
  registry_->find_if_live(id_);  // marks it used: an unwatched grace counts from here
}

Watcher::Outcome Watcher::show_news(const std::function<void(const News&)>& show) {
  const std::shared_ptr<LiveSession> live = registry_->find_if_live(id_);
  if (!live) return Outcome::gone;
  std::unique_lock lock(live->mutex, std::try_to_lock);
  if (!lock) return Outcome::busy;
  const std::vector<sim::Event>& events = live->session().state().events;
  const std::int64_t tick = live->session().state().tick;
  const bool restarted = live->generation != shown_generation_;
  if (restarted) events_shown_ = 0;
  if (!restarted && tick == shown_tick_ && events_shown_ == events.size()) return Outcome::unchanged;
  show(News{*live, restarted, std::span(events).subspan(events_shown_)});
  events_shown_ = events.size();
  shown_tick_ = tick;
  shown_generation_ = live->generation;
  return Outcome::shown;
}

}  // namespace hrisim::live
