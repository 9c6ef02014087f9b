#include "http/ws_tickets.hpp"

#include "core/random.hpp"

namespace hrisim::http {

std::string TicketBook::issue(const std::string& session_id, const Caller& caller) {
  const auto now = std::chrono::steady_clock::now();
  std::string ticket = core::unguessable_id('t');
  std::lock_guard lock(mutex_);
  std::erase_if(tickets_, [&](const auto& entry) { return entry.second.expires < now; });
  tickets_[ticket] = {session_id, caller, now + kTicketLifetime};
  return ticket;
}

std::optional<Caller> TicketBook::redeem(const std::string& ticket, const std::string& session_id) {
  std::lock_guard lock(mutex_);
  const auto found = tickets_.find(ticket);
  if (found == tickets_.end()) return std::nullopt;
  const bool valid = found->second.session_id == session_id && found->second.expires >= std::chrono::steady_clock::now();
  const Caller caller = found->second.caller;
  tickets_.erase(found);  // used or expired, it never opens anything again
  return valid ? std::optional(caller) : std::nullopt;
}

}  // namespace hrisim::http
