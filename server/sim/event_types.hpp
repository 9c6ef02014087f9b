#pragma once
// The closed set of the simulation's events (docs/events.md): one struct per kind, each with its
// kind's name and the fields the API shows in the event's `data`. Consumers read these fields; the
// JSON form is made only at the edges (runs/event_json.hpp), and the state's events digest hashes the
// same fields (sim::emit). A struct lists its data fields once, in visit_fields: the JSON writer and
// the digest both walk that list, so the two cannot disagree.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "humans/behaviour.hpp"

namespace hrisim::sim {

enum class DoorPhase { closed, opening, open, closing };
constexpr std::string_view phase_name(DoorPhase phase) {
  switch (phase) {
    case DoorPhase::closed: return "closed";
    case DoorPhase::opening: return "opening";
    case DoorPhase::open: return "open";
    case DoorPhase::closing: return "closing";
  }
  return "closed";
}

namespace events {

/// A field shown as null when empty (not left out, as an empty std::optional field is).
struct NullWhenEmpty {
  const std::optional<std::string>& value;
};

// Doors and elevators. Floors are 0-based here and 1-based in the event's data.
struct DoorState {
  static constexpr std::string_view kind = "door_state";
  int door = -1;  ///< index of Model::doors (the subject names it)
  DoorPhase state = DoorPhase::closed;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("state", phase_name(state)); }
};
struct ElevatorDeparted {
  static constexpr std::string_view kind = "elevator_departed";
  int from = 0, to = 0;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("from", from + 1);
    visit("to", to + 1);
  }
};
struct ElevatorArrived {
  static constexpr std::string_view kind = "elevator_arrived";
  int elevator = -1;  ///< index of Model::elevators (the subject names it)
  int floor = 0;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("floor", floor + 1); }
};
struct ElevatorIgnoredRequest {
  static constexpr std::string_view kind = "elevator_ignored_request";
  std::string message;  ///< the request topic's text that names no floor
  template <class Visit> void visit_fields(Visit&& visit) const { visit("message", message); }
};

// Choreography and routines.
struct StepStarted {
  static constexpr std::string_view kind = "step_started";
  int index = 0;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("index", index); }
};
struct StepFinished {
  static constexpr std::string_view kind = "step_finished";
  int index = 0;
  double duration = 0.0;  ///< s
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("index", index);
    visit("duration", duration);
  }
};
struct GroupEmpty {
  static constexpr std::string_view kind = "group_empty";
  std::string step;  ///< the step's name
  template <class Visit> void visit_fields(Visit&& visit) const { visit("step", step); }
};
struct GroupFormed {
  static constexpr std::string_view kind = "group_formed";
  std::int64_t members = 0;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("members", members); }
};
struct GroupDismantled {
  static constexpr std::string_view kind = "group_dismantled";
  template <class Visit> void visit_fields(Visit&&) const {}
};
struct Publish {
  static constexpr std::string_view kind = "publish";
  std::string topic, message;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("topic", topic);
    visit("message", message);
  }
};
struct Command {
  static constexpr std::string_view kind = "command";
  std::string text;  ///< the command as given
  template <class Visit> void visit_fields(Visit&& visit) const { visit("text", text); }
};
struct ActivityStarted {
  static constexpr std::string_view kind = "activity_started";
  std::string activity, model;
  std::optional<std::string> location;  ///< when the activity walks to a location
  std::optional<std::string> waiting;   ///< when a walk found no free place
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("activity", activity);
    visit("model", model);
    visit("location", location);
    visit("waiting", waiting);
  }
};
struct StayStarted {
  static constexpr std::string_view kind = "stay_started";
  std::string room, at, until;  ///< at, until: the scenario clock's HH:MM:SS
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("room", room);
    visit("at", at);
    visit("until", until);
  }
};
struct ScenarioFinished {
  static constexpr std::string_view kind = "scenario_finished";
  template <class Visit> void visit_fields(Visit&&) const {}
};

// Requests and queues. A request's routine is shown twice, as `routine` and as its deprecated name `task`.
struct Request {
  static constexpr std::string_view kind = "request";
  std::int64_t request = 0;
  std::string routine;
  double x = 0.0, y = 0.0;  ///< the robot's position, m
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("request", request);
    visit("routine", routine);
    visit("task", routine);
    visit("x", x);
    visit("y", y);
  }
};
struct RequestAccepted {
  static constexpr std::string_view kind = "request_accepted";
  std::int64_t request = 0;
  std::string routine, robot;
  double distance = 0.0;  ///< from the answering human to where the robot asked, m
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("request", request);
    visit("routine", routine);
    visit("task", routine);
    visit("robot", robot);
    visit("distance", distance);
  }
};
enum class DropReason { no_response, no_idle_human };
struct RequestDropped {
  static constexpr std::string_view kind = "request_dropped";
  std::int64_t request = 0;
  std::string routine;
  DropReason reason = DropReason::no_response;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("request", request);
    visit("routine", routine);
    visit("task", routine);
    visit("reason", reason == DropReason::no_response ? std::string_view("the scenario has no response for this routine") : std::string_view("no idle human within 3 m"));
  }
};
struct QueueJoined {
  static constexpr std::string_view kind = "queue_joined";
  std::string queue;
  std::int64_t place = 0;  ///< in line, 0 = head
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("queue", queue);
    visit("place", place);
  }
};
struct Served {
  static constexpr std::string_view kind = "served";
  std::string queue;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("queue", queue); }
};

