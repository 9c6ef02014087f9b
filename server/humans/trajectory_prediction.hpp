#pragma once
// Recorded pedestrians predicted by a fixed protocol (observe 3.2 s, predict 4.8 s): by constant
// velocity, or by hrisim's crowd models walking each person to their recorded end among the others
// replayed as recorded; scored by the average and final displacement errors (ADE, FDE).
#include <array>
#include <string_view>
#include <vector>

#include "humans/locomotion.hpp"
#include "humans/recorded_trajectories.hpp"

namespace hrisim::humans {

/// Annotations observed in a window: 3.2 s, as Social-GAN (Gupta et al. 2018), Trajectron++ (Salzmann
/// et al. 2020) and the constant-velocity study of Schöller et al. (2020) evaluate ETH/UCY.
inline constexpr int kObservedFrames = 8;
/// Annotations predicted after them: 4.8 s, the same protocol.
inline constexpr int kPredictedFrames = 12;

enum class Predictor {
  constant_velocity,  ///< the last observed velocity (the last two observed positions / 0.4 s), kept
  orca,               ///< hrisim's ORCA among the others replayed
  social_force,       ///< hrisim's social force among the others replayed
};
inline constexpr std::array<Predictor, 3> kPredictors = {Predictor::constant_velocity, Predictor::orca, Predictor::social_force};

/// "constant_velocity", "orca", "social_force".
std::string_view to_string(Predictor predictor);

/// What the crowd models predict with: a calibrated parameter set is evaluated by giving it here.
struct PredictionSettings {
  CrowdParams crowd;  ///< the crowd models' settings: hrisim's defaults, or a preset's
  double dt = 0.0;                      ///< s, the simulation step; required (hrisim's scenarios default to 1/60)
  double radius = CrowdAgent{}.radius;  ///< m, everyone's disc, hrisim's default person's
};

/// A predictor's errors over every window of a file, m; NaN when the file has no window.
struct PredictionErrors {
  Predictor predictor = Predictor::constant_velocity;
  std::size_t windows = 0;
  double ade = 0.0;  ///< mean over windows of the mean displacement over the predicted frames
  double fde = 0.0;  ///< mean over windows of the displacement at the last predicted frame
  std::array<double, kPredictedFrames> by_frame{};  ///< mean over windows of the displacement at each predicted frame
};

/// A window: one person seen in kObservedFrames + kPredictedFrames consecutive annotations
/// (kEthUcyFrameStep apart). Every such run of every person is one, sliding by one annotation.
struct PredictionWindow {
  std::size_t track = 0;  ///< index in RecordedTrajectories::tracks
  std::size_t first = 0;  ///< index of its first sample in the track
};

/// Every window of `trajectories`, by track, then by first frame.
std::vector<PredictionWindow> prediction_windows(const RecordedTrajectories& trajectories);

/// Runs the protocol for one predictor (docs/crowd-validation.md): in every window the person's
/// kPredictedFrames positions, each compared with the recorded one. The crowd models start the person
/// at their last observed position with their last observed velocity and walk them towards their
/// recorded last position at their mean observed speed, everyone else present replayed as recorded
/// (positions interpolated between annotations, velocities the recorded ones), without walls.
/// Throws core::Error(bad_request) when settings.dt is not positive.
PredictionErrors evaluate_predictor(const RecordedTrajectories& trajectories, Predictor predictor, const PredictionSettings& settings);

}  // namespace hrisim::humans
