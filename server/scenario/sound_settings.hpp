#pragma once
// The scenario's sound settings: the clips people can say (WAV files beside the scenario) and a
// robot's `microphones` (its description's array listening, and the direction of arrival's rate).
#include <filesystem>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "core/json_schema.hpp"
#include "scenario/model.hpp"

namespace hrisim::scenario {

/// Reads "clips" ({NAME: FILE}): each WAV file found like a map (next to the scenario, then among the
/// bundled ones; confined to those folders when `confined`), read and resampled to kSampleRate.
/// Errors carry the clip's JSON pointer.
std::vector<std::pair<std::string, std::shared_ptr<const sensors::AudioClip>>> read_clips(
    const nlohmann::json& clips, const std::vector<std::filesystem::path>& search_path, bool confined,
    std::vector<core::ValidationError>& errors);

/// Reads a robot entry's "microphones" into `agent`: the robot's model must have microphone mounts.
void read_microphones(const nlohmann::json& settings, const std::string& pointer, AgentDef& agent,
                      std::vector<core::ValidationError>& errors);

}  // namespace hrisim::scenario
