#pragma once
// Videos of stored episodes, filmed on a thread of their own, one at a time (the renderer is software
// OpenGL and takes a core): a queue of jobs with their progress, the files they wrote in a folder of
// the server's, and the finished ones kept until more than kMaxVideoJobs are there.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "runs/executor.hpp"
#include "runs/video.hpp"

namespace hrisim::http {

/// Most video jobs kept, queued and finished together; the oldest finished go first.
inline constexpr std::size_t kMaxVideoJobs = 32;
/// Largest frame a video job may ask for, each way (the command line's hrisim render takes more).
inline constexpr int kMaxVideoSide = 1920;

/// What a video job films: the episode, its replay and how it is filmed.
struct VideoRequest {
  storage::EpisodeRecord episode;
  runs::RunSpec spec;  ///< the episode's run again: its scenario record, controller, time limit and requests
  runs::VideoOptions options;
  std::string format = "mp4";  ///< mp4 (H.264) or webm (VP8)
  runs::VideoSize size;        ///< of the frames, as runs::video_size found it
};

class VideoJobs {
 public:
  /// Writes the videos in `folder` (made when missing, removed with everything in it at the end).
  explicit VideoJobs(std::filesystem::path folder);
  ~VideoJobs();
  VideoJobs(const VideoJobs&) = delete;
  VideoJobs& operator=(const VideoJobs&) = delete;

  /// The job filming `request`: the one there is for the same episode and options unless it failed or
  /// was cancelled (`created` false), else a new one at the end of the queue. Throws
  /// core::Error(unavailable) when kMaxVideoJobs are queued or filming.
  nlohmann::json submit(VideoRequest request, bool& created);
  /// The job's status: queued, filming, done, failed or cancelled, its progress in ticks, and when done
  /// the video's facts; nullopt for no job of that id.
  std::optional<nlohmann::json> status(const std::string& id) const;
  /// The episode a job films, for deciding who may see it.
  std::optional<std::string> episode_of(const std::string& id) const;

  struct File {
    std::filesystem::path path;
    std::string content_type;
    std::string name;  ///< to save it under
  };
  /// The finished video; core::Error(conflict) while the job is not done.
  File file(const std::string& id) const;
  /// Cancels the job if it runs and forgets it and its file; false for no job of that id.
  bool remove(const std::string& id);

 private:
  struct Job;
  void work();
  nlohmann::json status_of(const Job& job) const;
  void make_room();

  std::filesystem::path folder_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<Job>> jobs_;  ///< in the order they were asked for
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace hrisim::http
