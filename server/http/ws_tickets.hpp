#pragma once
// Short-lived, single-use tickets for opening a session's WebSocket from a browser, which cannot put
// an Authorization header on the upgrade: an authenticated POST gets one, the upgrade URL carries it.
#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "http/router.hpp"

namespace hrisim::http {

/// How long a WebSocket ticket may wait to be used.
inline constexpr std::chrono::seconds kTicketLifetime{30};

class TicketBook {
 public:
  /// A new ticket for `caller` to open the WebSocket of session `session_id`.
  std::string issue(const std::string& session_id, const Caller& caller);
  /// The caller it was issued to, once, for an unexpired ticket issued for this session.
  std::optional<Caller> redeem(const std::string& ticket, const std::string& session_id);

 private:
  struct Ticket {
    std::string session_id;
    Caller caller;
    std::chrono::steady_clock::time_point expires;
  };
  std::mutex mutex_;
  std::map<std::string, Ticket> tickets_;
};

}  // namespace hrisim::http
