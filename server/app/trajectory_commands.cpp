#include "app/trajectory_commands.hpp"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "app/command_line.hpp"
#include "core/error.hpp"
#include "humans/trajectory_prediction.hpp"
#include "scenario/model.hpp"

namespace hrisim::app {
namespace {

const char* table_name(humans::Predictor predictor) {
  switch (predictor) {
    case humans::Predictor::constant_velocity: return "constant velocity";
    case humans::Predictor::orca: return "ORCA";
    case humans::Predictor::social_force: return "social force";
  }
  return "?";
}

}  // namespace

int trajectories_command(const std::vector<std::string>& args) {
  const ParsedArgs parsed =
      parse_args(args, {"--preset"}, {"--json"}, "usage: hrisim trajectories FILE [--preset hrisim|calibrated|crowdnav] [--json]");
  const std::string preset = parsed.last("--preset").value_or("hrisim");
  const std::optional<humans::CrowdPreset> named = humans::crowd_preset_named(preset);
  if (!named) usage_error("--preset: no crowd preset '" + preset + "' (hrisim, calibrated, crowdnav)");
  std::ifstream input(parsed.file, std::ios::binary);
  if (!input) throw core::Error(core::ErrorCode::not_found, "cannot open " + parsed.file);
  humans::RecordedTrajectories trajectories;
  try {
    trajectories = humans::read_eth_ucy(input, parsed.file);
  } catch (const core::Error& error) {  // the file's fault, not the arguments': exit 1, as validate does
    std::fprintf(stderr, "hrisim: %s\n", error.what());
    return 1;
  }

  // The defaults every hrisim scenario starts from: its step and its people's discs.
  humans::PredictionSettings settings;
  settings.crowd = humans::crowd_preset(*named);
  settings.dt = scenario::kDefaultDt;
  settings.radius = scenario::kDefaultAgentRadius;
  std::vector<humans::PredictionErrors> results;
  for (const humans::Predictor predictor : humans::kPredictors) results.push_back(humans::evaluate_predictor(trajectories, predictor, settings));
  const std::size_t windows = results.front().windows;
  if (windows == 0) {
    throw core::Error(core::ErrorCode::conflict, parsed.file + ": no person is seen in " +
                                                     std::to_string(humans::kObservedFrames + humans::kPredictedFrames) +
                                                     " consecutive annotations " + std::to_string(humans::kEthUcyFrameStep) +
                                                     " frames apart: nothing to predict");
  }

  if (parsed.flags.contains("--json")) {
    nlohmann::json report = {{"file", parsed.file},
                             {"rows", trajectories.rows},
                             {"people", trajectories.tracks.size()},
                             {"windows", windows},
                             {"observed_frames", humans::kObservedFrames},
                             {"predicted_frames", humans::kPredictedFrames},
                             {"frame_interval", humans::kEthUcyFrameInterval},
                             {"dt", settings.dt},
                             {"preset", preset},
                             {"predictors", nlohmann::json::array()}};
    for (const humans::PredictionErrors& result : results) {
      report["predictors"].push_back(
          {{"predictor", humans::to_string(result.predictor)}, {"ade", result.ade}, {"fde", result.fde}, {"by_frame", result.by_frame}});
    }
    std::printf("%s\n", report.dump(2).c_str());
    return 0;
  }
  std::printf("%s: %zu windows from %zu people (observe %d annotations = %.1f s, predict %d = %.1f s), crowd preset %s\n", parsed.file.c_str(), windows,
              trajectories.tracks.size(), humans::kObservedFrames, humans::kObservedFrames * humans::kEthUcyFrameInterval,
              humans::kPredictedFrames, humans::kPredictedFrames * humans::kEthUcyFrameInterval, preset.c_str());
  std::printf("%-18s %8s %8s\n", "predictor", "ADE (m)", "FDE (m)");
  for (const humans::PredictionErrors& result : results) std::printf("%-18s %8.3f %8.3f\n", table_name(result.predictor), result.ade, result.fde);
  return 0;
}

}  // namespace hrisim::app
