#pragma once
// JSON text written straight into a string, for the replies sent many thousand times a second (a
// lockstep step): no tree of values to build, allocate and walk first. The output parses as the same
// values nlohmann::json would give: numbers round-trip exactly, a double always reads as a double
// ("1.0", not "1"), a non-finite double is null, strings not in UTF-8 get U+FFFD.
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace hrisim::core {

class JsonWriter {
 public:
  JsonWriter& begin_object() { return open('{'); }
  JsonWriter& end_object() { return close('}'); }
  JsonWriter& begin_array() { return open('['); }
  JsonWriter& end_array() { return close(']'); }
  /// The next member's name, inside an object.
  JsonWriter& key(std::string_view name);

  JsonWriter& value(std::string_view text);
  JsonWriter& value(const char* text) { return value(std::string_view(text)); }
  JsonWriter& value(const std::string& text) { return value(std::string_view(text)); }
  JsonWriter& value(double number);
  JsonWriter& value(std::int64_t number);
  JsonWriter& value(int number) { return value(static_cast<std::int64_t>(number)); }
  JsonWriter& value(std::uint64_t number);
  JsonWriter& value(bool flag);
  JsonWriter& null();
  /// A value already held as a JSON tree (rare, small parts of a reply).
  JsonWriter& value(const nlohmann::json& tree);
  JsonWriter& value(std::span<const double> numbers);

  /// A value already written as JSON text (a reply made elsewhere), inserted as it is.
  JsonWriter& raw(std::string_view json_text);
  /// The members of `object` (a JSON object) into the object being written.
  JsonWriter& members(const nlohmann::json& object);

  const std::string& text() const { return out_; }
  std::string take() { return std::move(out_); }

 private:
  /// A comma before every element of an array or object but its first.
  void separate();
  JsonWriter& open(char bracket);
  JsonWriter& close(char bracket);

  std::string out_;
  std::vector<bool> first_;  ///< per open array or object: nothing written in it yet
  bool after_key_ = false;
};

}  // namespace hrisim::core
