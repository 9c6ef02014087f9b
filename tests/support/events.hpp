#pragma once
// Reading a session's events in tests.
#include <string>
#include <vector>

#include "sim/session.hpp"

namespace hrisim::testing {

/// The session's events of one kind, in order.
inline std::vector<const sim::Event*> events_of(const sim::Session& session, const std::string& kind) {
  std::vector<const sim::Event*> found;
  for (const sim::Event& event : session.state().events) {
    if (event.kind == kind) found.push_back(&event);
  }
  return found;
}

}  // namespace hrisim::testing
