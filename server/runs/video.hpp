#pragma once
// A stored episode played again and filmed: the same scenario record, seed, controller, time limit and
// requests (bit for bit the same episode), what one camera sees every few ticks written to a video.
// One function for `hrisim render` and the server's video jobs.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "runs/executor.hpp"
#include "storage/store.hpp"

namespace hrisim::runs {

/// Frames per second of an episode's video unless asked otherwise, and the most a video may ask for.
inline constexpr int kDefaultVideoFps = 25;
inline constexpr int kMaxVideoFps = 120;
/// The camera that films the whole scene from above.
inline constexpr const char* kDefaultVideoCamera = "overview";

struct VideoOptions {
  std::string camera = kDefaultVideoCamera;  ///< "overview", "follow", or ROBOT.SENSOR
  int fps = kDefaultVideoFps;
  int width = 0, height = 0;  ///< the camera's own size when 0; one alone scales the other
};

struct VideoSize {
  int width = 0, height = 0;
};

/// The size of the frames `options` asks for, from the episode's first state; throws
/// core::Error(bad_request) naming the cameras there are when `options.camera` is none of them.
VideoSize video_size(const RunSpec& spec, std::uint64_t seed, const VideoOptions& options);

struct VideoResult {
  bool cancelled = false;
  int frames = 0;
  double fps = 0.0;     ///< what the video plays at: whole ticks between frames, so close to the asked
  std::string codec;    ///< as VideoWriter names it
  storage::EpisodeRecord replay;  ///< how the replay ended (ticks, termination, state hash)
  bool matches_stored_episode = false;
};

/// Replays `stored` (an episode of `spec`'s scenario and seed) into `out` (.mp4 or .webm or .avi).
/// `progress` gets each tick filmed; `cancel` stops it at the next tick (the file is then removed).
VideoResult render_episode_video(const RunSpec& spec, const storage::EpisodeRecord& stored, const std::filesystem::path& out,
                                 const VideoOptions& options, const std::function<void(std::int64_t tick)>& progress = {},
                                 const std::atomic<bool>* cancel = nullptr);

}  // namespace hrisim::runs
