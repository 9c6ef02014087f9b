#include "http/static_files.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "support/temp_dir.hpp"

namespace hrisim::http {
namespace {

void write_file(const std::filesystem::path& path, const std::string& content) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path) << content;
}

class StaticFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    write_file(dir_ / "web/index.html", "<h1>hrisim</h1>");
    write_file(dir_ / "web/js/app.js", "console.log(1)");
    write_file(dir_ / "web/docs/index.html", "docs");
    write_file(dir_ / "secret.txt", "outside");
    std::filesystem::create_symlink(dir_ / "secret.txt", dir_ / "web/escape.txt");
  }
  Response fetch(const std::string& path, const std::string& method = "GET") const {
    Request request;
    request.method = method;
    request.path = path;
    return StaticFiles(dir_ / "web").serve(request);
  }
  testing::TempDir dir_;
};

TEST_F(StaticFilesTest, ServesFilesWithTheirType) {
  const Response page = fetch("/");
  EXPECT_EQ(page.status, 200);
  EXPECT_EQ(page.body, "<h1>hrisim</h1>");
  EXPECT_EQ(page.content_type, "text/html; charset=utf-8");
  const Response script = fetch("/js/app.js");
  EXPECT_EQ(script.status, 200);
  EXPECT_EQ(script.content_type, "text/javascript; charset=utf-8");
  EXPECT_EQ(fetch("/docs").body, "docs");
  EXPECT_EQ(fetch("/docs/").body, "docs");
}

TEST_F(StaticFilesTest, MissingFileIs404) { EXPECT_EQ(fetch("/nope.html").status, 404); }

TEST_F(StaticFilesTest, DotDotIsRefused) {
  const Response response = fetch("/../secret.txt");
  EXPECT_EQ(response.status, 400);
  EXPECT_EQ(response.body.find("outside"), std::string::npos);
  EXPECT_EQ(fetch("/js/../../secret.txt").status, 400);
}

TEST_F(StaticFilesTest, SymlinkOutOfTheRootIsNotServed) {
  const Response response = fetch("/escape.txt");
  EXPECT_EQ(response.status, 404);
  EXPECT_EQ(response.body.find("outside"), std::string::npos);
}

TEST_F(StaticFilesTest, OnlyGetAndHead) {
  EXPECT_EQ(fetch("/", "HEAD").status, 200);
  const Response response = fetch("/", "POST");
  EXPECT_EQ(response.status, 405);
  EXPECT_EQ(response.headers.at(0).second, "GET, HEAD");
}

TEST(ContentType, KnownAndUnknownExtensions) {
  EXPECT_EQ(content_type_for("a.css"), "text/css; charset=utf-8");
  EXPECT_EQ(content_type_for("a.png"), "image/png");
  EXPECT_EQ(content_type_for("a.svg"), "image/svg+xml");
  EXPECT_EQ(content_type_for("a.unknown"), "application/octet-stream");
  EXPECT_EQ(content_type_for("Makefile"), "application/octet-stream");
}

}  // namespace
}  // namespace hrisim::http
