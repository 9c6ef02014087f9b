#include "render/scene_renderer.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>

#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "render/mesh.hpp"
#include "render/offscreen_context.hpp"

namespace hrisim::render {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 colour;
layout(location = 3) in uint id;
uniform mat4 view_projection;
uniform vec4 axis_depth;  // metres along the optical axis: dot(axis_depth, position)
out vec3 world_normal;
out vec3 surface_colour;
out float metres;
flat out uint instance;
void main() {
  world_normal = normal;
  surface_colour = colour;
  metres = dot(axis_depth, vec4(position, 1.0));
  instance = id;
  gl_Position = view_projection * vec4(position, 1.0);
}
)";

// One pass writes the three images: the lit colour, the depth in metres (interpolated in perspective,
// so exact, and read back as it is, with no conversion from the depth buffer's window depth), and the
// instance id for segmentation.
constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 world_normal;
in vec3 surface_colour;
in float metres;
flat in uint instance;
layout(location = 0) out vec4 fragment;
layout(location = 1) out uint fragment_id;
layout(location = 2) out float fragment_metres;
void main() {
  vec3 light = normalize(vec3(0.3, 0.5, 1.0));
  float lit = 0.35 + 0.65 * max(dot(normalize(world_normal), light), 0.0);
  fragment = vec4(surface_colour * lit, 1.0);
  fragment_id = instance;
  fragment_metres = metres;
}
)";

constexpr int kFloatsPerVertex = 10;  // position, normal, colour, id (its bits)
constexpr int kRoundSegments = 12;    // around cylinders, spheres and capsules
constexpr int kSphereStacks = 6;      // even: the equator is an edge, so a sphere splits into capsule caps

/// Triangles in a shape's local frame: positions and normals, three vertices per triangle.
struct LocalMesh {
  std::vector<Eigen::Vector3f> positions, normals;
  void add(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
    positions.push_back(p);
    normals.push_back(n);
  }
};

/// The unit cube centred at the origin, faces counter-clockwise seen from outside.
LocalMesh unit_cube() {
  LocalMesh mesh;
  for (int axis = 0; axis < 3; ++axis) {
    for (const float side : {-1.0f, 1.0f}) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = side;
      const Eigen::Vector3f u = Eigen::Vector3f::Unit((axis + 1) % 3), v = Eigen::Vector3f::Unit((axis + 2) % 3);
      const Eigen::Vector3f c = 0.5f * n;
      Eigen::Vector3f corners[4] = {c - 0.5f * u - 0.5f * v, c + 0.5f * u - 0.5f * v, c + 0.5f * u + 0.5f * v, c - 0.5f * u + 0.5f * v};
      if (side < 0) std::swap(corners[1], corners[3]);
      for (const int i : {0, 1, 2, 0, 2, 3}) mesh.add(corners[i], n);
    }
  }
  return mesh;
}

Eigen::Vector3f around(int segment, float radius, float z) {
  const float angle = 2.0f * std::numbers::pi_v<float> * static_cast<float>(segment) / kRoundSegments;
  return {radius * std::cos(angle), radius * std::sin(angle), z};
}

/// The side of a cylinder of radius 0.5 from z = −0.5 to 0.5 (with its caps when `caps`).
LocalMesh unit_cylinder(bool caps) {
  LocalMesh mesh;
  for (int s = 0; s < kRoundSegments; ++s) {
    const Eigen::Vector3f a0 = around(s, 0.5f, -0.5f), a1 = around(s + 1, 0.5f, -0.5f);
    const Eigen::Vector3f b0 = around(s, 0.5f, 0.5f), b1 = around(s + 1, 0.5f, 0.5f);
    const Eigen::Vector3f n0 = around(s, 1.0f, 0.0f), n1 = around(s + 1, 1.0f, 0.0f);
    mesh.add(a0, n0), mesh.add(a1, n1), mesh.add(b1, n1);
    mesh.add(a0, n0), mesh.add(b1, n1), mesh.add(b0, n0);
    if (!caps) continue;
    mesh.add({0, 0, 0.5f}, Eigen::Vector3f::UnitZ()), mesh.add(b0, Eigen::Vector3f::UnitZ()), mesh.add(b1, Eigen::Vector3f::UnitZ());
    mesh.add({0, 0, -0.5f}, -Eigen::Vector3f::UnitZ()), mesh.add(a1, -Eigen::Vector3f::UnitZ()), mesh.add(a0, -Eigen::Vector3f::UnitZ());
  }
  return mesh;
}

