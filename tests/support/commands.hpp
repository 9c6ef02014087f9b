#pragma once
// Giving people text commands in tests, as the API gives them: parsed against the model, then given.
#include <string>
#include <string_view>

#include "scenario/human_commands.hpp"
#include "sim/session.hpp"

namespace hrisim::testing {

/// Throws core::Error(bad_request) for a command the person cannot take, as the API refuses it.
inline void command(sim::Session& session, const std::string& person, std::string_view text) {
  const int agent = session.index_of(session.agent_id(person));
  session.command_human(scenario::parse_human_command(session.model(), agent, text), std::string(text));
}

}  // namespace hrisim::testing
