#pragma once
// A front end's watch on one live session — a socket that pushes what happens (the session WebSocket's
// state frames; a Foxglove or rosbridge socket). Every such socket holds one, so that what a watch
// means is the same for all of them:
//   - it counts as a client while it exists: a session with a watcher never expires as unwatched, and
//     its unwatched grace counts from the last watcher's end;
//   - it holds no reference to the session: a deleted session is freed, and the watcher notices;
//   - it knows what it has shown, so each push carries only what is new (the events since the last,
//     everything again after a reset or restore).
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>

#include "live/registry.hpp"

namespace hrisim::live {

class Watcher {
 public:
  Watcher(std::shared_ptr<Registry> registry, const LiveSession& live);
  ~Watcher();
  Watcher(const Watcher&) = delete;
  Watcher& operator=(const Watcher&) = delete;

  const std::string& session_id() const { return id_; }
  /// Whether the session is still there, without counting as a use.
  bool session_live() const { return registry_->contains(id_); }

  /// What happened since the watcher last showed the session.
  struct News {
    LiveSession& session;  ///< locked while the news is shown
    bool restarted;        ///< reset or restored since: show everything again
    std::span<const sim::Event> events;  ///< the events not shown yet
  };
  enum class Outcome {
    shown,      ///< `show` was called: the news count as shown
    unchanged,  ///< no tick, event or restart since
    busy,       ///< the session is stepping: its next news will show it
    gone,       ///< the session ended
  };
  /// Calls `show` with what is new, the session locked, unless it is busy, unchanged or gone.
  Outcome show_news(const std::function<void(const News&)>& show);

 private:
  std::shared_ptr<Registry> registry_;
  std::string id_;
  std::shared_ptr<std::atomic<int>> clients_;  ///< the session's count, shared with it
  std::size_t events_shown_ = 0;  ///< events before this index were shown
  std::int64_t shown_tick_ = -1;
  std::uint64_t shown_generation_ = 0;  ///< the session's resets and restores when last shown
};

}  // namespace hrisim::live
