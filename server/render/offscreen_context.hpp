#pragma once
// An OpenGL context that renders into memory (OSMesa, software llvmpipe): no display, no GPU needed.
// A context is current on one thread at a time; use one context per rendering thread.
#include <cstdint>
#include <string>
#include <vector>

#include "render/image.hpp"

namespace hrisim::render {

/// What OpenGL implementation answers, as reported by glGetString.
struct GlInfo {
  std::string version;
  std::string renderer;
  std::string vendor;
};

/// OpenGL version requested for every context: 3.3 core, which llvmpipe provides.
inline constexpr int kGlMajorVersion = 3;
inline constexpr int kGlMinorVersion = 3;

class OffscreenContext {
 public:
  /// Creates a width × height RGBA colour buffer with a 24-bit depth buffer, and makes it current on
  /// the calling thread. Throws core::Error when OSMesa cannot create the context.
  OffscreenContext(int width, int height);
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// Makes this context current on the calling thread.
  void make_current();
  int width() const { return width_; }
  int height() const { return height_; }
  GlInfo info() const;
  /// Finishes rendering and returns the colour buffer, top row first.
  ImageRgba8 read_rgba() const;

 private:
  void* context_ = nullptr;  // OSMesaContext, kept opaque so GL headers stay in the .cpp
  int width_;
  int height_;
  std::vector<std::uint8_t> buffer_;
};

/// Creates a 1×1 context once per process and reports the OpenGL implementation; on failure the
/// version field carries the error message.
const GlInfo& probe_gl();

}  // namespace hrisim::render
