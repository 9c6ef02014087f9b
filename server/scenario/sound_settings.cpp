#include "scenario/sound_settings.hpp"

#include <map>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/files.hpp"
#include "sensors/wav.hpp"

namespace hrisim::scenario {

std::vector<std::pair<std::string, std::shared_ptr<const sensors::AudioClip>>> read_clips(
    const nlohmann::json& clips, const std::vector<std::filesystem::path>& search_path, bool confined,
    std::vector<core::ValidationError>& errors) {
  std::vector<std::pair<std::string, std::shared_ptr<const sensors::AudioClip>>> result;
  // A file named by several clips is read once: naming one file many times does not multiply the work.
  std::map<std::filesystem::path, std::shared_ptr<const sensors::AudioClip>> read;
  for (const auto& [name, file] : clips.items()) {
    const std::string pointer = "/clips/" + core::pointer_token(name);
    const std::string path_text = file.get<std::string>();
    const auto path = core::find_file(search_path, path_text, confined);
    if (!path) {
      errors.push_back({pointer, "clip '" + path_text + "' not found (a relative path, looked up next to the scenario and among the bundled scenarios)"});
      continue;
    }
    if (const auto known = read.find(*path); known != read.end()) {
      result.emplace_back(name, known->second);
      continue;
    }
    try {
      const std::string bytes = core::read_file(*path);
      const sensors::AudioClip clip = sensors::read_wav(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
      read[*path] = std::make_shared<const sensors::AudioClip>(sensors::resampled(clip, sensors::kSampleRate));
      result.emplace_back(name, read[*path]);
    } catch (const core::Error& e) {
      errors.push_back({pointer, path_text + ": " + e.what()});
    }
  }
  return result;
}

void read_microphones(const nlohmann::json& settings, const std::string& pointer, AgentDef& agent,
                      std::vector<core::ValidationError>& errors) {
  if (!agent.robot_model) {
    errors.push_back({pointer, "only a robot with a model has microphones"});
    return;
  }
  try {
    if (!sensors::microphone_array(*agent.robot_model)) {
      errors.push_back({pointer, "robot model '" + agent.robot_model->name + "' has no microphones (hsr and roman have)"});
      return;
    }
  } catch (const core::Error& e) {
    errors.push_back({pointer, e.what()});
    return;
  }
  sensors::MicrophonesParams params;
  params.self_noise = settings.value("self_noise", params.self_noise);
  params.motor_noise = settings.value("motor_noise", params.motor_noise);
  agent.microphones = params;
  agent.sound_direction.rate = settings.value("direction_rate", agent.sound_direction.rate);
}

}  // namespace hrisim::scenario
