#pragma once
// The text command language for people, as SimVis3D's command interface: "walk X Y", "wait S",
// "turn_to RAD", "look_at NAME", "motion NAME [S]", "say S|CLIP", "behaviour NAME". Front ends read it
// (the REST and WebSocket commands, a snapshot file's inputs) and give the simulation the Action it
// says; the simulation itself takes only Actions.
#include <string_view>

#include "scenario/model.hpp"

namespace hrisim::scenario {

/// The action a command to person `agent` (an index of model.agents) says, checked against the model.
/// Throws core::Error(bad_request) saying what is wrong.
Action parse_human_command(const Model& model, int agent, std::string_view text);

}  // namespace hrisim::scenario
