#include "http/ros_messages.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <sstream>

#include "core/error.hpp"
#include "core/text.hpp"

namespace hrisim::http::ros {
namespace {

using nlohmann::json;

/// The message types hrisim sends or takes, as ROS 2 (Jazzy) and the people stack define their fields; the constants of
/// the enumerations hrisim fills in are kept, comments and the rest left out. Types from another
/// package are written in full, as rosapi's definitions text does.
const std::map<std::string, std::string> kDefinitions = {
    {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
    {"builtin_interfaces/Duration", "int32 sec\nuint32 nanosec\n"},
    {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
    {"std_msgs/ColorRGBA", "float32 r\nfloat32 g\nfloat32 b\nfloat32 a\n"},
    {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
    {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
    {"geometry_msgs/Quaternion", "float64 x 0\nfloat64 y 0\nfloat64 z 0\nfloat64 w 1\n"},
    {"geometry_msgs/Pose", "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"},
    {"geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose pose\nfloat64[36] covariance\n"},
    {"geometry_msgs/Twist", "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n"},
    {"geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist twist\nfloat64[36] covariance\n"},
    {"geometry_msgs/Transform", "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"},
    {"geometry_msgs/TransformStamped", "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"},
    {"sensor_msgs/LaserScan",
     "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\nfloat32 time_increment\nfloat32 scan_time\n"
     "float32 range_min\nfloat32 range_max\nfloat32[] ranges\nfloat32[] intensities\n"},
    {"sensor_msgs/CompressedImage", "std_msgs/Header header\nstring format\nuint8[] data\n"},
    {"nav_msgs/Odometry", "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n"},
    {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
    {"rosgraph_msgs/Clock", "builtin_interfaces/Time clock\n"},
    {"rcl_interfaces/Log",
     "uint8 DEBUG=10\nuint8 INFO=20\nuint8 WARN=30\nuint8 ERROR=40\nuint8 FATAL=50\n"
     "builtin_interfaces/Time stamp\nuint8 level\nstring name\nstring msg\nstring file\nstring function\nuint32 line\n"},
    {"visualization_msgs/UVCoordinate", "float32 u\nfloat32 v\n"},
    {"visualization_msgs/MeshFile", "string filename\nuint8[] data\n"},
    {"visualization_msgs/Marker",
     "int32 ARROW=0\nint32 CUBE=1\nint32 SPHERE=2\nint32 CYLINDER=3\nint32 LINE_STRIP=4\nint32 TEXT_VIEW_FACING=9\n"
     "int32 ADD=0\nint32 DELETE=2\nint32 DELETEALL=3\n"
     "std_msgs/Header header\nstring ns\nint32 id\nint32 type\nint32 action\ngeometry_msgs/Pose pose\ngeometry_msgs/Vector3 scale\n"
     "std_msgs/ColorRGBA color\nbuiltin_interfaces/Duration lifetime\nbool frame_locked\ngeometry_msgs/Point[] points\n"
     "std_msgs/ColorRGBA[] colors\nstring texture_resource\nsensor_msgs/CompressedImage texture\n"
     "visualization_msgs/UVCoordinate[] uv_coordinates\nstring text\nstring mesh_resource\nvisualization_msgs/MeshFile mesh_file\n"
     "bool mesh_use_embedded_materials\n"},
    {"visualization_msgs/MarkerArray", "visualization_msgs/Marker[] markers\n"},
    // people_msgs of ROS's people stack (its ROS 2 branch): people as a robot's detector tracks them.
    {"people_msgs/Person", "string name\ngeometry_msgs/Point position\ngeometry_msgs/Point velocity\nfloat64 reliability\nstring[] tagnames\nstring[] tags\n"},
    {"people_msgs/People", "std_msgs/Header header\npeople_msgs/Person[] people\n"},
};

/// Bytes of each primitive type in CDR (a string's are its length's, then its own).
const std::map<std::string, std::size_t> kPrimitiveSizes = {
    {"bool", 1}, {"byte", 1}, {"char", 1}, {"int8", 1}, {"uint8", 1}, {"int16", 2}, {"uint16", 2}, {"int32", 4}, {"uint32", 4},
    {"int64", 8}, {"uint64", 8}, {"float32", 4}, {"float64", 8}, {"string", 4}};

struct Field {
  std::string type;  ///< a primitive's name, or a message type's "pkg/Type"
  std::string name;
  enum class Array { none, fixed, sequence } array = Array::none;
  std::size_t length = 0;  ///< a fixed array's
  json default_value;      ///< a primitive's, when its definition gives one
  bool primitive() const { return kPrimitiveSizes.contains(type); }
};

/// "pkg/Type" of a name in either spelling, or empty.
std::string short_type(const std::string& name) {
  const std::size_t slash = name.find('/');
  if (slash == std::string::npos || slash == 0) return {};
  const std::string package = name.substr(0, slash), rest = name.substr(slash + 1);
  const std::string type = rest.starts_with("msg/") ? rest.substr(4) : rest;
  if (type.empty() || type.find('/') != std::string::npos) return {};
  return package + "/" + type;
}

std::vector<Field> parse_definition(const std::string& text) {
  std::vector<Field> fields;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream tokens(line);
    std::string type, name, default_text;
    tokens >> type >> name >> default_text;
    if (type.empty() || name.find('=') != std::string::npos) continue;  // a constant
    Field field;
    field.type = type;
    field.name = name;
    if (const std::size_t bracket = type.find('['); bracket != std::string::npos) {
      const std::string size = type.substr(bracket + 1, type.size() - bracket - 2);
      field.type = type.substr(0, bracket);
      field.array = size.empty() ? Field::Array::sequence : Field::Array::fixed;
      field.length = size.empty() ? 0 : std::stoul(size);
    }
    if (!default_text.empty()) field.default_value = json::parse(default_text);
    fields.push_back(std::move(field));
  }
  return fields;
}

/// The parsed fields of a type ("pkg/Type"), parsed once.
const std::vector<Field>& fields_of(const std::string& type) {
  static const std::map<std::string, std::vector<Field>> parsed = [] {
    std::map<std::string, std::vector<Field>> all;
    for (const auto& [name, text] : kDefinitions) all.emplace(name, parse_definition(text));
    return all;
  }();
  const auto found = parsed.find(short_type(type));
  if (found == parsed.end()) throw core::Error(core::ErrorCode::internal, "no ROS message definition of " + type);
  return found->second;
}

std::string path_of(const std::string& prefix, const std::string& name) { return prefix.empty() ? name : prefix + "." + name; }

json conform_message(const std::string& type, const json& message, const std::string& path);

/// One value of a primitive type, checked.
json conform_primitive(const std::string& type, const json& value, const std::string& path) {
  const auto wrong = [&](const std::string& what) { return core::Error(core::ErrorCode::bad_request, path + " must be " + what); };
  if (type == "bool") {
    if (!value.is_boolean()) throw wrong("true or false");
    return value;
  }
  if (type == "string") {
    if (!value.is_string()) throw wrong("a string");
    return value;
  }
  if (type == "float32" || type == "float64") {
    if (!value.is_number()) throw wrong("a number");
    return value.get<double>();
  }
  // An integer type: its range from its name, [low, high], the bounds held exactly (no double).
  const bool is_signed = type.starts_with("int");
  const int bits = type == "byte" || type == "char" ? 8 : std::stoi(type.substr(is_signed ? 3 : 4));
  const std::int64_t low = !is_signed ? 0 : bits == 64 ? std::numeric_limits<std::int64_t>::min() : -(std::int64_t{1} << (bits - 1));
  const std::uint64_t high = bits == 64 ? (is_signed ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::uint64_t>::max())
                                        : (std::uint64_t{1} << (is_signed ? bits - 1 : bits)) - 1;
  const auto out_of_range = [&] { return wrong("an integer from " + std::to_string(low) + " to " + std::to_string(high)); };
  if (value.is_number_unsigned()) {
    if (value.get<std::uint64_t>() > high) throw out_of_range();
    return value;
  }
  if (value.is_number_integer()) {
    const auto number = value.get<std::int64_t>();
    if (number < low || (number > 0 && static_cast<std::uint64_t>(number) > high)) throw out_of_range();
    return value;
  }
  // A float only when it is a whole number within range: 2^bits (2^(bits-1) signed) is the first out.
  const double number = value.is_number_float() ? value.get<double>() : 0.5;
  if (std::trunc(number) != number || number < static_cast<double>(low) || number >= std::ldexp(1.0, is_signed ? bits - 1 : bits)) throw out_of_range();
  return is_signed ? json(static_cast<std::int64_t>(number)) : json(static_cast<std::uint64_t>(number));
}

json default_of(const Field& field) {
  if (!field.primitive()) return conform_message(field.type, json::object(), "");
  if (!field.default_value.is_null()) return field.default_value;
  if (field.type == "bool") return false;
  if (field.type == "string") return "";
  return field.type.starts_with("float") ? json(0.0) : json(0);
}

bool is_bytes(const Field& field) { return field.array == Field::Array::sequence && (field.type == "uint8" || field.type == "byte"); }

/// A uint8[] as JSON binary, from binary, base64 text (rosbridge's JSON form) or a list of numbers.
json conform_bytes(const json& value, const std::string& path) {
  if (value.is_binary()) return value;
  if (value.is_string()) {
    const auto bytes = core::base64_decode(value.get<std::string>());
    if (!bytes) throw core::Error(core::ErrorCode::bad_request, path + " must be base64 text, bytes or a list of integers from 0 to 255");
    return json::binary(std::vector<std::uint8_t>(bytes->begin(), bytes->end()));
  }
  if (!value.is_array()) throw core::Error(core::ErrorCode::bad_request, path + " must be base64 text, bytes or a list of integers from 0 to 255");
  std::vector<std::uint8_t> bytes;
  for (std::size_t i = 0; i < value.size(); ++i) bytes.push_back(conform_primitive("uint8", value[i], path + "[" + std::to_string(i) + "]").get<std::uint8_t>());
  return json::binary(std::move(bytes));
}

json conform_field(const Field& field, const json& value, const std::string& path) {
  const auto one = [&](const json& item, const std::string& at) {
    return field.primitive() ? conform_primitive(field.type, item, at) : conform_message(field.type, item, at);
  };
  if (field.array == Field::Array::none) return one(value, path);
  if (is_bytes(field)) return conform_bytes(value, path);
  if (!value.is_array()) throw core::Error(core::ErrorCode::bad_request, path + " must be a list");
  if (field.array == Field::Array::fixed && value.size() != field.length) {
    throw core::Error(core::ErrorCode::bad_request, path + " must hold " + std::to_string(field.length) + " items, not " + std::to_string(value.size()));
  }
  json items = json::array();
  for (std::size_t i = 0; i < value.size(); ++i) items.push_back(one(value[i], path + "[" + std::to_string(i) + "]"));
  return items;
}

json conform_message(const std::string& type, const json& message, const std::string& path) {
  if (!message.is_object()) throw core::Error(core::ErrorCode::bad_request, (path.empty() ? std::string("the message") : path) + " must be an object (" + type + ")");
  const std::vector<Field>& fields = fields_of(type);
  for (const auto& item : message.items()) {
    const std::string& key = item.key();  // a name, not a structured binding: clang 14's lambdas cannot capture those
    if (std::none_of(fields.begin(), fields.end(), [&key](const Field& f) { return f.name == key; })) {
      throw core::Error(core::ErrorCode::bad_request, path_of(path, key) + " is not a field of " + canonical_type(type));
    }
  }
  json complete = json::object();
  for (const Field& field : fields) {
    if (!message.contains(field.name)) {
      complete[field.name] = field.array == Field::Array::none ? default_of(field)
                             : is_bytes(field)                 ? json::binary({})
                             : field.array == Field::Array::fixed ? json(std::vector<json>(field.length, default_of(field)))
                                                                  : json::array();
      continue;
    }
    complete[field.name] = conform_field(field, message[field.name], path_of(path, field.name));
  }
  return complete;
}

/// Plain CDR, little-endian, after its 4-byte encapsulation header.
class CdrWriter {
 public:
  CdrWriter() : bytes_{'\0', '\1', '\0', '\0'} {}
  template <typename T>
  void put(T value) {
    static_assert(std::endian::native == std::endian::little, "CDR is written little-endian, as the host holds numbers");
    align(sizeof(T));
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    bytes_.append(raw, sizeof(T));
  }
  void put_string(const std::string& text) {
    put(static_cast<std::uint32_t>(text.size() + 1));
    bytes_ += text;
    bytes_ += '\0';
  }
  void put_bytes(const std::vector<std::uint8_t>& bytes) {
    put(static_cast<std::uint32_t>(bytes.size()));
    bytes_.append(bytes.begin(), bytes.end());
  }
  std::string take() { return std::move(bytes_); }

 private:
  static constexpr std::size_t kHeader = 4;
  void align(std::size_t size) {
    while ((bytes_.size() - kHeader) % size != 0) bytes_ += '\0';
  }
  std::string bytes_;
};

void write_primitive(CdrWriter& out, const std::string& type, const json& value) {
  if (type == "bool") return out.put<std::uint8_t>(value.get<bool>() ? 1 : 0);
  if (type == "string") return out.put_string(value.get<std::string>());
  if (type == "float32") return out.put(static_cast<float>(value.get<double>()));
  if (type == "float64") return out.put(value.get<double>());
  if (type == "int8") return out.put(value.get<std::int8_t>());
  if (type == "uint8" || type == "byte" || type == "char") return out.put(value.get<std::uint8_t>());
  if (type == "int16") return out.put(value.get<std::int16_t>());
  if (type == "uint16") return out.put(value.get<std::uint16_t>());
  if (type == "int32") return out.put(value.get<std::int32_t>());
  if (type == "uint32") return out.put(value.get<std::uint32_t>());
  if (type == "int64") return out.put(value.get<std::int64_t>());
  out.put(value.get<std::uint64_t>());
}

/// A complete message (conform's) in CDR.
void write_message(CdrWriter& out, const std::string& type, const json& message) {
  for (const Field& field : fields_of(type)) {
    const json& value = message[field.name];
    const auto one = [&](const json& item) { field.primitive() ? write_primitive(out, field.type, item) : write_message(out, field.type, item); };
    if (field.array == Field::Array::none) {
      one(value);
    } else if (is_bytes(field)) {
      out.put_bytes(value.get_binary());
    } else {
      if (field.array == Field::Array::sequence) out.put(static_cast<std::uint32_t>(value.size()));
      for (const json& item : value) one(item);
    }
  }
}

/// The message types `type` uses, each once, in the order first met.
void add_dependencies(const std::string& type, std::vector<std::string>& found) {
  for (const Field& field : fields_of(type)) {
    if (field.primitive() || std::find(found.begin(), found.end(), field.type) != found.end()) continue;
    found.push_back(field.type);
    add_dependencies(field.type, found);
  }
}

}  // namespace

std::string canonical_type(const std::string& name) {
  const std::string type = short_type(name);
  if (type.empty()) return {};
  const std::size_t slash = type.find('/');
  return type.substr(0, slash) + "/msg/" + type.substr(slash + 1);
}

bool known_type(const std::string& name) { return kDefinitions.contains(short_type(name)); }

std::string full_definition(const std::string& type) {
  fields_of(type);  // throws for a type not defined here
  std::string text = kDefinitions.at(short_type(type));
  std::vector<std::string> dependencies;
  add_dependencies(type, dependencies);
  for (const std::string& dependency : dependencies) text += "\n" + std::string(80, '=') + "\nMSG: " + dependency + "\n" + kDefinitions.at(dependency);
  return text;
}

json conform(const std::string& type, const json& message) { return conform_message(type, message, ""); }

std::string encode_cdr(const std::string& type, const json& message) {
  CdrWriter out;
  write_message(out, type, conform(type, message));
  return out.take();
}

}  // namespace hrisim::http::ros
