#pragma once
// Runs the episodes of runs on worker threads, several episodes (of one run or of several) at once,
// and stores each episode in one transaction as it ends. A run is queued, then running, then
// finished (failed when an episode ended in error, cancelled when asked to stop). Episodes in flight
// when the process dies are lost; the run is marked interrupted at the next server start.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "runs/episode.hpp"
#include "storage/store.hpp"

namespace hrisim::runs {

struct RunSpec {
  std::string id;  ///< a new unguessable one when empty; a shard's is its run's (runs::shard_run_id)
  std::string scenario_id;
  std::shared_ptr<const scenario::Model> model;  ///< with the run's controller applied
  std::vector<std::uint64_t> seeds;
  std::string controller;  ///< its type, as listed
  nlohmann::json config;   ///< stored with the run: seeds, gates, controller, max time, provenance
  std::optional<double> max_time;
  std::vector<std::pair<double, std::string>> requests;  ///< scripted robot requests (time, routine)
  bool baseline_without_robot = false;                    ///< see EpisodeOptions
  std::string owner;  ///< who started it (a token's name); empty without owners
  std::string name;   ///< what its user calls it, its tags and notes (editable later)
  std::vector<std::string> tags;
  std::string notes;
};

class Executor {
 public:
  /// Called on a worker thread after an episode is stored (or, for an error, after it is recorded).
  using EpisodeListener = std::function<void(const std::string& run_id, const storage::EpisodeRecord& episode)>;

  /// `recording_memory` bounds the recordings of the episodes in flight, together with whatever else
  /// shares it (see EpisodeOptions); none: unbounded.
  Executor(storage::Store& store, unsigned threads, EpisodeListener listener = nullptr, core::MemoryBudget* recording_memory = nullptr);
  /// Stops the workers; episodes in flight are abandoned, unstored, and their runs stay as they are.
  ~Executor();
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;

  /// Stores the run as queued and queues one episode per seed; returns the stored run.
  storage::RunRecord submit(RunSpec spec);
  /// Stops a queued or running run: queued episodes are dropped, running ones stop at their next step
  /// unstored. False when the run is not active here.
  bool cancel(const std::string& run_id);
  /// Seeds of an active run that are not done: "queued", "running", or "cancelled" once the run is
  /// being cancelled (stored episodes may be listed too: the store's word wins); empty when the run
  /// is not active here.
  std::map<std::uint64_t, std::string> live(const std::string& run_id) const;
  /// Blocks until the run is no longer active.
  void wait(const std::string& run_id);

 private:
  struct ActiveRun;
  struct Job {
    std::shared_ptr<ActiveRun> run;
    std::uint64_t seed = 0;
  };
  void work();
  void run_job(const Job& job);
  void finish_job(ActiveRun& run, std::uint64_t seed);

  storage::Store& store_;
  EpisodeListener listener_;
  core::MemoryBudget* recording_memory_;
  mutable std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<Job> queue_;
  std::map<std::string, std::shared_ptr<ActiveRun>> active_;
  std::atomic<bool> stopping_{false};
  std::vector<std::thread> workers_;
};

}  // namespace hrisim::runs