// People.
struct Entered {
  static constexpr std::string_view kind = "entered";
  template <class Visit> void visit_fields(Visit&&) const {}
};
struct Left {
  static constexpr std::string_view kind = "left";
  template <class Visit> void visit_fields(Visit&&) const {}
};
struct AgentRemoved {
  static constexpr std::string_view kind = "agent_removed";
  template <class Visit> void visit_fields(Visit&&) const {}
};
struct AgentPlaced {
  static constexpr std::string_view kind = "placed";
  double x = 0.0, y = 0.0, theta = 0.0;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("x", x);
    visit("y", y);
    visit("theta", theta);
  }
};
struct ObjectPlaced {
  static constexpr std::string_view kind = "placed";
  double x = 0.0, y = 0.0, z = 0.0;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("x", x);
    visit("y", y);
    visit("z", z);
  }
};
struct Stuck {
  static constexpr std::string_view kind = "stuck";
  double x = 0.0, y = 0.0;            ///< where the person is, m
  double goal_x = 0.0, goal_y = 0.0;  ///< m
  double goal_distance = 0.0;         ///< path length left, m
  double without_progress = 0.0;      ///< s ("for" in the data)
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("x", x);
    visit("y", y);
    visit("goal_x", goal_x);
    visit("goal_y", goal_y);
    visit("goal_distance", goal_distance);
    visit("for", without_progress);
  }
};
struct GoalUnreachable {
  static constexpr std::string_view kind = "goal_unreachable";
  double x = 0.0, y = 0.0;  ///< the goal, m
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("x", x);
    visit("y", y);
  }
};
/// An agent whose own spot was unplannable for its clearance (pushed or placed where its body does not
/// fit) planned from the nearest free cell, and walks there first.
struct ReplannedFromFreeCell {
  static constexpr std::string_view kind = "replanned_from_free_cell";
  double x = 0.0, y = 0.0;            ///< where the agent is, m
  double free_x = 0.0, free_y = 0.0;  ///< the free cell's centre, m
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("x", x);
    visit("y", y);
    visit("free_x", free_x);
    visit("free_y", free_y);
  }
};
struct Attracted {
  static constexpr std::string_view kind = "attracted";
  std::string attraction;
  double x = 0.0, y = 0.0;  ///< the spot chosen, m
  double stay = 0.0;        ///< how long they will stay, s ("for" in the data)
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("attraction", attraction);
    visit("x", x);
    visit("y", y);
    visit("for", stay);
  }
};
struct ReactionStarted {
  static constexpr std::string_view kind = "reaction_started";
  humans::BehaviourType behaviour = humans::BehaviourType::regular;
  std::string robot;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("behaviour", humans::behaviour_name(behaviour));
    visit("robot", robot);
  }
};
enum class ReactionEnd { out_of_view, another_robot, duration };
constexpr std::string_view why_text(ReactionEnd why) {
  switch (why) {
    case ReactionEnd::out_of_view: return "out of view";
    case ReactionEnd::another_robot: return "another robot";
    case ReactionEnd::duration: return "duration";
  }
  return "duration";
}
struct ReactionEnded {
  static constexpr std::string_view kind = "reaction_ended";
  humans::BehaviourType behaviour = humans::BehaviourType::regular;
  std::string robot;
  ReactionEnd why = ReactionEnd::duration;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("behaviour", humans::behaviour_name(behaviour));
    visit("robot", robot);
    visit("why", why_text(why));
  }
};
struct Startled {
  static constexpr std::string_view kind = "startled";
  std::string robot;
  bool stepped_back = false;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("robot", robot);
    visit("stepped_back", stepped_back);
  }
};

