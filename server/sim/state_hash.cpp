#include "sim/state.hpp"

#include <cstdio>
#include <type_traits>
#include <utility>
#include <variant>

#include "core/state_hash.hpp"

namespace hrisim::sim {
namespace {

using Hasher = core::StateHasher;

// Adding a member to a state struct without listing it in its fields() would leave it out of the
// hash: these sizes make that a compile error (x86-64, libstdc++). List the member, then update the size.
static_assert(sizeof(PendingAction) == 24, "PendingAction changed: list every member in its fields()");
static_assert(sizeof(PlanningFallback) == 16, "PlanningFallback changed: hash every member in its put()");
static_assert(sizeof(Navigation) == 208, "Navigation changed: list every member in its fields()");
static_assert(sizeof(Attitude) == 96, "Attitude changed: list every member in its fields()");
static_assert(sizeof(Reservation) == 12, "Reservation changed: list every member in its fields()");
static_assert(sizeof(Queueing) == 12, "Queueing changed: list every member in its fields()");
static_assert(sizeof(Reaction) == 88, "Reaction changed: list every member in its fields()");
static_assert(sizeof(Living) == 288, "Living changed: list every member in its fields()");
static_assert(sizeof(Animation) == 48, "Animation changed: list every member in its fields()");
static_assert(sizeof(Seating) == 32, "Seating changed: list every member in its fields()");
static_assert(sizeof(Carrying) == 8, "Carrying changed: list every member in its fields()");
static_assert(sizeof(AgentState) == 1008, "AgentState changed: list every member in its fields()");
static_assert(sizeof(OpenRequest) == 48, "OpenRequest changed: list every member in its fields()");
static_assert(sizeof(ScheduledRequest) == 16, "ScheduledRequest changed: list every member in its fields()");
static_assert(sizeof(StepRecord) == 16, "StepRecord changed: list every member in its fields()");
static_assert(sizeof(DoorState) == 16, "DoorState changed: list every member in its fields()");
static_assert(sizeof(ElevatorState) == 112, "ElevatorState changed: list every member in its fields()");
static_assert(sizeof(Message) == 64, "Message changed: list every member in its fields()");
static_assert(sizeof(QueueState) == 72, "QueueState changed: list every member in its fields()");
static_assert(sizeof(ObjectState) == 176, "ObjectState changed: list every member in its fields()");
static_assert(sizeof(NavigationTaskState) == 80, "NavigationTaskState changed: list every member in its fields()");
static_assert(sizeof(PickAndPlaceState) == 40, "PickAndPlaceState changed: list every member in its fields()");
static_assert(sizeof(MirrorGestureState) == 48, "MirrorGestureState changed: list every member in its fields()");
static_assert(sizeof(TaskState) == 168, "TaskState changed: list every member in its fields()");
static_assert(sizeof(State) == 776, "State changed: list every member in its fields()");

template <class T>
concept WithFields = requires(const T& value) { value.fields(); };

void put(Hasher& hash, bool value) { hash.add(value); }
void put(Hasher& hash, int value) { hash.add(value); }
void put(Hasher& hash, std::int64_t value) { hash.add(value); }
void put(Hasher& hash, std::uint64_t value) { hash.add(value); }
void put(Hasher& hash, double value) { hash.add(value); }
/// As the int it holds: hashes made when indices were ints still hold.
template <class List>
void put(Hasher& hash, core::Index<List> index) {
  hash.add(index.value);
}
template <class E>
  requires std::is_enum_v<E>
void put(Hasher& hash, E value) {
  hash.add(static_cast<std::int64_t>(value));
}
void put(Hasher& hash, const std::string& text) { hash.add(std::string_view(text)); }
/// By its name, as when it was a string: hashes made before it became an enum still hold.
void put(Hasher& hash, Termination termination) { hash.add(to_string(termination)); }
void put(Hasher& hash, const Vec2& point) { hash.add(point.x()).add(point.y()); }
void put(Hasher& hash, const Pose2& pose) { hash.add(pose.x).add(pose.y).add(pose.theta); }
void put(Hasher& hash, const Eigen::Vector3d& vector) { hash.add(vector.x()).add(vector.y()).add(vector.z()); }
void put(Hasher& hash, const Eigen::Isometry3d& pose) {
  for (int k = 0; k < 16; ++k) hash.add(pose.data()[k]);
}
void put(Hasher& hash, const humans::MotionClip* motion) { hash.add(std::string_view(motion ? motion->name() : std::string())); }
void put(Hasher& hash, const core::Random& random) {
  for (const std::uint64_t word : random.state()) hash.add(word);
}
void put(Hasher& hash, const RobotRuntime& runtime) { runtime.hash(hash); }
void put(Hasher& hash, const sensors::SoundSource& source) { source.hash(hash); }
void put(Hasher& hash, const world::PlanningHistory& history) { history.hash(hash); }
/// Only when set: a session that never needed it hashes as it did before it existed.
void put(Hasher& hash, const PlanningFallback& fallback) {
  if (fallback != PlanningFallback{}) hash.add(fallback.body_clearance).add(fallback.from_free_cell);
}
/// The events' content is in State::events_digest, kept as they happen: hashing each every time would
/// cost more the longer a session runs.
void put(Hasher& hash, const std::vector<Event>& events) { hash.add(static_cast<std::uint64_t>(events.size())); }
/// A command's action (an input, fixed once given).
void put(Hasher& hash, const scenario::Action& action);
/// The empty alternative of a variant (no benchmark task's state): its index says it all.
void put(Hasher&, std::monostate) {}

template <class A, class B>
void put(Hasher& hash, const std::pair<A, B>& pair);
template <class... T>
void put(Hasher& hash, const std::variant<T...>& value);

template <class T>
void put(Hasher& hash, const std::optional<T>& value);
template <class T>
void put(Hasher& hash, const std::vector<T>& values);
template <class T>
void put(Hasher& hash, const std::deque<T>& values);
template <class K, class V>
void put(Hasher& hash, const std::map<K, V>& values);
template <WithFields T>
void put(Hasher& hash, const T& value);

template <class T>
void put(Hasher& hash, const std::optional<T>& value) {
  hash.add(value.has_value());
  if (value) put(hash, *value);
}
template <class T>
void put(Hasher& hash, const std::vector<T>& values) {
  hash.add(static_cast<std::uint64_t>(values.size()));
  for (const T& value : values) put(hash, value);
}
template <class T>
void put(Hasher& hash, const std::deque<T>& values) {
  hash.add(static_cast<std::uint64_t>(values.size()));
  for (const T& value : values) put(hash, value);
}
template <class K, class V>
void put(Hasher& hash, const std::map<K, V>& values) {
  hash.add(static_cast<std::uint64_t>(values.size()));
  for (const auto& [key, value] : values) {
    put(hash, key);
    put(hash, value);
  }
}
template <class A, class B>
void put(Hasher& hash, const std::pair<A, B>& pair) {
  put(hash, pair.first);
  put(hash, pair.second);
}
/// Which alternative it holds, then that alternative.
template <class... T>
void put(Hasher& hash, const std::variant<T...>& value) {
  hash.add(static_cast<std::uint64_t>(value.index()));
  std::visit([&hash](const auto& alternative) { put(hash, alternative); }, value);
}
template <WithFields T>
void put(Hasher& hash, const T& value) {
  std::apply([&hash](const auto&... field) { (put(hash, field), ...); }, value.fields());
}

void put(Hasher& hash, const scenario::Action& action) {
  put(hash, action.kind);
  hash.add(action.agent).add(action.group).add(action.target).add(action.radius).add(action.value);
  put(hash, action.members);
  put(hash, action.pose);
  hash.add(std::string_view(action.topic)).add(std::string_view(action.message)).add(std::string_view(action.motion));
}

}  // namespace

std::uint64_t state_hash(const State& state) {
  Hasher hash;
  put(hash, state);
  return hash.value();
}

std::size_t state_data_bytes(const State& state) {
  Hasher hash;
  put(hash, state);
  return hash.bytes();
}

std::string hash_hex(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace hrisim::sim
