#pragma once
// What a client gives a live session (its lock held by the caller): env steps with actions, commands,
// placements, snapshots, restores and seeks — checked first, then given through the episode, which keeps
// them in its input log.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "episode/episode.hpp"
#include "http/session_work.hpp"
#include "http/router.hpp"

namespace hrisim::http {

/// An action as the request contract lets it in: a list of numbers, or null for none.
std::optional<std::vector<double>> action_of(const nlohmann::json& action);
/// 409 for stepping a session the server steps itself.
void check_lockstep(const LiveSession& live);
/// Gives a list of commands, each checked before any is given.
nlohmann::json give_commands(LiveSession& live, const nlohmann::json& commands);
/// Advances up to `steps` environment steps (each the task's frame skip in ticks, one tick without a
/// task): the reply's JSON text — its `type` first when given (a WebSocket's), the status, the events
/// of those steps, Gymnasium's observation, reward, info, terminated (the task's ending, or the
/// scenario's last step done) and truncated (its time limit).
std::string step_session(LiveSession& live, std::int64_t steps, const std::optional<std::vector<double>>& action, std::string_view type = {});
/// Steps several lockstep sessions `n` env steps each, each by its own action, the sessions shared out
/// over the worker pool: the body {"sessions": [ids], "actions": [one per session, a list or null],
/// "n"} is checked first (an unknown or realtime session, a repeated id, a malformed action: an error
/// at its JSON pointer, and nothing is stepped). The answer lists each session's step reply, or its
/// {"error": …}, in the order asked, under "results" (after `type`, when given).
Response step_many(Registry& registry, const Caller& caller, const nlohmann::json& body, std::string_view type = {});
/// Keeps the episode's present point as a snapshot.
nlohmann::json take_snapshot(LiveSession& live);
/// Goes back (or forth) to the snapshot the body names: the episode again from its start with the
/// snapshot's inputs, up to its tick. Gymnasium's observation and info, with the status.
nlohmann::json restore_snapshot(LiveSession& live, const nlohmann::json& body);
/// The session goes on from `episode` (restored or rewound): viewers see a fresh start; the events up
/// to here are not reported again; a realtime session's clock starts from its tick. Gymnasium's
/// observation and info, with the status.
nlohmann::json go_on_from(LiveSession& live, std::unique_ptr<episode::Episode> episode);
/// Gymnasium's reset: a fresh episode of the same scenario with `seed` (null: the session's), the
/// `poses` ({name: pose}, as place() reads them, under /options/poses) set before its first tick, all or
/// none. The first observation and info, with the status.
nlohmann::json reset_session(LiveSession& live, const nlohmann::json& seed, const nlohmann::json& poses);
/// Goes to the tick the body names ({"tick"}): back, the episode again from its start with its inputs
/// up to that tick (a new branch from there); forward (lockstep only, at most kMaxStepsPerRequest
/// ticks), the ticks a clock would give. Gymnasium's observation and info, with the status.
nlohmann::json seek_session(LiveSession& live, const nlohmann::json& body);
/// The input that places an agent or object by name at a pose {x, y, z, roll, pitch, yaw} (checked; `at`
/// is its JSON pointer prefix): seed 000's uniform pose interface. People and robots stay upright on
/// the floor; a place off the floor is refused when the input is given.
episode::Input place(const sim::Session& session, const std::string& name, const nlohmann::json& body, const std::string& at);
/// An input as the API takes it, {"command": a command} or {"place": name, "pose": {…}}, checked against
/// the session (`at`: its JSON pointer); input_json writes one so.
episode::Input input_of(const sim::Session& session, const nlohmann::json& given, const std::string& at);
nlohmann::json input_json(const scenario::Model& model, const episode::Input& input);

}  // namespace hrisim::http
