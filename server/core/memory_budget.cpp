#include "core/memory_budget.hpp"

#include <utility>

namespace hrisim::core {

MemoryBudget::Lease::Lease(Lease&& other) noexcept
    : budget_(std::exchange(other.budget_, nullptr)), bytes_(std::exchange(other.bytes_, 0)) {}

MemoryBudget::Lease& MemoryBudget::Lease::operator=(Lease&& other) noexcept {
  if (this != &other) {
    release();
    budget_ = std::exchange(other.budget_, nullptr);
    bytes_ = std::exchange(other.bytes_, 0);
  }
  return *this;
}

bool MemoryBudget::Lease::grow(std::size_t bytes) {
  if (budget_) {
    std::size_t used = budget_->used_.load(std::memory_order_relaxed);
    do {
      if (bytes > budget_->limit_ || used > budget_->limit_ - bytes) return false;
    } while (!budget_->used_.compare_exchange_weak(used, used + bytes, std::memory_order_relaxed));
  }
  bytes_ += bytes;
  return true;
}

void MemoryBudget::Lease::shrink(std::size_t bytes) {
  bytes = bytes < bytes_ ? bytes : bytes_;
  if (budget_) budget_->used_.fetch_sub(bytes, std::memory_order_relaxed);
  bytes_ -= bytes;
}

void MemoryBudget::Lease::release() {
  if (budget_) budget_->used_.fetch_sub(bytes_, std::memory_order_relaxed);
  budget_ = nullptr;
  bytes_ = 0;
}

}  // namespace hrisim::core
