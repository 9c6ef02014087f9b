#include "render/mesh.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <span>
#include <system_error>
#include <utility>

#include "core/embedded.hpp"
#include "core/error.hpp"

namespace hrisim::render::embedded {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace hrisim::render::embedded

namespace hrisim::render {
namespace {

const std::span<const core::EmbeddedFile> kFiles{embedded::kEmbedded, static_cast<std::size_t>(embedded::kEmbeddedCount)};

[[noreturn]] void bad(const std::string& source, std::size_t line, const std::string& reason) {
  throw core::Error(core::ErrorCode::bad_request, source + ":" + std::to_string(line) + ": " + reason,
                    {{"line", line}, {"source", source}});
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

/// A finite number, the whole token (an optional leading '+' allowed, as C's strtod would).
bool parse_number(std::string_view token, float& value) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '+' && token[1] != '-') token.remove_prefix(1);
  const char* const end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return ec == std::errc() && ptr == end && std::isfinite(value);
}

bool parse_integer(std::string_view token, long long& value) {
  const char* const end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, value);
  return !token.empty() && ec == std::errc() && ptr == end;
}

/// The unit normal of a polygon by Newell's method (counter-clockwise seen from where it points);
/// +z for a degenerate one.
Eigen::Vector3f face_normal(const std::vector<Eigen::Vector3f>& corners) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const Eigen::Vector3d a = corners[i].cast<double>();
    const Eigen::Vector3d b = corners[(i + 1) % corners.size()].cast<double>();
    sum.x() += (a.y() - b.y()) * (a.z() + b.z());
    sum.y() += (a.z() - b.z()) * (a.x() + b.x());
    sum.z() += (a.x() - b.x()) * (a.y() + b.y());
  }
  const double length = sum.norm();
  if (!(length > 0.0) || !std::isfinite(length)) return Eigen::Vector3f::UnitZ();
  return (sum / length).cast<float>();
}

class ObjReader {
 public:
  explicit ObjReader(const std::string& source) : source_(source) {}

  TriangleMesh read(std::string_view text) {
    std::size_t position = 0;
    while (position < text.size()) {
      std::size_t end = text.find('\n', position);
      if (end == std::string_view::npos) end = text.size();
      std::string_view line = text.substr(position, end - position);
      position = end + 1;
      ++line_;
      if (const std::size_t comment = line.find('#'); comment != std::string_view::npos) line = line.substr(0, comment);
      statement(split(line));
    }
    if (mesh_.positions.empty()) bad(source_, std::max<std::size_t>(line_, 1), "no faces");
    return std::move(mesh_);
  }

 private:
  void statement(const std::vector<std::string_view>& tokens) {
    if (tokens.empty()) return;
    if (tokens[0] == "v") {
      if (tokens.size() < 4) fail("a vertex needs three coordinates");
      vertices_.push_back(vector_of(tokens));
    } else if (tokens[0] == "vn") {
      if (tokens.size() < 4) fail("a normal needs three components");
      const Eigen::Vector3f normal = vector_of(tokens);
      const float length = normal.norm();
      // A zero normal is kept as zero: the faces that use it get their flat normal instead.
      normals_.push_back(length > 0.0f && std::isfinite(length) ? Eigen::Vector3f(normal / length) : Eigen::Vector3f::Zero());
    } else if (tokens[0] == "vt") {
      ++texture_coordinates_;
    } else if (tokens[0] == "f") {
      face(tokens);
    }
  }

  /// The first three numbers after the keyword; any further ones (w, colours) must be numbers too.
  Eigen::Vector3f vector_of(const std::vector<std::string_view>& tokens) {
    Eigen::Vector3f vector = Eigen::Vector3f::Zero();
    for (std::size_t i = 1; i < tokens.size(); ++i) {
      float value = 0.0f;
      if (!parse_number(tokens[i], value)) fail("malformed number '" + std::string(tokens[i]) + "'");
      if (i <= 3) vector[static_cast<Eigen::Index>(i - 1)] = value;
    }
    return vector;
  }

