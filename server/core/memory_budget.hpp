#pragma once
// Bytes many holders share under one ceiling (the recordings of every session and run of a server):
// each holder takes a lease that grows while the ceiling allows and gives everything back when it ends.
#include <atomic>
#include <cstddef>

namespace hrisim::core {

class MemoryBudget {
 public:
  explicit MemoryBudget(std::size_t limit) : limit_(limit) {}
  MemoryBudget(const MemoryBudget&) = delete;
  MemoryBudget& operator=(const MemoryBudget&) = delete;

  std::size_t limit() const { return limit_; }
  std::size_t used() const { return used_.load(std::memory_order_relaxed); }

  /// What one holder has taken; given back when the lease ends. Without a budget it takes nothing and
  /// always may grow.
  class Lease {
   public:
    Lease() = default;
    explicit Lease(MemoryBudget* budget) : budget_(budget) {}
    Lease(Lease&& other) noexcept;
    Lease& operator=(Lease&& other) noexcept;
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    ~Lease() { release(); }

    /// Takes `bytes` more; false, taking nothing, when the budget's ceiling would be passed.
    bool grow(std::size_t bytes);
    /// Gives `bytes` back (at most what it holds): its holder let go of part of what it kept.
    void shrink(std::size_t bytes);
    std::size_t bytes() const { return bytes_; }
    const MemoryBudget* budget() const { return budget_; }

   private:
    void release();
    MemoryBudget* budget_ = nullptr;
    std::size_t bytes_ = 0;
  };

 private:
  const std::size_t limit_;
  std::atomic<std::size_t> used_{0};
};

}  // namespace hrisim::core