// Robots and grasping.
struct RobotGoalReached {
  static constexpr std::string_view kind = "robot_goal_reached";
  double x = 0.0, y = 0.0;  ///< the robot's position, m
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("x", x);
    visit("y", y);
  }
};
struct SearchRoom {
  static constexpr std::string_view kind = "search_room";
  std::string room;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("room", room); }
};
struct PersonFound {
  static constexpr std::string_view kind = "person_found";
  std::string person;
  std::optional<std::string> room;  ///< the person's room; null in the data when in none
  double range = 0.0;               ///< detected range, m
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("person", person);
    visit("room", NullWhenEmpty{room});
    visit("range", range);
  }
};
/// What a robot's body touches: `with` an agent id, an object's name or "map"; `part` a body part,
/// link, object or obstacle name.
struct ContactStart {
  static constexpr std::string_view kind = "contact_start";
  std::string with, part;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("with", with);
    visit("part", part);
  }
};
struct ContactEnd {
  static constexpr std::string_view kind = "contact_end";
  std::string with, part;
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("with", with);
    visit("part", part);
  }
};
struct Grasp {
  static constexpr std::string_view kind = "grasp";
  std::string object;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("object", object); }
};
struct Release {
  static constexpr std::string_view kind = "release";
  std::string object;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("object", object); }
};
struct Slip {
  static constexpr std::string_view kind = "slip";
  std::string object;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("object", object); }
};

// Carrying and seats.
struct PickedUp {
  static constexpr std::string_view kind = "picked_up";
  std::string object;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("object", object); }
};
struct PutDown {
  static constexpr std::string_view kind = "put_down";
  std::string object;
  double x = 0.0, y = 0.0;  ///< the put-down point, m
  template <class Visit> void visit_fields(Visit&& visit) const {
    visit("object", object);
    visit("x", x);
    visit("y", y);
  }
};
struct PickUpSkipped {
  static constexpr std::string_view kind = "pick_up_skipped";
  std::string reason;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("reason", reason); }
};
struct PutDownSkipped {
  static constexpr std::string_view kind = "put_down_skipped";
  std::string reason;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("reason", reason); }
};
/// A person who left while carrying let go of the object.
struct Dropped {
  static constexpr std::string_view kind = "dropped";
  std::string object;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("object", object); }
};
struct SeatUnreachable {
  static constexpr std::string_view kind = "seat_unreachable";
  std::string seat;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("seat", seat); }
};
struct SatDown {
  static constexpr std::string_view kind = "sat_down";
  std::string seat;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("seat", seat); }
};
struct StoodUp {
  static constexpr std::string_view kind = "stood_up";
  std::string seat;
  template <class Visit> void visit_fields(Visit&& visit) const { visit("seat", seat); }
};

// Episode end.
struct TimeLimit {
  static constexpr std::string_view kind = "time_limit";
  int step = 0;  ///< the current step's index (the number of steps after the last)
  template <class Visit> void visit_fields(Visit&& visit) const { visit("step", step); }
};
struct TaskEnded {
  static constexpr std::string_view kind = "task_ended";
  template <class Visit> void visit_fields(Visit&&) const {}
};

}  // namespace events

/// What an event says: one of the kinds above.
using EventData =
    std::variant<events::DoorState, events::ElevatorDeparted, events::ElevatorArrived, events::ElevatorIgnoredRequest, events::StepStarted,
                 events::StepFinished, events::GroupEmpty, events::GroupFormed, events::GroupDismantled, events::Publish, events::Command,
                 events::ActivityStarted, events::StayStarted, events::ScenarioFinished, events::Request, events::RequestAccepted,
                 events::RequestDropped, events::QueueJoined, events::Served, events::Entered, events::Left, events::AgentRemoved,
                 events::AgentPlaced, events::ObjectPlaced, events::Stuck, events::GoalUnreachable, events::ReplannedFromFreeCell,
                 events::Attracted, events::ReactionStarted, events::ReactionEnded, events::Startled, events::RobotGoalReached, events::SearchRoom,
                 events::PersonFound, events::ContactStart, events::ContactEnd, events::Grasp, events::Release, events::Slip,
                 events::PickedUp, events::PutDown, events::PickUpSkipped, events::PutDownSkipped, events::Dropped,
                 events::SeatUnreachable, events::SatDown, events::StoodUp, events::TimeLimit, events::TaskEnded>;

/// An event: what happened (`data`), to what (`subject`: usually an agent's id; see docs/events.md),
/// stamped with the tick it happened at.
struct Event {
  std::int64_t tick = 0;
  double time = 0.0;
  std::string subject;
  EventData data;

  std::string_view kind() const {
    return std::visit([](const auto& what) { return std::remove_cvref_t<decltype(what)>::kind; }, data);
  }
  template <class Kind>
  bool is() const {
    return std::holds_alternative<Kind>(data);
  }
  /// The event's data as `Kind`, or null when it is another kind.
  template <class Kind>
  const Kind* as() const {
    return std::get_if<Kind>(&data);
  }
};

}  // namespace hrisim::sim
