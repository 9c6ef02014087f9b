#include "humans/trajectory_prediction.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>

#include "core/error.hpp"

namespace hrisim::humans {
namespace {

constexpr int kWindowFrames = kObservedFrames + kPredictedFrames;
/// The shortest simulation step taken, s: finer steps only cost time (400 per annotation here).
constexpr double kMinStep = 0.001;

using Prediction = std::array<Vec2, kPredictedFrames>;

/// Who walks where between two annotations: everyone annotated at a frame and at the next one.
class Replay {
 public:
  explicit Replay(const RecordedTrajectories& trajectories) : trajectories_(trajectories) {
    for (std::size_t t = 0; t < trajectories.tracks.size(); ++t) {
      const std::vector<RecordedSample>& samples = trajectories.tracks[t].samples;
      for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
        if (samples[k + 1].frame - samples[k].frame == kEthUcyFrameStep) walking_from_[samples[k].frame].emplace_back(t, k);
      }
    }
  }

  /// Everyone but track `self` walking from `frame` to the next annotation, appended to `agents` at the
  /// start of that walk with its recorded velocity, and to `starts` their positions at the start.
  void walkers(long long frame, std::size_t self, double radius, std::vector<CrowdAgent>& agents, std::vector<Vec2>& starts) const {
    const auto found = walking_from_.find(frame);
    if (found == walking_from_.end()) return;
    for (const auto& [track, k] : found->second) {
      if (track == self) continue;
      const std::vector<RecordedSample>& samples = trajectories_.tracks[track].samples;
      CrowdAgent other;
      other.position = samples[k].position;
      other.velocity = (samples[k + 1].position - samples[k].position) / kEthUcyFrameInterval;
      other.radius = radius;
      other.replayed = true;
      agents.push_back(other);
      starts.push_back(other.position);
    }
  }

 private:
  const RecordedTrajectories& trajectories_;
  std::unordered_map<long long, std::vector<std::pair<std::size_t, std::size_t>>> walking_from_;  ///< frame → (track, sample)
};

Prediction constant_velocity(const RecordedSample* window) {
  const Vec2 last = window[kObservedFrames - 1].position;
  const Vec2 step = last - window[kObservedFrames - 2].position;
  Prediction prediction;
  for (int k = 0; k < kPredictedFrames; ++k) prediction[static_cast<std::size_t>(k)] = last + (k + 1) * step;
  return prediction;
}

/// Towards `goal` at `speed`, slowing so as to stop on it within a step.
Vec2 towards(const Vec2& position, const Vec2& goal, double speed, double step) {
  const Vec2 offset = goal - position;
  const double distance = offset.norm();
  if (distance <= 0.0) return Vec2::Zero();
  return offset / distance * std::min(speed, distance / step);
}

/// What one crowd model predicts for the person of `track` in the window starting at sample `first`.
class CrowdPrediction {
 public:
  CrowdPrediction(const Replay& replay, const PredictionSettings& settings, LocalAvoidance model)
      : replay_(replay),
        settings_(settings),
        model_(model),
        crowd_(settings.crowd.orca, settings.crowd.social_force, settings.crowd.personal_space, settings.crowd.headway),
        steps_(static_cast<int>(std::ceil(kEthUcyFrameInterval / settings.dt - 1e-9))),
        step_(kEthUcyFrameInterval / steps_) {}

