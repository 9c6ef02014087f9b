#pragma once
// A position in one of the model's fixed lists (its agents, seats, queues, …), typed by the list it
// indexes: a cross-reference in the state says what it points at, and an agent's index cannot be
// stored where a seat's belongs. Unlike core::Id (generational, for what the API adds and removes),
// an index names a slot that never changes owner.
namespace hrisim::core {

template <class List>
struct Index {
  int value = -1;  ///< -1: none

  constexpr Index() = default;
  constexpr explicit Index(int position) : value(position) {}
  constexpr bool valid() const { return value >= 0; }
  constexpr bool operator==(const Index&) const = default;
  constexpr auto operator<=>(const Index&) const = default;
};

}  // namespace hrisim::core
