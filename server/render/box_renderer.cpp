#include "render/box_renderer.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/glext.h>

#include <string>

#include "core/error.hpp"
#include "render/offscreen_context.hpp"

namespace hrisim::render {
namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model;
uniform mat4 view_projection;
out vec3 world_normal;
void main() {
  world_normal = mat3(model) * normal;
  gl_Position = view_projection * model * vec4(position, 1.0);
}
)";

// Lit colour, or the flat id colour for segmentation.
constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 world_normal;
uniform vec3 colour;
uniform int flat_colour;
out vec4 fragment;
void main() {
  if (flat_colour == 1) { fragment = vec4(colour, 1.0); return; }
  vec3 light = normalize(vec3(0.3, 0.5, 1.0));
  float lit = 0.35 + 0.65 * max(dot(normalize(world_normal), light), 0.0);
  fragment = vec4(colour * lit, 1.0);
}
)";

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

/// The unit cube centred at the origin: 36 vertices with their face normals.
std::vector<float> unit_cube() {
  std::vector<float> data;
  for (int axis = 0; axis < 3; ++axis) {
    for (const float side : {-1.0f, 1.0f}) {
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = side;
      const Eigen::Vector3f u = Eigen::Vector3f::Unit((axis + 1) % 3), v = Eigen::Vector3f::Unit((axis + 2) % 3);
      const Eigen::Vector3f c = 0.5f * n;
      // Counter-clockwise seen from outside.
      Eigen::Vector3f corners[4] = {c - 0.5f * u - 0.5f * v, c + 0.5f * u - 0.5f * v, c + 0.5f * u + 0.5f * v, c - 0.5f * u + 0.5f * v};
      if (side < 0) std::swap(corners[1], corners[3]);
      for (const int i : {0, 1, 2, 0, 2, 3}) data.insert(data.end(), {corners[i].x(), corners[i].y(), corners[i].z(), n.x(), n.y(), n.z()});
    }
  }
  return data;
}

/// OpenGL's projection for pinhole intrinsics (pixel rows from the top), mapping depth to [-1, 1].
Eigen::Matrix4f projection(const Camera& c) {
  const float w = static_cast<float>(c.width), h = static_cast<float>(c.height), n = static_cast<float>(c.near), f = static_cast<float>(c.far);
  Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
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

}  // namespace

struct BoxRenderer::Gl {
  OffscreenContext context;
  GLuint program = 0, vao = 0, vbo = 0;
  GLint model = -1, view_projection = -1, colour = -1, flat_colour = -1;
  Gl(int width, int height) : context(width, height) {}
};

BoxRenderer::BoxRenderer(int width, int height) : gl_(std::make_unique<Gl>(width, height)) {
  Gl& gl = *gl_;
  gl.program = glCreateProgram();
  glAttachShader(gl.program, compile(GL_VERTEX_SHADER, kVertexShader));
  glAttachShader(gl.program, compile(GL_FRAGMENT_SHADER, kFragmentShader));
  glLinkProgram(gl.program);
  GLint ok = 0;
  glGetProgramiv(gl.program, GL_LINK_STATUS, &ok);
  if (!ok) throw core::Error(core::ErrorCode::internal, "the box shaders do not link");
  gl.model = glGetUniformLocation(gl.program, "model");
  gl.view_projection = glGetUniformLocation(gl.program, "view_projection");
  gl.colour = glGetUniformLocation(gl.program, "colour");
  gl.flat_colour = glGetUniformLocation(gl.program, "flat_colour");
  const std::vector<float> cube = unit_cube();
  glGenVertexArrays(1, &gl.vao);
  glBindVertexArray(gl.vao);
  glGenBuffers(1, &gl.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, gl.vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(cube.size() * sizeof(float)), cube.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<const void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(1);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_CULL_FACE);
}

BoxRenderer::~BoxRenderer() {
  gl_->context.make_current();
  glDeleteBuffers(1, &gl_->vbo);
  glDeleteVertexArrays(1, &gl_->vao);
  glDeleteProgram(gl_->program);
}

Frame BoxRenderer::render(const std::vector<Box>& boxes, const Camera& camera) {
  Gl& gl = *gl_;
  if (camera.width != gl.context.width() || camera.height != gl.context.height()) {
    throw core::Error(core::ErrorCode::bad_request, "the camera's image size is not the renderer's");
  }
  gl.context.make_current();
  glViewport(0, 0, camera.width, camera.height);
  glUseProgram(gl.program);
  glBindVertexArray(gl.vao);
  const Eigen::Matrix4f view_projection = projection(camera) * view(camera);
  glUniformMatrix4fv(gl.view_projection, 1, GL_FALSE, view_projection.data());
  const auto draw = [&](bool ids) {
    glClearColor(ids ? 0.0f : kBackground[0], ids ? 0.0f : kBackground[1], ids ? 0.0f : kBackground[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUniform1i(gl.flat_colour, ids ? 1 : 0);
    for (const Box& box : boxes) {
      Eigen::Affine3d model = box.pose * Eigen::Scaling(box.size);
      const Eigen::Matrix4f matrix = model.matrix().cast<float>();
      glUniformMatrix4fv(gl.model, 1, GL_FALSE, matrix.data());
      // An id as a colour: 8 bits per channel, exact in an 8-bit buffer.
      const float id_colour[3] = {static_cast<float>(box.id & 0xFF) / 255.0f, static_cast<float>((box.id >> 8) & 0xFF) / 255.0f,
                                  static_cast<float>((box.id >> 16) & 0xFF) / 255.0f};
      glUniform3fv(gl.colour, 1, ids ? id_colour : box.colour.data());
      glDrawArrays(GL_TRIANGLES, 0, 36);
    }
  };
  Frame frame;
  const std::size_t pixels = static_cast<std::size_t>(camera.width) * camera.height;
  draw(true);
  const ImageRgba8 ids = gl.context.read_rgba();
  std::vector<float> window_depth(pixels);
  glReadPixels(0, 0, camera.width, camera.height, GL_DEPTH_COMPONENT, GL_FLOAT, window_depth.data());
  frame.ids.resize(pixels);
  frame.depth.resize(pixels);
  const double n = camera.near, f = camera.far;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * camera.width + x;
      const std::uint8_t* p = ids.pixel(x, y);
      frame.ids[i] = p[0] | (p[1] << 8) | (p[2] << 16);
      // GL's rows start at the bottom; depth from the window value back to metres along the axis.
      const float d = window_depth[static_cast<std::size_t>(camera.height - 1 - y) * camera.width + x];
      const double ndc = 2.0 * d - 1.0;
      frame.depth[i] = d >= 1.0f ? 0.0f : static_cast<float>(2.0 * f * n / (f + n - ndc * (f - n)));
    }
  }
  draw(false);
  frame.colour = gl.context.read_rgba();
  return frame;
}

}  // namespace hrisim::render