  /// A 1-based or negative (relative) OBJ index into `count` elements, as a 0-based index.
  std::size_t resolve(std::string_view token, std::size_t count, const char* what) {
    long long index = 0;
    if (!parse_integer(token, index)) fail(std::string("malformed ") + what + " index '" + std::string(token) + "'");
    const auto size = static_cast<long long>(count);
    if (index > 0 && index <= size) return static_cast<std::size_t>(index - 1);
    if (index < 0 && index >= -size) return static_cast<std::size_t>(size + index);
    fail(std::string(what) + " index " + std::to_string(index) + " out of range (" + std::to_string(count) + " " + what + "s so far)");
  }

  void face(const std::vector<std::string_view>& tokens) {
    if (tokens.size() < 4) fail("a face needs at least 3 vertices");
    std::vector<Eigen::Vector3f> corners;
    std::vector<const Eigen::Vector3f*> corner_normals;  // null: none given
    for (std::size_t i = 1; i < tokens.size(); ++i) {
      const std::string_view token = tokens[i];
      std::string_view parts[3];
      std::size_t count = 0, start = 0;
      while (true) {
        const std::size_t slash = token.find('/', start);
        if (count == 3) fail("malformed face vertex '" + std::string(token) + "'");
        parts[count++] = token.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
      }
      corners.push_back(vertices_[resolve(parts[0], vertices_.size(), "vertex")]);
      if (count > 1 && !parts[1].empty()) resolve(parts[1], texture_coordinates_, "texture coordinate");
      const Eigen::Vector3f* normal = nullptr;
      if (count > 2 && !parts[2].empty()) {
        normal = &normals_[resolve(parts[2], normals_.size(), "normal")];
        if (normal->squaredNorm() == 0.0f) normal = nullptr;
      }
      corner_normals.push_back(normal);
    }
    const Eigen::Vector3f flat = face_normal(corners);
    const auto add = [&](std::size_t k) {
      mesh_.positions.push_back(corners[k]);
      mesh_.normals.push_back(corner_normals[k] != nullptr ? *corner_normals[k] : flat);
    };
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      add(0);
      add(k);
      add(k + 1);
    }
  }

  [[noreturn]] void fail(const std::string& reason) const { bad(source_, line_, reason); }

  const std::string& source_;
  std::size_t line_ = 0;
  std::vector<Eigen::Vector3f> vertices_;
  std::vector<Eigen::Vector3f> normals_;
  std::size_t texture_coordinates_ = 0;
  TriangleMesh mesh_;
};

}  // namespace

Eigen::AlignedBox3f TriangleMesh::bounds() const {
  Eigen::AlignedBox3f box;  // empty
  for (const Eigen::Vector3f& position : positions) box.extend(position);
  return box;
}

TriangleMesh parse_obj(std::string_view text, const std::string& source) { return ObjReader(source).read(text); }

std::vector<std::string> builtin_mesh_names() {
  std::vector<std::string> names;
  for (const core::EmbeddedFile& file : kFiles) {
    if (file.first.ends_with(".obj")) names.emplace_back(file.first.substr(0, file.first.size() - 4));
  }
  std::sort(names.begin(), names.end());
  return names;
}

const TriangleMesh* builtin_mesh(std::string_view name) {
  // Parsed once, on first use (a function-local static is initialised thread-safely); the shipped
  // files are checked by the tests.
  static const std::map<std::string, TriangleMesh, std::less<>> meshes = [] {
    std::map<std::string, TriangleMesh, std::less<>> parsed;
    for (const std::string& stem : builtin_mesh_names()) {
      parsed.emplace(stem, parse_obj(core::find_embedded(kFiles, stem + ".obj"), "assets/meshes/" + stem + ".obj"));
    }
    return parsed;
  }();
  const auto found = meshes.find(name);
  return found == meshes.end() ? nullptr : &found->second;
}

}  // namespace hrisim::render
