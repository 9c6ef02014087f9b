#pragma once
// Generational ids and the table that hands them out: an id names a slot and the generation of
// the entity in it, so an id kept after its entity was removed is detected instead of silently
// reaching whatever took the slot. Entities are iterated in creation order.
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace hrisim::core {

/// 404 for an id whose slot holds no entity of that generation (details: index, generation).
[[noreturn]] void throw_unknown_id(std::uint32_t index, std::uint32_t generation);

template <class Tag>
struct Id {
  std::uint32_t index = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t generation = 0;

  bool valid() const { return index != std::numeric_limits<std::uint32_t>::max(); }
  bool operator==(const Id&) const = default;
  auto operator<=>(const Id&) const = default;
};

template <class Tag, class T>
class EntityTable {
 public:
  using Key = Id<Tag>;

  Key add(T value) {
    std::uint32_t index;
    if (!free_.empty()) {
      index = free_.back();
      free_.pop_back();
      slots_[index].value = std::move(value);
      slots_[index].alive = true;
    } else {
      index = static_cast<std::uint32_t>(slots_.size());
      slots_.push_back({std::move(value), 0, true});
    }
    order_.push_back(index);
    return {index, slots_[index].generation};
  }

  void remove(Key id) {
    check(id);
    Slot& slot = slots_[id.index];
    slot.alive = false;
    ++slot.generation;
    free_.push_back(id.index);
    std::erase(order_, id.index);
  }

  bool contains(Key id) const {
    return id.index < slots_.size() && slots_[id.index].alive && slots_[id.index].generation == id.generation;
  }

  T& at(Key id) {
    check(id);
    return slots_[id.index].value;
  }
  const T& at(Key id) const {
    check(id);
    return slots_[id.index].value;
  }

  std::size_t size() const { return order_.size(); }

  /// Ids of live entities in creation order.
  std::vector<Key> ids() const {
    std::vector<Key> result;
    result.reserve(order_.size());
    for (std::uint32_t index : order_) result.push_back({index, slots_[index].generation});
    return result;
  }

  /// Calls f(id, value) for every live entity in creation order.
  template <class F>
  void for_each(F&& f) {
    for (std::uint32_t index : order_) f(Key{index, slots_[index].generation}, slots_[index].value);
  }
  template <class F>
  void for_each(F&& f) const {
    for (std::uint32_t index : order_) f(Key{index, slots_[index].generation}, slots_[index].value);
  }

 private:
  struct Slot {
    T value;
    std::uint32_t generation;
    bool alive;
  };

  void check(Key id) const {
    if (!contains(id)) throw_unknown_id(id.index, id.generation);
  }

  std::vector<Slot> slots_;
  std::vector<std::uint32_t> free_;
  std::vector<std::uint32_t> order_;
};

}  // namespace hrisim::core
