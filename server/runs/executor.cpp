#include "runs/executor.hpp"

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"
#include "core/random.hpp"

namespace hrisim::runs {

struct Executor::ActiveRun {
  storage::RunRecord record;
  RunSpec spec;
  std::atomic<bool> cancelled{false};
  std::set<std::uint64_t> running;  ///< guarded by the executor's mutex
  std::size_t unfinished = 0;       ///< episodes queued or running; guarded by the executor's mutex
  bool started = false;
  bool any_error = false;
};

Executor::Executor(storage::Store& store, unsigned threads, EpisodeListener listener, core::MemoryBudget* recording_memory)
    : store_(store), listener_(std::move(listener)), recording_memory_(recording_memory) {
  for (unsigned i = 0; i < std::max(1u, threads); ++i) workers_.emplace_back([this] { work(); });
}

Executor::~Executor() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    for (auto& [id, run] : active_) run->cancelled = true;
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

storage::RunRecord Executor::submit(RunSpec spec) {
  auto run = std::make_shared<ActiveRun>();
  run->record = store_.put_run({spec.id.empty() ? core::unguessable_id('r') : spec.id, spec.scenario_id, spec.controller, spec.config, "queued", "", std::nullopt, spec.owner,
                                spec.name, spec.tags, spec.notes});
  run->spec = std::move(spec);
  {
    std::lock_guard lock(mutex_);
    run->unfinished = run->spec.seeds.size();
    active_[run->record.id] = run;
    for (const std::uint64_t seed : run->spec.seeds) queue_.push_back({run, seed});
    if (run->unfinished == 0) {
      active_.erase(run->record.id);
      store_.set_run_status(run->record.id, "finished");
    }
  }
  wake_.notify_all();
  return run->record;
}

bool Executor::cancel(const std::string& run_id) {
  std::shared_ptr<ActiveRun> run;
  {
    std::lock_guard lock(mutex_);
    const auto found = active_.find(run_id);
    if (found == active_.end()) return false;
    run = found->second;
    run->cancelled = true;
    // Queued episodes of the run never start.
    const auto before = queue_.size();
    std::erase_if(queue_, [&](const Job& job) { return job.run == run; });
    run->unfinished -= before - queue_.size();
    if (run->unfinished == 0) {
      active_.erase(run_id);
      store_.set_run_status(run_id, "cancelled");
      done_.notify_all();
    }
  }
  return true;
}

std::map<std::uint64_t, std::string> Executor::live(const std::string& run_id) const {
  std::lock_guard lock(mutex_);
  std::map<std::uint64_t, std::string> seeds;
  const auto found = active_.find(run_id);
  if (found == active_.end()) return seeds;
  const ActiveRun& run = *found->second;
  // Once cancelled, the seeds that will never run say so at once (stored ones are the store's).
  if (run.cancelled) {
    for (const std::uint64_t seed : run.spec.seeds) seeds[seed] = "cancelled";
  }
  for (const Job& job : queue_) {
    if (job.run == found->second) seeds[job.seed] = "queued";
  }
  for (const std::uint64_t seed : run.running) seeds[seed] = "running";
  return seeds;
}

void Executor::wait(const std::string& run_id) {
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] { return !active_.contains(run_id); });
}

void Executor::work() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      job = std::move(queue_.front());
      queue_.pop_front();
      job.run->running.insert(job.seed);
      if (!job.run->started) {
        job.run->started = true;
        store_.set_run_status(job.run->record.id, "running");
      }
    }
    run_job(job);
  }
}

void Executor::run_job(const Job& job) {
  ActiveRun& run = *job.run;
  storage::EpisodeRecord record;
  bool store = true;
  try {
    EpisodeOptions options;
    options.max_time = run.spec.max_time;
    options.requests = run.spec.requests;
    options.baseline_without_robot = run.spec.baseline_without_robot;
    options.cancel = &run.cancelled;
    options.recording_memory = recording_memory_;
    EpisodeResult result = run_episode(run.spec.model, job.seed, options);
    store = !result.cancelled;
    record = std::move(result.record);
  } catch (const std::exception& e) {
    // The episode failed; it is kept with the reason so that the run shows what went wrong.
    record = {};
    record.seed = job.seed;
    record.status = "error";
    record.termination_reason = "error";
    record.events.push_back({0, 0.0, "error", "", {{"message", e.what()}}});
  }
  if (store && !stopping_) {
    record.id = core::unguessable_id('e');
    record.run_id = run.record.id;
    record.scenario_id = run.spec.scenario_id;
    record.controller = run.spec.controller;
    try {
      store_.write_episode(record);
      if (listener_) listener_(run.record.id, record);
    } catch (const core::Error& e) {
      std::fprintf(stderr, "hrisim: episode of run %s, seed %llu, could not be stored: %s\n", run.record.id.c_str(),
                   static_cast<unsigned long long>(job.seed), e.what());
      std::lock_guard lock(mutex_);
      run.any_error = true;
    }
  }
  std::lock_guard lock(mutex_);
  run.any_error = run.any_error || record.status == "error";
  finish_job(run, job.seed);
}

void Executor::finish_job(ActiveRun& run, std::uint64_t seed) {
  run.running.erase(seed);
  if (--run.unfinished > 0 || stopping_) return;
  store_.set_run_status(run.record.id, run.cancelled ? "cancelled" : run.any_error ? "failed" : "finished");
  active_.erase(run.record.id);
  done_.notify_all();
}

}  // namespace hrisim::runs