/// A sphere of radius 0.5 at the origin in latitude bands.
LocalMesh unit_sphere() {
  LocalMesh mesh;
  const auto point = [](int stack, int segment) {
    const float polar = std::numbers::pi_v<float> * static_cast<float>(stack) / kSphereStacks;
    const float azimuth = 2.0f * std::numbers::pi_v<float> * static_cast<float>(segment) / kRoundSegments;
    return Eigen::Vector3f(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), std::cos(polar));
  };
  for (int t = 0; t < kSphereStacks; ++t) {
    for (int s = 0; s < kRoundSegments; ++s) {
      const Eigen::Vector3f a = point(t, s), b = point(t + 1, s), c = point(t + 1, s + 1), d = point(t, s + 1);
      if (t > 0) mesh.add(0.5f * a, a), mesh.add(0.5f * b, b), mesh.add(0.5f * d, d);
      if (t < kSphereStacks - 1) mesh.add(0.5f * d, d), mesh.add(0.5f * b, b), mesh.add(0.5f * c, c);
    }
  }
  return mesh;
}

/// OpenGL's projection for the camera (pixel rows from the top), mapping depth to [-1, 1].
Eigen::Matrix4f projection(const Camera& c) {
  const float w = static_cast<float>(c.width), h = static_cast<float>(c.height), n = static_cast<float>(c.near), f = static_cast<float>(c.far);
  Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
  if (c.orthographic_width > 0.0) {
    const float span = static_cast<float>(c.orthographic_width);
    p(0, 0) = 2.0f / span;
    p(1, 1) = 2.0f / (span * h / w);
    p(2, 2) = -2.0f / (f - n);
    p(2, 3) = -(f + n) / (f - n);
    p(3, 3) = 1.0f;
    return p;
  }
  p(0, 0) = 2.0f * static_cast<float>(c.fx) / w;
  p(0, 2) = 1.0f - 2.0f * static_cast<float>(c.cx) / w;
  p(1, 1) = 2.0f * static_cast<float>(c.fy) / h;
  p(1, 2) = 2.0f * static_cast<float>(c.cy) / h - 1.0f;
  p(2, 2) = -(f + n) / (f - n);
  p(2, 3) = -2.0f * f * n / (f - n);
  p(3, 2) = -1.0f;
  return p;
}

/// From the map into OpenGL's eye frame (x right, y up, looking down −z) of a REP 103 camera.
Eigen::Matrix4f view(const Camera& c) {
  Eigen::Matrix4d body_to_eye = Eigen::Matrix4d::Zero();
  body_to_eye(0, 1) = -1.0;  // right = −left
  body_to_eye(1, 2) = 1.0;   // up
  body_to_eye(2, 0) = -1.0;  // −forward
  body_to_eye(3, 3) = 1.0;
  return (body_to_eye * c.pose.inverse().matrix()).cast<float>();
}

/// Appends a part's triangles, in the map frame, to the vertex array.
class VertexWriter {
 public:
  explicit VertexWriter(std::vector<float>& out) : out_(out) {}

  /// `local` mapped by `linear` and moved by `offset`; normals by `normal_matrix` (inverse transpose).
  void add(const std::vector<Eigen::Vector3f>& positions, const std::vector<Eigen::Vector3f>& normals, const Eigen::Matrix3f& linear,
           const Eigen::Vector3f& offset, const Eigen::Matrix3f& normal_matrix, const Part& part, std::size_t first = 0,
           std::size_t count = SIZE_MAX) {
    const std::size_t end = std::min(positions.size(), count == SIZE_MAX ? SIZE_MAX : first + count);
    for (std::size_t i = first; i < end; ++i) write(linear * positions[i] + offset, normal_matrix * normals[i], part);
  }
  void add(const LocalMesh& local, const Eigen::Matrix3f& linear, const Eigen::Vector3f& offset, const Eigen::Matrix3f& normal_matrix,
           const Part& part, std::size_t first = 0, std::size_t count = SIZE_MAX) {
    add(local.positions, local.normals, linear, offset, normal_matrix, part, first, count);
  }
  void write(const Eigen::Vector3f& p, const Eigen::Vector3f& n, const Part& part) {
    const Eigen::Vector3f unit = n.normalized();
    float id_bits = 0.0f;
    std::memcpy(&id_bits, &part.id, sizeof id_bits);
    out_.insert(out_.end(), {p.x(), p.y(), p.z(), unit.x(), unit.y(), unit.z(), part.colour[0], part.colour[1], part.colour[2], id_bits});
  }

