#pragma once
// Triangle meshes for furniture: a Wavefront OBJ reader and the meshes shipped in assets/meshes/*.obj
// (embedded in the binary), each in its own frame, standing on z = 0, its front facing +x.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <string_view>
#include <vector>

namespace hrisim::render {

/// Triangles with a normal per vertex, in the mesh's own frame (REP 103: x forward, y left, z up, metres).
struct TriangleMesh {
  std::vector<Eigen::Vector3f> positions;  ///< three per triangle, counter-clockwise seen from outside
  std::vector<Eigen::Vector3f> normals;    ///< one per position, unit length
  Eigen::AlignedBox3f bounds() const;      ///< of the positions; empty box for an empty mesh
};

/// Reads Wavefront OBJ text: `v`, `vn`, `f` (triangles and convex polygons, fan-triangulated; indices
/// v, v/t, v//n, v/t/n, negative = relative), `#` comments; other statements (o, g, s, usemtl, mtllib, vt) are ignored.
/// Faces without normals get their flat face normal (a degenerate face: +z); given normals are normalised.
/// Throws core::Error(core::ErrorCode::bad_request, "<source>:<line>: <reason>", {{"line", n}, {"source", source}})
/// on a malformed number, an index out of range, a face with fewer than 3 vertices, or a file with no
/// faces (named at its last line).
TriangleMesh parse_obj(std::string_view text, const std::string& source);

/// Names (file names without ".obj", sorted) of the meshes shipped in assets/meshes/.
std::vector<std::string> builtin_mesh_names();

/// A shipped mesh by name (parsed once, on first use, thread-safe), or nullptr.
const TriangleMesh* builtin_mesh(std::string_view name);

}  // namespace hrisim::render
