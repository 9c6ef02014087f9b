#pragma once
// Reading a session's events in tests.
#include <vector>

#include "sim/session.hpp"

namespace hrisim::testing {

/// The session's events of one kind, in order.
template <class Kind>
std::vector<const sim::Event*> events_of(const sim::Session& session) {
  std::vector<const sim::Event*> found;
  for (const sim::Event& event : session.state().events) {
    if (event.is<Kind>()) found.push_back(&event);
  }
  return found;
}

}  // namespace hrisim::testing
