#pragma once
// Helper threads that share one loop of a tick with the calling thread. The loop's index range is cut
// into as many fixed parts as the team has threads, part k always the same indices; what an index
// computes never depends on which thread runs it or when, so a tick gives the same bits on one
// thread or several.
#include <cstddef>
#include <functional>
#include <memory>

namespace hrisim::core {

class ThreadTeam {
 public:
  /// The work of one part: its number and its indices [begin, end).
  using Part = std::function<void(unsigned part, std::size_t begin, std::size_t end)>;

  /// `threads` in all, the caller included; 1 starts no helper and runs loops on the caller.
  explicit ThreadTeam(unsigned threads);
  ~ThreadTeam();
  ThreadTeam(const ThreadTeam&) = delete;
  ThreadTeam& operator=(const ThreadTeam&) = delete;

  unsigned size() const { return threads_; }

  /// Runs `part` on each part of [0, count) — the caller takes part 0 — and returns when all are
  /// done; an exception thrown by a part is thrown here (the first, by part number).
  void run(std::size_t count, const Part& part);

  /// Part k's indices of [0, count) among `parts`.
  static std::pair<std::size_t, std::size_t> bounds(std::size_t count, unsigned parts, unsigned k) {
    return {count * k / parts, count * (k + 1) / parts};
  }

 private:
  struct Shared;
  unsigned threads_;
  std::shared_ptr<Shared> shared_;
};

}  // namespace hrisim::core