 private:
  std::vector<float>& out_;
};

struct Shapes {
  LocalMesh cube = unit_cube(), cylinder = unit_cylinder(true), tube = unit_cylinder(false), sphere = unit_sphere();
};

const Shapes& shapes() {
  static const Shapes instance;
  return instance;
}

/// A sphere around the part, in the map frame: centre and radius.
std::pair<Eigen::Vector3d, double> bounding_sphere(const Part& part) {
  if (part.shape == Part::Shape::capsule) return {0.5 * (part.from + part.to), 0.5 * (part.to - part.from).norm() + part.radius};
  return {part.pose.translation(), 0.5 * part.size.norm()};
}

/// Whether a sphere (in the camera's REP 103 frame) may show in the image: it is not wholly outside
/// one of the view volume's six planes.
bool in_view(const Camera& c, const Eigen::Vector3d& centre, double radius) {
  const double x = centre.x(), y = centre.y(), z = centre.z();
  if (x + radius < c.near || x - radius > c.far) return false;
  if (c.orthographic_width > 0.0) {
    const double half_width = c.orthographic_width / 2, half_height = half_width * c.height / c.width;
    return std::abs(y) - radius <= half_width && std::abs(z) - radius <= half_height;
  }
  // The image's edges as planes through the optical centre: y/x from (cx − w)/fx to cx/fx, z/x from
  // (cy − h)/fy to cy/fy; the signed distance of the centre to each, positive inside.
  const auto inside = [&](double along, double lateral, double slope, double sign) {
    return sign * (slope * along - lateral) / std::sqrt(1.0 + slope * slope) >= -radius;
  };
  return inside(x, y, c.cx / c.fx, 1.0) && inside(x, y, (c.cx - c.width) / c.fx, -1.0) && inside(x, z, c.cy / c.fy, 1.0) &&
         inside(x, z, (c.cy - c.height) / c.fy, -1.0);
}

void write_part(VertexWriter& writer, const Part& part) {
  const Shapes& s = shapes();
  const Eigen::Matrix3f rotation = part.pose.linear().cast<float>();
  const Eigen::Vector3f centre = part.pose.translation().cast<float>();
  switch (part.shape) {
    case Part::Shape::box:
    case Part::Shape::cylinder:
    case Part::Shape::sphere: {
      const Eigen::Vector3f size = part.size.cast<float>();
      const LocalMesh& local = part.shape == Part::Shape::box ? s.cube : part.shape == Part::Shape::cylinder ? s.cylinder : s.sphere;
      writer.add(local, rotation * size.asDiagonal(), centre, rotation * size.cwiseInverse().asDiagonal(), part);
      return;
    }
    case Part::Shape::mesh: {
      if (!part.mesh || part.mesh->positions.empty()) return;
      const Eigen::AlignedBox3f bounds = part.mesh->bounds();
      const Eigen::Vector3f extent = bounds.sizes().cwiseMax(1e-6f), fit = part.size.cast<float>().cwiseQuotient(extent);
      // Stretched so its bounds fill the part's box, centred on the pose.
      const Eigen::Matrix3f linear = rotation * fit.asDiagonal();
      writer.add(part.mesh->positions, part.mesh->normals, linear, centre - linear * bounds.center(), rotation * fit.cwiseInverse().asDiagonal(), part);
      return;
    }
    case Part::Shape::capsule: {
      const Eigen::Vector3f from = part.from.cast<float>(), to = part.to.cast<float>(), axis = to - from;
      const float length = axis.norm(), diameter = 2.0f * static_cast<float>(part.radius);
      const Eigen::Matrix3f turn = length > 0.0f ? Eigen::Quaternionf::FromTwoVectors(Eigen::Vector3f::UnitZ(), axis / length).toRotationMatrix()
                                                 : Eigen::Matrix3f::Identity();
      const Eigen::Matrix3f round = turn * (diameter * Eigen::Matrix3f::Identity());
      writer.add(s.tube, turn * Eigen::Vector3f(diameter, diameter, length).asDiagonal(), 0.5f * (from + to),
                 turn * Eigen::Vector3f(1.0f / diameter, 1.0f / diameter, length > 0.0f ? 1.0f / length : 1.0f).asDiagonal(), part);
      // The sphere's upper half caps `to`, its lower half `from` (the first half of its triangles lie above the equator).
      const std::size_t half = s.sphere.positions.size() / 2;
      writer.add(s.sphere, round, to, turn, part, 0, half);
      writer.add(s.sphere, round, from, turn, part, half, half);
      return;
    }
  }
}

