#include "humans/trajectory_prediction.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"

namespace hrisim::humans {
namespace {

const std::string kSourceDir = HRISIM_SOURCE_DIR;
const std::string kShared = HRISIM_SHARED_DIR;
/// hrisim's scenarios' step (scenario::kDefaultDt; humans does not see the scenario module).
constexpr double kSceneStep = 1.0 / 60.0;

PredictionSettings defaults() {
  PredictionSettings settings;
  settings.dt = kSceneStep;
  return settings;
}

/// A person walking a straight line: `count` annotations from `frame`, `step` apart in space.
RecordedTrack straight(long long person, long long frame, int count, const Vec2& start, const Vec2& step) {
  RecordedTrack track{person, {}};
  for (int k = 0; k < count; ++k) track.samples.push_back({frame + k * kEthUcyFrameStep, start + k * step});
  return track;
}

RecordedTrajectories read_file(const std::string& path) {
  std::ifstream input(path);
  EXPECT_TRUE(input) << path;
  return read_eth_ucy(input, path);
}

TEST(TrajectoryPrediction, EveryRunOfTwentyConsecutiveAnnotationsIsAWindow) {
  RecordedTrajectories trajectories;
  trajectories.tracks.push_back(straight(1, 0, 24, {0, 0}, {0.5, 0}));
  RecordedTrack gap = straight(2, 0, 25, {0, 5}, {0.5, 0});
  gap.samples.erase(gap.samples.begin() + 10);  // runs of 10 and 14: no window
  trajectories.tracks.push_back(gap);
  RecordedTrack sparse = straight(3, 0, 20, {0, 9}, {0.5, 0});
  for (RecordedSample& sample : sparse.samples) sample.frame *= 2;  // 20 frames apart: not consecutive
  trajectories.tracks.push_back(sparse);
  trajectories.tracks.push_back(straight(4, 1000, 20, {0, 12}, {0.5, 0}));
  const std::vector<PredictionWindow> windows = prediction_windows(trajectories);
  ASSERT_EQ(windows.size(), 6u);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(windows[k].track, 0u);
    EXPECT_EQ(windows[k].first, k);
  }
  EXPECT_EQ(windows[5].track, 3u);
  EXPECT_EQ(windows[5].first, 0u);
}

// A person who turns a right angle at their last observed position: constant velocity walks on
// straight, j·√2 m from where they are at the j-th predicted annotation.
TEST(TrajectoryPrediction, ConstantVelocityKeepsTheLastObservedStep) {
  RecordedTrajectories trajectories;
  RecordedTrack turning = straight(1, 0, 20, {0, 0}, {1, 0});
  for (int k = kObservedFrames; k < 20; ++k) turning.samples[static_cast<std::size_t>(k)].position = Vec2(7, k - 7);
  trajectories.tracks.push_back(turning);
  const PredictionErrors errors = evaluate_predictor(trajectories, Predictor::constant_velocity, defaults());
  EXPECT_EQ(errors.windows, 1u);
  EXPECT_NEAR(errors.ade, 6.5 * std::sqrt(2.0), 1e-12);  // the mean of 1…12, times √2
  EXPECT_NEAR(errors.fde, 12 * std::sqrt(2.0), 1e-12);
  for (int j = 0; j < kPredictedFrames; ++j) EXPECT_NEAR(errors.by_frame[static_cast<std::size_t>(j)], (j + 1) * std::sqrt(2.0), 1e-12);
}

// Alone and walking straight at a constant speed, each predictor walks the recorded line.
TEST(TrajectoryPrediction, AWalkerAloneIsPredictedByEveryPredictor) {
  RecordedTrajectories trajectories;
  trajectories.tracks.push_back(straight(1, 0, 23, {-3, 1}, {0.3, 0.4}));
  for (const Predictor predictor : kPredictors) {
    const PredictionErrors errors = evaluate_predictor(trajectories, predictor, defaults());
    EXPECT_EQ(errors.windows, 4u) << to_string(predictor);
    EXPECT_LT(errors.ade, 1e-9) << to_string(predictor);
    EXPECT_LT(errors.fde, 1e-9) << to_string(predictor);
  }
}

// Two people recorded passing 0.8 m apart, centre to centre, walking straight at 1.3 m/s: constant
// velocity is exact; a crowd model's person, avoiding the other replayed, deviates (0.8 m is less than
// two radii and the 0.3 m margin between people). Without margin ORCA's discs (0.6 m together) pass
// clear and its person walks straight; the social force needs its interaction term turned off too.
TEST(TrajectoryPrediction, PeoplePassingCloseMakeTheCrowdModelsDeviate) {
  RecordedTrajectories trajectories;
  trajectories.tracks.push_back(straight(2, 0, 20, {0, 0.4}, {0.52, 0}));
  trajectories.tracks.push_back(straight(3, 0, 20, {9.88, -0.4}, {-0.52, 0}));
  EXPECT_LT(evaluate_predictor(trajectories, Predictor::constant_velocity, defaults()).ade, 1e-9);
  for (const Predictor model : {Predictor::orca, Predictor::social_force}) {
    const PredictionErrors errors = evaluate_predictor(trajectories, model, defaults());
    EXPECT_EQ(errors.windows, 2u);
    EXPECT_GT(errors.ade, 0.02) << to_string(model);
  }
  PredictionSettings no_margin = defaults();
  no_margin.crowd.personal_space = {0.0, 0.0};
  EXPECT_LT(evaluate_predictor(trajectories, Predictor::orca, no_margin).ade, 1e-9);
  EXPECT_GT(evaluate_predictor(trajectories, Predictor::social_force, no_margin).ade, 0.01);
  no_margin.crowd.social_force.social_factor = 0.0;
  EXPECT_LT(evaluate_predictor(trajectories, Predictor::social_force, no_margin).ade, 1e-9);
  // Larger discs collide again.
  no_margin.radius = 0.45;
  EXPECT_GT(evaluate_predictor(trajectories, Predictor::orca, no_margin).ade, 0.02);
}

TEST(TrajectoryPrediction, AStepOutsideTheAnnotationIntervalIsRefused) {
  RecordedTrajectories trajectories;
  PredictionSettings settings;
  EXPECT_THROW(evaluate_predictor(trajectories, Predictor::orca, settings), core::Error);  // no step given
  settings.dt = 0.5;
  EXPECT_THROW(evaluate_predictor(trajectories, Predictor::orca, settings), core::Error);
  settings.dt = 0.4;
  EXPECT_TRUE(std::isnan(evaluate_predictor(trajectories, Predictor::orca, settings).ade)) << "no window: no mean";
}

// The project's fixture (tests/fixtures/trajectories/passing.txt): a walker alone (5 windows), the pair
// passing close (1 window each) and a walker with an annotation missing (none).
TEST(TrajectoryPrediction, TheFixtureFile) {
  const RecordedTrajectories trajectories = read_file(kSourceDir + "/tests/fixtures/trajectories/passing.txt");
  const PredictionErrors constant = evaluate_predictor(trajectories, Predictor::constant_velocity, defaults());
  EXPECT_EQ(constant.windows, 7u);
  EXPECT_LT(constant.ade, 1e-9);
  EXPECT_LT(constant.fde, 1e-9);
  for (const Predictor model : {Predictor::orca, Predictor::social_force}) {
    const PredictionErrors errors = evaluate_predictor(trajectories, model, defaults());
    EXPECT_EQ(errors.windows, 7u);
    EXPECT_GT(errors.ade, 0.01) << to_string(model);
    EXPECT_LT(errors.ade, 0.5) << to_string(model);
  }
}

// The ETH and ZARA01 test sets as Trajectron++ publishes them (reference data in ../shared/external,
// read in place), every window. Constant velocity measures 0.43 / 0.95 m (ADE / FDE) on ZARA01, inside
// the band the literature gives for it (0.3–0.5 / 0.7–1.0 m), and 1.08 / 2.28 m on ETH, the hardest set
// (its people move 0.98 m between annotations, median, against ZARA01's 0.46: 2.4 m/s at the 0.4 s the
// set states, a timing Trajectron++'s issue 67 disputes); the band there is the measured value less
// 25 %, up to Social-GAN's linear baseline on the same file (1.33 / 2.94 m, Gupta et al. 2018, table 1). A window miscounted or an
// error averaged wrongly leaves the bands. The crowd models are given each person's recorded end: they
// must end nearer it than constant velocity does, and stay a prediction on the way (below 1.5 times
// constant velocity's ADE).
struct RealSet {
  const char* file;
  std::size_t windows;
  double ade_low, ade_high, fde_low, fde_high;
};

TEST(TrajectoryPrediction, TheEthAndZara01TestSets) {
  const std::string folder = kShared + "/external/trajectories";
  if (!std::filesystem::exists(folder + "/biwi_eth.txt")) {
    GTEST_SKIP() << "no ../shared/external/trajectories beside the project: the project's own fixture "
                    "tests/fixtures/trajectories/passing.txt covers these paths (TrajectoryPrediction.TheFixtureFile)";
  }
  for (const RealSet& set : {RealSet{"biwi_eth.txt", 364, 0.81, 1.33, 1.71, 2.94}, RealSet{"crowds_zara01.txt", 2356, 0.3, 0.5, 0.7, 1.0}}) {
    const RecordedTrajectories trajectories = read_file(folder + "/" + set.file);
    const PredictionErrors constant = evaluate_predictor(trajectories, Predictor::constant_velocity, defaults());
    EXPECT_EQ(constant.windows, set.windows) << set.file;
    EXPECT_GT(constant.ade, set.ade_low) << set.file;
    EXPECT_LT(constant.ade, set.ade_high) << set.file;
    EXPECT_GT(constant.fde, set.fde_low) << set.file;
    EXPECT_LT(constant.fde, set.fde_high) << set.file;
    for (const Predictor model : {Predictor::orca, Predictor::social_force}) {
      const PredictionErrors errors = evaluate_predictor(trajectories, model, defaults());
      EXPECT_EQ(errors.windows, set.windows);
      EXPECT_LT(errors.ade, 1.5 * constant.ade) << set.file << " " << to_string(model);
      EXPECT_LT(errors.fde, constant.fde) << set.file << " " << to_string(model);
    }
  }
}

}  // namespace
}  // namespace hrisim::humans
