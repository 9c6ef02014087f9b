#include "render/offscreen_context.hpp"

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>
#include <GL/osmesa.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace hrisim::render {
namespace {

std::string gl_string(GLenum name) {
  const auto* text = reinterpret_cast<const char*>(glGetString(name));
  return text ? text : "";
}

}  // namespace

OffscreenContext::OffscreenContext(int width, int height)
    : width_(width), height_(height), buffer_(static_cast<std::size_t>(width) * height * 4) {
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192) {
    throw core::Error(core::ErrorCode::bad_request,
                      "image size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is outside 1x1 to 8192x8192",
                      {{"width", width}, {"height", height}});
  }
  const int attributes[] = {OSMESA_FORMAT,        OSMESA_RGBA,         OSMESA_DEPTH_BITS,
                            24,                   OSMESA_PROFILE,      OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, kGlMajorVersion, OSMESA_CONTEXT_MINOR_VERSION,
                            kGlMinorVersion,      0};
  context_ = OSMesaCreateContextAttribs(attributes, nullptr);
  if (!context_) {
    throw core::Error(core::ErrorCode::internal, "OSMesa could not create an OpenGL " +
                                                     std::to_string(kGlMajorVersion) + "." +
                                                     std::to_string(kGlMinorVersion) + " core context");
  }
  make_current();
}

OffscreenContext::~OffscreenContext() { OSMesaDestroyContext(static_cast<OSMesaContext>(context_)); }

void OffscreenContext::make_current() {
  if (!OSMesaMakeCurrent(static_cast<OSMesaContext>(context_), buffer_.data(), GL_UNSIGNED_BYTE, width_, height_)) {
    throw core::Error(core::ErrorCode::internal, "OSMesa could not make the context current");
  }
  // Rows in memory top to bottom, as images are stored.
  OSMesaPixelStore(OSMESA_Y_UP, 0);
}

GlInfo OffscreenContext::info() const { return {gl_string(GL_VERSION), gl_string(GL_RENDERER), gl_string(GL_VENDOR)}; }

ImageRgba8 OffscreenContext::read_rgba() const {
  glFinish();
  return {width_, height_, buffer_};
}

const GlInfo& probe_gl() {
  static const GlInfo info = [] {
    try {
      OffscreenContext context(1, 1);
      return context.info();
    } catch (const core::Error& e) {
      return GlInfo{std::string("unavailable: ") + e.what(), "", ""};
    }
  }();
  return info;
}

}  // namespace hrisim::render