  Prediction operator()(std::size_t track, const RecordedSample* window) {
    double observed_path = 0.0;
    for (int k = 1; k < kObservedFrames; ++k) observed_path += (window[k].position - window[k - 1].position).norm();
    const double speed = observed_path / ((kObservedFrames - 1) * kEthUcyFrameInterval);
    const Vec2 goal = window[kWindowFrames - 1].position;
    CrowdAgent self;
    self.position = window[kObservedFrames - 1].position;
    self.velocity = (self.position - window[kObservedFrames - 2].position) / kEthUcyFrameInterval;
    self.radius = settings_.radius;
    self.max_speed = speed * kMaxSpeedFactor;
    self.avoidance = model_;
    Prediction prediction;
    for (int j = 0; j < kPredictedFrames; ++j) {
      agents_.assign(1, self);
      starts_.assign(1, self.position);
      replay_.walkers(window[kObservedFrames - 1].frame + static_cast<long long>(j) * kEthUcyFrameStep, track, settings_.radius,
                      agents_, starts_);
      for (int s = 0; s < steps_; ++s) {
        for (std::size_t k = 1; k < agents_.size(); ++k) agents_[k].position = starts_[k] + agents_[k].velocity * (s * step_);
        self.preferred_velocity = towards(self.position, goal, speed, step_);
        agents_[0] = self;
        crowd_.compute_velocities(agents_, no_walls, step_, velocities_);
        self.velocity = velocities_[0];
        self.position += self.velocity * step_;
      }
      prediction[static_cast<std::size_t>(j)] = self.position;
    }
    return prediction;
  }

 private:
  static std::optional<Vec2> no_walls(const Vec2&, double) { return std::nullopt; }

  const Replay& replay_;
  const PredictionSettings& settings_;
  LocalAvoidance model_;
  Crowd crowd_;
  int steps_;    ///< simulation steps per annotation
  double step_;  ///< s, the annotation interval divided into them
  std::vector<CrowdAgent> agents_;
  std::vector<Vec2> starts_;  ///< where each agent was at the annotation this walk started from
  std::vector<Vec2> velocities_;
};

}  // namespace

std::string_view to_string(Predictor predictor) {
  switch (predictor) {
    case Predictor::constant_velocity: return "constant_velocity";
    case Predictor::orca: return "orca";
    case Predictor::social_force: return "social_force";
  }
  return "unknown";
}

std::vector<PredictionWindow> prediction_windows(const RecordedTrajectories& trajectories) {
  std::vector<PredictionWindow> windows;
  for (std::size_t t = 0; t < trajectories.tracks.size(); ++t) {
    const std::vector<RecordedSample>& samples = trajectories.tracks[t].samples;
    std::size_t run = 1;  // consecutive annotations ending at sample k
    for (std::size_t k = 1; k < samples.size(); ++k) {
      run = samples[k].frame - samples[k - 1].frame == kEthUcyFrameStep ? run + 1 : 1;
      if (run >= static_cast<std::size_t>(kWindowFrames)) windows.push_back({t, k + 1 - kWindowFrames});
    }
  }
  return windows;
}

PredictionErrors evaluate_predictor(const RecordedTrajectories& trajectories, Predictor predictor, const PredictionSettings& settings) {
  if (!(settings.dt >= kMinStep && settings.dt <= kEthUcyFrameInterval)) {
    throw core::Error(core::ErrorCode::bad_request, "the simulation step must be " + std::to_string(kMinStep) + " to " +
                                                        std::to_string(kEthUcyFrameInterval) + " s, not " + std::to_string(settings.dt));
  }
  const Replay replay(trajectories);
  CrowdPrediction crowd(replay, settings, predictor == Predictor::social_force ? LocalAvoidance::social_force : LocalAvoidance::orca);
  PredictionErrors errors;
  errors.predictor = predictor;
  for (const PredictionWindow& window : prediction_windows(trajectories)) {
    const RecordedSample* samples = &trajectories.tracks[window.track].samples[window.first];
    const Prediction prediction = predictor == Predictor::constant_velocity ? constant_velocity(samples) : crowd(window.track, samples);
    for (int k = 0; k < kPredictedFrames; ++k) {
      errors.by_frame[static_cast<std::size_t>(k)] += (prediction[static_cast<std::size_t>(k)] - samples[kObservedFrames + k].position).norm();
    }
    ++errors.windows;
  }
  const double windows = errors.windows > 0 ? static_cast<double>(errors.windows) : std::numeric_limits<double>::quiet_NaN();
  // The mean over windows of each window's mean is the mean of the frames' means.
  for (double& displacement : errors.by_frame) {
    displacement /= windows;
    errors.ade += displacement / kPredictedFrames;
  }
  errors.fde = errors.by_frame.back();
  return errors;
}

}  // namespace hrisim::humans
