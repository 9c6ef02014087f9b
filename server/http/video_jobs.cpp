#include "http/video_jobs.hpp"

#include <algorithm>
#include <chrono>

#include "core/error.hpp"
#include "core/sha256.hpp"

namespace hrisim::http {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct VideoJobs::Job {
  std::string id;
  VideoRequest request;
  std::filesystem::path path;
  std::string status = "queued";  ///< queued, filming, done, failed or cancelled; under the mutex
  std::atomic<std::int64_t> tick{0};
  std::atomic<bool> cancel{false};
  Clock::time_point started, finished;
  runs::VideoResult result;
  std::uintmax_t bytes = 0;
  std::string error;

  bool finished_or_failed() const { return status != "queued" && status != "filming"; }
};

VideoJobs::VideoJobs(std::filesystem::path folder) : folder_(std::move(folder)) {
  std::filesystem::create_directories(folder_);
  worker_ = std::thread([this] { work(); });
}

VideoJobs::~VideoJobs() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    for (const auto& job : jobs_) job->cancel = true;
  }
  wake_.notify_all();
  worker_.join();
  std::error_code ignored;
  std::filesystem::remove_all(folder_, ignored);
}

json VideoJobs::submit(VideoRequest request, bool& created) {
  const runs::VideoOptions& options = request.options;
  const std::string id = "v" + core::sha256_hex(request.episode.id + "\n" + options.camera + "\n" + std::to_string(options.fps) + "\n" +
                                                std::to_string(options.width) + "\n" + std::to_string(options.height) + "\n" + request.format)
                                   .substr(0, 20);
  std::lock_guard lock(mutex_);
  const auto same = std::find_if(jobs_.begin(), jobs_.end(), [&](const auto& job) { return job->id == id; });
  if (same != jobs_.end() && (*same)->status != "failed" && (*same)->status != "cancelled") {
    created = false;
    return status_of(**same);
  }
  if (same != jobs_.end()) jobs_.erase(same);
  make_room();
  auto job = std::make_shared<Job>();
  job->id = id;
  job->path = folder_ / (id + "." + request.format);
  job->request = std::move(request);
  jobs_.push_back(job);
  created = true;
  wake_.notify_all();
  return status_of(*job);
}

void VideoJobs::make_room() {
  while (jobs_.size() >= kMaxVideoJobs) {
    const auto oldest = std::find_if(jobs_.begin(), jobs_.end(), [](const auto& job) { return job->finished_or_failed(); });
    if (oldest == jobs_.end()) {
      throw core::Error(core::ErrorCode::unavailable, std::to_string(jobs_.size()) +
                                                          " videos are queued or filming: wait for one, or cancel one (DELETE /api/v1/videos/{id})");
    }
    std::error_code ignored;
    std::filesystem::remove((*oldest)->path, ignored);
    jobs_.erase(oldest);
  }
}

void VideoJobs::work() {
  std::unique_lock lock(mutex_);
  while (true) {
    std::shared_ptr<Job> job;
    wake_.wait(lock, [&] {
      if (stopping_) return true;
      const auto queued = std::find_if(jobs_.begin(), jobs_.end(), [](const auto& j) { return j->status == "queued"; });
      if (queued != jobs_.end()) job = *queued;
      return job != nullptr;
    });
    if (stopping_) return;
    job->status = "filming";
    job->started = Clock::now();
    lock.unlock();
    std::string error;
    runs::VideoResult result;
    try {
      result = runs::render_episode_video(job->request.spec, job->request.episode, job->path, job->request.options,
                                          [&job](std::int64_t tick) { job->tick = tick; }, &job->cancel);
    } catch (const std::exception& e) {
      error = e.what();
    }
    std::error_code ignored;
    const std::uintmax_t bytes = error.empty() && !result.cancelled ? std::filesystem::file_size(job->path, ignored) : 0;
    lock.lock();
    job->finished = Clock::now();
    job->result = std::move(result);
    job->bytes = bytes;
    job->error = error;
    job->status = !error.empty() ? "failed" : job->result.cancelled ? "cancelled" : "done";
    // A job removed while it was filming leaves no file behind.
    if (job->status != "done" || job->cancel) std::filesystem::remove(job->path, ignored);
  }
}

json VideoJobs::status_of(const Job& job) const {
  const runs::VideoOptions& options = job.request.options;
  const std::int64_t total = job.request.episode.ticks;
  const std::int64_t tick = job.status == "done" ? total : job.tick.load();
  const auto elapsed = job.status == "queued"    ? Clock::duration::zero()
                       : job.status == "filming" ? Clock::now() - job.started
                                                 : job.finished - job.started;
  json status = {{"id", job.id},
                 {"episode", job.request.episode.id},
                 {"camera", options.camera},
                 {"fps", options.fps},
                 {"width", job.request.size.width},
                 {"height", job.request.size.height},
                 {"format", job.request.format},
                 {"status", job.status},
                 {"progress", {{"tick", tick}, {"ticks", total}, {"fraction", total > 0 ? std::min(1.0, static_cast<double>(tick) / static_cast<double>(total)) : 0.0}}},
                 {"elapsed", std::chrono::duration<double>(elapsed).count()}};
  if (job.status == "done") {
    status["file"] = "/api/v1/videos/" + job.id + "/file";
    status["bytes"] = job.bytes;
    status["frames"] = job.result.frames;
    status["video_fps"] = job.result.fps;
    status["codec"] = job.result.codec;
    status["matches_stored_episode"] = job.result.matches_stored_episode;
  }
  if (job.status == "failed") status["error"] = job.error;
  return status;
}

std::optional<json> VideoJobs::status(const std::string& id) const {
  std::lock_guard lock(mutex_);
  for (const auto& job : jobs_) {
    if (job->id == id) return status_of(*job);
  }
  return std::nullopt;
}

std::optional<std::string> VideoJobs::episode_of(const std::string& id) const {
  std::lock_guard lock(mutex_);
  for (const auto& job : jobs_) {
    if (job->id == id) return job->request.episode.id;
  }
  return std::nullopt;
}

VideoJobs::File VideoJobs::file(const std::string& id) const {
  std::lock_guard lock(mutex_);
  for (const auto& job : jobs_) {
    if (job->id != id) continue;
    if (job->status != "done") {
      throw core::Error(core::ErrorCode::conflict, "video " + id + " is " + job->status + ", not done" + (job->error.empty() ? "" : ": " + job->error),
                        {{"id", id}, {"status", job->status}});
    }
    const std::string& format = job->request.format;
    return {job->path, format == "webm" ? "video/webm" : "video/mp4", job->request.episode.id + "-" + job->request.options.camera + "." + format};
  }
  throw core::Error(core::ErrorCode::not_found, "no video '" + id + "'", {{"id", id}});
}

bool VideoJobs::remove(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto found = std::find_if(jobs_.begin(), jobs_.end(), [&](const auto& job) { return job->id == id; });
  if (found == jobs_.end()) return false;
  (*found)->cancel = true;
  if ((*found)->status != "filming") {
    std::error_code ignored;
    std::filesystem::remove((*found)->path, ignored);
  }
  jobs_.erase(found);
  return true;
}

}  // namespace hrisim::http