GLuint compile(GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024];
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw core::Error(core::ErrorCode::internal, std::string("shader does not compile: ") + log);
  }
  return shader;
}

}  // namespace

Part Part::box(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, std::array<float, 3> colour, std::uint32_t id) {
  Part part;
  part.pose = pose;
  part.size = size;
  part.colour = colour;
  part.id = id;
  return part;
}

Part Part::capsule(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius, std::array<float, 3> colour, std::uint32_t id) {
  Part part;
  part.shape = Shape::capsule;
  part.from = from;
  part.to = to;
  part.radius = radius;
  part.colour = colour;
  part.id = id;
  return part;
}

Camera Camera::pinhole(int width, int height, double horizontal_fov, double near, double far) {
  Camera camera;
  camera.width = width;
  camera.height = height;
  camera.fx = camera.fy = (width / 2.0) / std::tan(horizontal_fov / 2.0);
  camera.cx = width / 2.0;
  camera.cy = height / 2.0;
  camera.near = near;
  camera.far = far;
  return camera;
}

struct SceneRenderer::Gl {
  OffscreenContext context;
  GLuint program = 0, vao = 0, vbo = 0;
  GLuint framebuffer = 0, colour = 0, ids = 0, metres = 0, depth = 0;  ///< the frame: colour, instance ids, depth in metres; the depth test's buffer
  GLint view_projection = -1, axis_depth = -1;
  Gl(int width, int height) : context(width, height) {}
};

SceneRenderer::SceneRenderer(int width, int height) : gl_(std::make_unique<Gl>(width, height)) {
  Gl& gl = *gl_;
  gl.program = glCreateProgram();
  const GLuint vertex = compile(GL_VERTEX_SHADER, kVertexShader), fragment = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  glAttachShader(gl.program, vertex);
  glAttachShader(gl.program, fragment);
  glLinkProgram(gl.program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = 0;
  glGetProgramiv(gl.program, GL_LINK_STATUS, &ok);
  if (!ok) throw core::Error(core::ErrorCode::internal, "the scene shaders do not link");
  gl.view_projection = glGetUniformLocation(gl.program, "view_projection");
  gl.axis_depth = glGetUniformLocation(gl.program, "axis_depth");
  // A framebuffer with three colour images (RGBA8 colour, 32-bit ids, float metres) and 24-bit depth.
  glGenFramebuffers(1, &gl.framebuffer);
  glBindFramebuffer(GL_FRAMEBUFFER, gl.framebuffer);
  const auto attach = [&](GLuint& buffer, GLenum format, GLenum attachment) {
    glGenRenderbuffers(1, &buffer);
    glBindRenderbuffer(GL_RENDERBUFFER, buffer);
    glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachment, GL_RENDERBUFFER, buffer);
  };
  attach(gl.colour, GL_RGBA8, GL_COLOR_ATTACHMENT0);
  attach(gl.ids, GL_R32UI, GL_COLOR_ATTACHMENT1);
  attach(gl.metres, GL_R32F, GL_COLOR_ATTACHMENT2);
  attach(gl.depth, GL_DEPTH_COMPONENT24, GL_DEPTH_ATTACHMENT);
  const GLenum targets[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glDrawBuffers(3, targets);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw core::Error(core::ErrorCode::internal, "the off-screen framebuffer (colour, ids, depth) is incomplete");
  }
  glGenVertexArrays(1, &gl.vao);
  glBindVertexArray(gl.vao);
  glGenBuffers(1, &gl.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, gl.vbo);
  constexpr GLsizei stride = kFloatsPerVertex * sizeof(float);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
  glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(6 * sizeof(float)));
  glVertexAttribIPointer(3, 1, GL_UNSIGNED_INT, stride, reinterpret_cast<const void*>(9 * sizeof(float)));
  for (GLuint attribute = 0; attribute < 4; ++attribute) glEnableVertexAttribArray(attribute);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
  glFrontFace(GL_CW);  // counter-clockwise faces seen from outside, drawn upside down (render_into)
}

