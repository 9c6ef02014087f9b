#pragma once
// Who asks: the owner whose things they make and see, and what they may do. Front ends (http's token
// guard, a bridge's handshake) find it out; the services they call decide with it.
#include <string>

namespace hrisim::core {

struct Caller {
  std::string owner;       ///< namespace of what they create and see; empty on a server without owners
  bool sees_all = true;    ///< an admin (or a server without owners): everyone's sessions, runs and uploads
  bool read_only = false;  ///< may look, not change anything
};

/// Whether `caller` may see something `owner` made.
inline bool visible_to(const Caller& caller, const std::string& owner) { return caller.sees_all || caller.owner == owner; }

}  // namespace hrisim::core
