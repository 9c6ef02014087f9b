#pragma once
// Where a person stands to sit on a seat or to reach something with the hand: the map keeps every
// piece of furniture solid, so a person plans to a free spot beside it and covers the last few
// centimetres without the planner (stepping back onto a seat, bending over a table).
#include <optional>

#include "scenario/model.hpp"

namespace hrisim::scenario {

/// A person about to sit stands this far in front of the seat's centre, m: the distance sit_down's
/// root travels backwards (assets/motions/sit_down.json), so that the body comes to rest on the seat.
double sit_down_travel();
/// Looking for a free spot in front of a seat goes no farther than this beyond sit_down_travel(), m.
inline constexpr double kSeatApproachReach = 1.0;
/// A person walking to the spot in front of a seat, or within reach of an item, stops this close to
/// it, m (closer than the default goal radius: the last step and the hand need the spot itself).
inline constexpr double kReachSpotRadius = 0.05;
/// A person steps onto a seat's spot, or back off it, at this speed, m/s (a careful step).
inline constexpr double kSeatStepSpeed = 0.4;

/// Where a person stands to sit down: sit_down_travel() in front of the seat, facing its way.
Vec2 seat_spot(const Seat& seat);
/// The nearest point in front of the seat that a disc of `radius` reaches by planning, from which it
/// steps straight onto seat_spot(); none when the seat's front is blocked within kSeatApproachReach.
std::optional<Vec2> seat_approach(const Model& model, const Seat& seat, double radius);

/// The right hand reaches an item at table height from this far (horizontally, from the person's
/// centre), m: the reach motion's hand (assets/motions/reach.json) is about this far ahead.
inline constexpr double kHandReach = 0.5;
/// A person bends farther over furniture to reach an item no farther than this, m; beyond, the item
/// is out of reach.
inline constexpr double kMaxHandReach = 0.8;
/// The right hand is this far to the right of a person's centre line, m (an adult's shoulder).
inline constexpr double kHandSideOffset = 0.18;
/// Directions around an item tried for a spot to stand at.
inline constexpr int kReachDirections = 16;

/// Where a disc of `radius` stands to reach an item at `item` with the hand: of the free spots around
/// it, the nearest to the item (no nearer than kHandReach), then the nearest to `from`; none when no
/// spot within kMaxHandReach is free.
std::optional<Vec2> reach_spot(const Model& model, const Vec2& item, const Vec2& from, double radius);
/// The heading that puts an item ahead of the right hand, for a person standing at `spot`.
double reach_heading(const Vec2& spot, const Vec2& item);

}  // namespace hrisim::scenario
