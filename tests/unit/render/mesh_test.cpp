// Wavefront OBJ meshes: faces and their index forms, normals given or computed, bad files refused with
// their line, and the shipped furniture meshes.
#include "render/mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "core/error.hpp"

namespace hrisim::render {
namespace {

void expect_near(const Eigen::Vector3f& actual, const Eigen::Vector3f& expected) {
  EXPECT_NEAR((actual - expected).norm(), 0.0f, 1e-6f) << actual.transpose() << " instead of " << expected.transpose();
}

/// The error parse_obj throws for `text`; fails the test when it accepts it.
core::Error error_of(const std::string& text) {
  try {
    parse_obj(text, "test.obj");
  } catch (const core::Error& e) {
    return e;
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return core::Error(core::ErrorCode::internal, "accepted", {{"line", -1}, {"source", ""}});
}

TEST(Mesh, AQuadWithNormalsIsTwoTrianglesWithThoseNormals) {
  const TriangleMesh mesh = parse_obj(
      "# a quad facing +x\n"
      "o quad\n"
      "mtllib quad.mtl\n"
      "v 0 0 0\nv 0 1 0\nv 0 1 1\nv 0 0 1\n"
      "vt 0 0\n"
      "vn 2 0 0\n"                     // normalised when read
      "vn 0.6 0.8 0\n"
      "s off\nusemtl wood\n"
      "f 1//1 2//2 3//1 4//2\n",
      "quad.obj");
  ASSERT_EQ(mesh.positions.size(), 6u);
  ASSERT_EQ(mesh.normals.size(), 6u);
  // Fan: (1, 2, 3), (1, 3, 4).
  expect_near(mesh.positions[0], {0, 0, 0});
  expect_near(mesh.positions[1], {0, 1, 0});
  expect_near(mesh.positions[2], {0, 1, 1});
  expect_near(mesh.positions[3], {0, 0, 0});
  expect_near(mesh.positions[4], {0, 1, 1});
  expect_near(mesh.positions[5], {0, 0, 1});
  expect_near(mesh.normals[0], {1, 0, 0});
  expect_near(mesh.normals[1], {0.6f, 0.8f, 0});
  expect_near(mesh.normals[2], {1, 0, 0});
  expect_near(mesh.normals[5], {0.6f, 0.8f, 0});
  const Eigen::AlignedBox3f bounds = mesh.bounds();
  expect_near(bounds.min(), {0, 0, 0});
  expect_near(bounds.max(), {0, 1, 1});
  EXPECT_TRUE(TriangleMesh().bounds().isEmpty());
}

TEST(Mesh, IndexFormsAndNegativeIndicesReferToTheSameVertices) {
  const std::string vertices = "v 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nvn 1 0 0\n";
  const TriangleMesh plain = parse_obj(vertices + "f 1//2 2//2 3//2\n", "a.obj");
  const TriangleMesh full = parse_obj(vertices + "f 1/1/2 2/2/2 3/3/2\n", "b.obj");
  const TriangleMesh relative = parse_obj(vertices + "f -3//-1 -2//-1 -1//-1\n", "c.obj");
  const TriangleMesh textured = parse_obj(vertices + "f 1/1 2/2 3/3\n", "d.obj");
  for (const TriangleMesh* mesh : {&plain, &full, &relative, &textured}) {
    ASSERT_EQ(mesh->positions.size(), 3u);
    expect_near(mesh->positions[0], {1, 0, 0});
    expect_near(mesh->positions[1], {0, 1, 0});
    expect_near(mesh->positions[2], {0, 0, 1});
  }
  for (const TriangleMesh* mesh : {&plain, &full, &relative}) {
    for (const Eigen::Vector3f& normal : mesh->normals) expect_near(normal, {1, 0, 0});
  }
  // Without normals: the flat normal of the face, (1, 1, 1) / √3.
  for (const Eigen::Vector3f& normal : textured.normals) expect_near(normal, Eigen::Vector3f(1, 1, 1).normalized());
  // Relative indices count from the vertices read so far, not from the end of the file.
  const TriangleMesh two = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nf -4 -3 -2\n", "two.obj");
  ASSERT_EQ(two.positions.size(), 6u);
  expect_near(two.positions[3], {0, 0, 0});
  expect_near(two.positions[5], {0, 1, 0});
}

TEST(Mesh, FacesWithoutNormalsGetTheirFlatNormal) {
  // Counter-clockwise seen from +z: facing +z; clockwise: facing -z.
  const TriangleMesh up = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "up.obj");
  for (const Eigen::Vector3f& normal : up.normals) expect_near(normal, {0, 0, 1});
  const TriangleMesh down = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 3 2\n", "down.obj");
  for (const Eigen::Vector3f& normal : down.normals) expect_near(normal, {0, 0, -1});
  // A pentagon in the xz plane, counter-clockwise seen from -y: three triangles, all facing -y.
  const TriangleMesh pentagon = parse_obj("v 0 0 0\nv 2 0 0\nv 2 0 1\nv 1 0 2\nv 0 0 1\nf 1 2 3 4 5\n", "pentagon.obj");
  ASSERT_EQ(pentagon.positions.size(), 9u);
  for (const Eigen::Vector3f& normal : pentagon.normals) expect_near(normal, {0, -1, 0});
  // Windows line ends, tabs, comments after a statement and a number with an exponent.
  const TriangleMesh crlf = parse_obj("v 0 0 0\r\nv\t1e0 0 0 # x\r\nv 0 +1 0\r\nf 1 2 3\r\n", "crlf.obj");
  ASSERT_EQ(crlf.positions.size(), 3u);
  expect_near(crlf.positions[1], {1, 0, 0});
  expect_near(crlf.positions[2], {0, 1, 0});
}

TEST(Mesh, ABadIndexNamesItsLine) {
  const core::Error error = error_of("v 0 0 0\nv 1 0 0\nf 1 2 3\n");
  EXPECT_EQ(error.code(), core::ErrorCode::bad_request);
  EXPECT_NE(std::string(error.what()).find("test.obj:3:"), std::string::npos) << error.what();
  EXPECT_EQ(error.details()["line"], 3);
  EXPECT_EQ(error.details()["source"], "test.obj");
  for (const char* text : {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 2 3\n",
                           "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2 2/2 3/2\n",
                           "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/x 2 3\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1/1 2 3\n"}) {
    const core::Error bad = error_of(text);
    EXPECT_EQ(bad.details()["line"], 4) << text << ": " << bad.what();
  }
}

TEST(Mesh, AMalformedNumberOrAShortFaceIsRefused) {
  for (const char* text : {"v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", "v 0 0 0\nv 1 0,5 0\nv 0 1 0\nf 1 2 3\n",
                           "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n",
                           "v 0 0 0\nvn 1 0 x\nv 0 1 0\nf 1 1 1\n", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2.5 3\n"}) {
    const core::Error error = error_of(text);
    const int line = std::string(text).find("\n\n") == std::string::npos ? 2 : 5;
    EXPECT_EQ(error.details()["line"], line) << text << ": " << error.what();
    EXPECT_NE(std::string(error.what()).find("test.obj:" + std::to_string(line) + ":"), std::string::npos) << error.what();
  }
  const core::Error short_face = error_of("v 0 0 0\nv 1 0 0\nf 1 2\n");
  EXPECT_EQ(short_face.details()["line"], 3) << short_face.what();
}

TEST(Mesh, AFileWithoutFacesIsRefused) {
  const core::Error vertices_only = error_of("# nothing but vertices\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
  EXPECT_EQ(vertices_only.code(), core::ErrorCode::bad_request);
  EXPECT_NE(std::string(vertices_only.what()).find("no faces"), std::string::npos) << vertices_only.what();
  EXPECT_EQ(vertices_only.details()["line"], 4);
  EXPECT_EQ(error_of("").details()["line"], 1);
}

TEST(Mesh, TheShippedMeshesStandOnTheFloorWithUnitNormals) {
  const auto names = builtin_mesh_names();
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  for (const char* expected : {"chair", "armchair", "sofa", "table", "coffee_table", "lamp", "stove", "plant", "drawer", "cup",
                               "cutting_board", "glass", "shelf"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }
  for (const std::string& name : names) {
    const TriangleMesh* mesh = builtin_mesh(name);
    ASSERT_NE(mesh, nullptr) << name;
    ASSERT_FALSE(mesh->positions.empty()) << name;
    EXPECT_EQ(mesh->positions.size() % 3, 0u) << name;
    ASSERT_EQ(mesh->normals.size(), mesh->positions.size()) << name;
    const Eigen::AlignedBox3f bounds = mesh->bounds();
    EXPECT_NEAR(bounds.min().z(), 0.0f, 1e-4f) << name;
    EXPECT_GT(bounds.sizes().z(), 0.0f) << name;
    EXPECT_NEAR(bounds.center().x(), 0.0f, 1e-3f) << name << " is centred";
    EXPECT_NEAR(bounds.center().y(), 0.0f, 1e-3f) << name << " is centred";
    for (const Eigen::Vector3f& normal : mesh->normals) ASSERT_NEAR(normal.norm(), 1.0f, 1e-4f) << name;
  }
  EXPECT_EQ(builtin_mesh("chair"), builtin_mesh("chair")) << "parsed once";
  const Eigen::AlignedBox3f chair = builtin_mesh("chair")->bounds();
  EXPECT_GT(chair.sizes().z(), chair.sizes().x()) << "a chair is taller than deep";
  EXPECT_EQ(builtin_mesh("no_such"), nullptr);
  EXPECT_EQ(builtin_mesh("chair.obj"), nullptr);
}

}  // namespace
}  // namespace hrisim::render
