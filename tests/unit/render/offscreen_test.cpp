#include <gtest/gtest.h>

#define GL_GLEXT_PROTOTYPES
#include <GL/gl.h>

#include "core/error.hpp"
#include "render/image_codec.hpp"
#include "render/offscreen_context.hpp"

namespace hrisim::render {
namespace {

TEST(OffscreenContext, ProvidesTheRequestedCoreProfile) {
  OffscreenContext context(8, 8);
  const GlInfo info = context.info();
  EXPECT_FALSE(info.renderer.empty());
  ASSERT_GE(info.version.size(), 3u);
  const int major = info.version[0] - '0', minor = info.version[2] - '0';
  EXPECT_TRUE(major > kGlMajorVersion || (major == kGlMajorVersion && minor >= kGlMinorVersion)) << info.version;
  EXPECT_EQ(probe_gl().renderer, info.renderer);
}

TEST(OffscreenContext, ClearColourReachesTheImageTopRowFirst) {
  OffscreenContext context(32, 16);
  glClearColor(0.2f, 0.4f, 0.6f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  // A scissored clear paints only the top 4 rows (GL's y axis points up).
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 12, 32, 4);
  glClearColor(1.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  const ImageRgba8 image = context.read_rgba();
  ASSERT_EQ(image.width, 32);
  ASSERT_EQ(image.height, 16);
  const std::uint8_t* top = image.pixel(5, 0);
  EXPECT_EQ(top[0], 255);
  EXPECT_EQ(top[1], 0);
  const std::uint8_t* bottom = image.pixel(5, 15);
  EXPECT_NEAR(bottom[0], 51, 1);
  EXPECT_NEAR(bottom[1], 102, 1);
  EXPECT_NEAR(bottom[2], 153, 1);
  EXPECT_EQ(bottom[3], 255);
}

TEST(OffscreenContext, ImpossibleSizeIsRefused) {
  EXPECT_THROW(OffscreenContext(0, 10), core::Error);
  EXPECT_THROW(OffscreenContext(10, 100000), core::Error);
}

TEST(ImageCodec, PngRoundTripIsLossless) {
  ImageRgba8 image{7, 5, {}};
  for (int i = 0; i < 7 * 5 * 4; ++i) image.pixels.push_back(static_cast<std::uint8_t>(i * 37 % 256));
  const std::string png = encode_png(image);
  ASSERT_GE(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const ImageRgba8 decoded = decode_png(png);
  EXPECT_EQ(decoded.width, 7);
  EXPECT_EQ(decoded.height, 5);
  EXPECT_EQ(decoded.pixels, image.pixels);
}

TEST(ImageCodec, GarbageIsNotAnImage) {
  EXPECT_THROW(decode_png("definitely not a png"), core::Error);
  EXPECT_THROW(decode_png(""), core::Error);
}

TEST(ImageCodec, VersionIsReported) { EXPECT_EQ(opencv_version().substr(0, 2), "4."); }

}  // namespace
}  // namespace hrisim::render
