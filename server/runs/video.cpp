#include "runs/video.hpp"

#include <cmath>
#include <optional>

#include "core/error.hpp"
#include "episode/episode.hpp"
#include "render/scene_renderer.hpp"
#include "render/video_writer.hpp"
#include "runs/episode.hpp"
#include "sim/camera_scene.hpp"

namespace hrisim::runs {
namespace {

/// The camera as `options` asks for it, each side rounded down to an even number of pixels: H.264 and
/// VP8 store colour at half resolution, and FFmpeg would crop an odd side.
sim::CameraInfo filming_camera(const sim::Session& session, const VideoOptions& options) {
  sim::CameraInfo info = sim::camera_of(session, options.camera, options.width, options.height);
  const int width = info.camera.width, height = info.camera.height;
  if (width % 2 != 0 || height % 2 != 0) info = sim::camera_of(session, options.camera, width - width % 2, height - height % 2);
  return info;
}

}  // namespace

VideoSize video_size(const RunSpec& spec, std::uint64_t seed, const VideoOptions& options) {
  const episode::Episode first(spec.model, seed);
  try {
    const render::Camera camera = filming_camera(first.session(), options).camera;
    return {camera.width, camera.height};
  } catch (const core::Error& e) {
    if (e.code() != core::ErrorCode::not_found) throw;
    throw core::Error(core::ErrorCode::bad_request, std::string("camera: ") + e.what(), {{"pointer", "/camera"}});
  }
}

VideoResult render_episode_video(const RunSpec& spec, const storage::EpisodeRecord& stored, const std::filesystem::path& out,
                                 const VideoOptions& options, const std::function<void(std::int64_t tick)>& progress,
                                 const std::atomic<bool>* cancel) {
  // A frame every `stride` ticks, as close to the asked rate as whole ticks allow.
  const auto stride = std::max<std::int64_t>(1, std::llround(1.0 / (spec.model->dt * options.fps)));
  VideoResult result;
  result.fps = 1.0 / (static_cast<double>(stride) * spec.model->dt);
  std::optional<render::VideoWriter> video;
  EpisodeOptions episode;
  episode.max_time = spec.max_time;
  episode.requests = spec.requests;
  episode.cancel = cancel;
  episode.observe = [&](const sim::Session& session) {
    const std::int64_t tick = session.state().tick;
    if (tick % stride != 0) return;
    const sim::CameraInfo camera = filming_camera(session, options);
    if (!video) video.emplace(out, result.fps, camera.camera.width, camera.camera.height);
    video->write(render::render_on_this_thread(sim::scene_for(session, camera), camera.camera).colour);
    if (progress) progress(tick);
  };
  EpisodeResult replay = run_episode(spec.model, stored.seed, episode);
  if (replay.cancelled) {
    video.reset();
    std::filesystem::remove(out);
    result.cancelled = true;
    return result;
  }
  if (!video) throw core::Error(core::ErrorCode::internal, "the episode has no frame to write");
  video->close();
  result.frames = video->frames();
  result.codec = video->codec();
  result.replay = std::move(replay.record);
  // Episodes stored before the final state's hash was kept are compared by their end alone.
  result.matches_stored_episode = result.replay.ticks == stored.ticks && result.replay.termination_reason == stored.termination_reason &&
                                  (stored.state_hash.empty() || result.replay.state_hash == stored.state_hash);
  return result;
}

}  // namespace hrisim::runs