SceneRenderer::~SceneRenderer() {
  gl_->context.make_current();
  glDeleteFramebuffers(1, &gl_->framebuffer);
  const GLuint buffers[] = {gl_->colour, gl_->ids, gl_->metres, gl_->depth};
  glDeleteRenderbuffers(4, buffers);
  glDeleteBuffers(1, &gl_->vbo);
  glDeleteVertexArrays(1, &gl_->vao);
  glDeleteProgram(gl_->program);
}

void SceneRenderer::render_into(const Scene& scene, const Camera& camera, const FrameTarget& target) {
  Gl& gl = *gl_;
  if (camera.width != gl.context.width() || camera.height != gl.context.height()) {
    throw core::Error(core::ErrorCode::bad_request, "the camera's image size is not the renderer's");
  }
  gl.context.make_current();
  vertices_.clear();
  VertexWriter writer(vertices_);
  // Parts wholly outside the view are not sent: a robot's camera sees a fraction of the scene.
  const Eigen::Isometry3d to_camera = camera.pose.inverse();
  for (const Part& part : scene) {
    const auto [centre, radius] = bounding_sphere(part);
    if (in_view(camera, to_camera * centre, radius)) write_part(writer, part);
  }
  glViewport(0, 0, camera.width, camera.height);
  glUseProgram(gl.program);
  glBindVertexArray(gl.vao);
  glBindBuffer(GL_ARRAY_BUFFER, gl.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices_.size() * sizeof(float)), vertices_.data(), GL_STREAM_DRAW);
  // Drawn upside down (GL's rows start at the bottom, a frame's at the top), so each image is read
  // back straight into its target, row 0 first; the winding that counts as front turns with it.
  const Eigen::Matrix4f view_projection = Eigen::Vector4f(1.0f, -1.0f, 1.0f, 1.0f).asDiagonal() * projection(camera) * view(camera);
  glUniformMatrix4fv(gl.view_projection, 1, GL_FALSE, view_projection.data());
  // The camera's x (REP 103: forward) of a map point: the first row of the map-to-camera transform.
  const Eigen::Vector4f axis_depth = to_camera.matrix().row(0).transpose().cast<float>();
  glUniform4fv(gl.axis_depth, 1, axis_depth.data());
  const auto count = static_cast<GLsizei>(vertices_.size() / kFloatsPerVertex);
  glBindFramebuffer(GL_FRAMEBUFFER, gl.framebuffer);
  const GLfloat background[] = {kBackground[0], kBackground[1], kBackground[2], 1.0f};
  const GLuint no_id[] = {0, 0, 0, 0};
  const GLfloat no_depth[] = {0.0f, 0.0f, 0.0f, 0.0f};
  const GLfloat farthest = 1.0f;
  glClearBufferfv(GL_COLOR, 0, background);
  glClearBufferuiv(GL_COLOR, 1, no_id);
  glClearBufferfv(GL_COLOR, 2, no_depth);
  glClearBufferfv(GL_DEPTH, 0, &farthest);
  if (count > 0) glDrawArrays(GL_TRIANGLES, 0, count);

  const int w = camera.width, h = camera.height;
  if (target.colour) {
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, target.colour);
  }
  if (target.ids) {
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, w, h, GL_RED_INTEGER, GL_UNSIGNED_INT, target.ids);
  }
  if (target.depth) {
    glReadBuffer(GL_COLOR_ATTACHMENT2);
    glReadPixels(0, 0, w, h, GL_RED, GL_FLOAT, target.depth);
  }
}

Frame SceneRenderer::render(const Scene& scene, const Camera& camera) {
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  Frame frame{{camera.width, camera.height, std::vector<std::uint8_t>(pixels * 4)}, std::vector<float>(pixels), std::vector<std::uint32_t>(pixels)};
  render_into(scene, camera, {frame.colour.pixels.data(), frame.depth.data(), frame.ids.data()});
  return frame;
}

SceneRenderer& renderer_on_this_thread(int width, int height) {
  constexpr std::size_t kRenderersPerThread = 4;
  thread_local std::map<std::pair<int, int>, std::unique_ptr<SceneRenderer>> renderers;
  if (!renderers.contains({width, height}) && renderers.size() >= kRenderersPerThread) renderers.clear();
  auto& renderer = renderers[{width, height}];
  if (!renderer) renderer = std::make_unique<SceneRenderer>(width, height);
  return *renderer;
}

Frame render_on_this_thread(const Scene& scene, const Camera& camera) {
  return renderer_on_this_thread(camera.width, camera.height).render(scene, camera);
}

}  // namespace hrisim::render
