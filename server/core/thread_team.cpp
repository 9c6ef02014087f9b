#include "core/thread_team.hpp"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace hrisim::core {
namespace {

/// Waits in a tick are short: a helper spins this many times (about half a millisecond) for the
/// next loop before it sleeps, and the caller spins for its helpers. Waking a sleeping thread costs
/// tens of microseconds, more than a loop's share on a small crowd.
constexpr int kSpins = 20000;

void relax() {
#if defined(__x86_64__) || defined(__i386__)
  _mm_pause();
#else
  std::this_thread::yield();
#endif
}

}  // namespace

struct ThreadTeam::Shared {
  std::mutex mutex;
  std::condition_variable started;
  std::atomic<std::uint64_t> generation{0};  ///< one more for each loop handed out
  std::atomic<bool> stopping{false};
  const Part* part = nullptr;  // these three are written before `generation` moves on
  std::size_t count = 0;
  unsigned parts = 1;
  std::atomic<unsigned> pending{0};  ///< helpers' parts of this loop not yet done
  std::vector<std::exception_ptr> errors;  ///< per part
  std::vector<std::thread> helpers;

  /// The next loop after `seen`, or false when the team stops.
  bool wait_for_loop(std::uint64_t seen) {
    for (int spin = 0; spin < kSpins; ++spin) {
      if (stopping.load(std::memory_order_acquire)) return false;
      if (generation.load(std::memory_order_acquire) != seen) return true;
      relax();
    }
    std::unique_lock lock(mutex);
    started.wait(lock, [&] { return stopping.load() || generation.load() != seen; });
    return !stopping.load();
  }
};

ThreadTeam::ThreadTeam(unsigned threads) : threads_(threads < 1 ? 1 : threads), shared_(std::make_shared<Shared>()) {
  shared_->parts = threads_;
  shared_->errors.resize(threads_);
  for (unsigned k = 1; k < threads_; ++k) {
    shared_->helpers.emplace_back([shared = shared_.get(), k] {
      std::uint64_t seen = 0;
      while (shared->wait_for_loop(seen)) {
        seen = shared->generation.load(std::memory_order_acquire);
        const auto [begin, end] = bounds(shared->count, shared->parts, k);
        try {
          (*shared->part)(k, begin, end);
        } catch (...) {
          shared->errors[k] = std::current_exception();
        }
        shared->pending.fetch_sub(1, std::memory_order_acq_rel);
      }
    });
  }
}

ThreadTeam::~ThreadTeam() {
  {
    std::lock_guard lock(shared_->mutex);
    shared_->stopping = true;
  }
  shared_->started.notify_all();
  for (std::thread& helper : shared_->helpers) helper.join();
}

void ThreadTeam::run(std::size_t count, const Part& part) {
  if (threads_ == 1) return part(0, 0, count);
  shared_->part = &part;
  shared_->count = count;
  for (std::exception_ptr& error : shared_->errors) error = nullptr;
  shared_->pending.store(threads_ - 1, std::memory_order_relaxed);
  {
    // Under the lock, so a helper about to sleep sees the new loop or is woken.
    std::lock_guard lock(shared_->mutex);
    shared_->generation.fetch_add(1, std::memory_order_release);
  }
  shared_->started.notify_all();
  const auto [begin, end] = bounds(count, threads_, 0);
  try {
    part(0, begin, end);
  } catch (...) {
    shared_->errors[0] = std::current_exception();
  }
  for (int spin = 0; shared_->pending.load(std::memory_order_acquire) != 0; ++spin) {
    if (spin < kSpins) {
      relax();
    } else {
      std::this_thread::yield();
    }
  }
  for (const std::exception_ptr& error : shared_->errors) {
    if (error) std::rethrow_exception(error);
  }
}

}  // namespace hrisim::core
