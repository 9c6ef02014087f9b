#include "http/static_files.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <fstream>
#include <thread>

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
  static Response fetch_from(const StaticFiles& files, const std::string& path, std::map<std::string, std::string> headers = {}) {
    Request request;
    request.method = "GET";
    request.path = path;
    request.headers = std::move(headers);
    return files.serve(request);
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

std::string header(const Response& response, const std::string& name) {
  for (const auto& [key, value] : response.headers) {
    if (key == name) return value;
  }
  return "";
}

std::string gunzip(const std::string& packed) {
  z_stream stream{};
  EXPECT_EQ(inflateInit2(&stream, 15 + 16), Z_OK);
  std::string out(1 << 20, '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(packed.data()));
  stream.avail_in = static_cast<uInt>(packed.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(inflate(&stream, Z_FINISH), Z_STREAM_END);
  out.resize(stream.total_out);
  inflateEnd(&stream);
  return out;
}

TEST_F(StaticFilesTest, AnETagAnswersAConditionalGetWith304AndChangesWithTheFile) {
  const StaticFiles files(dir_ / "web");
  const Response first = fetch_from(files, "/js/app.js");
  const std::string etag = header(first, "ETag");
  ASSERT_EQ(etag.size(), 34u) << "128 bits in hex, quoted";
  EXPECT_EQ(header(first, "Cache-Control"), "no-cache");
  const Response again = fetch_from(files, "/js/app.js", {{"if-none-match", etag}});
  EXPECT_EQ(again.status, 304);
  EXPECT_TRUE(again.body.empty());
  EXPECT_EQ(header(again, "ETag"), etag);
  EXPECT_EQ(fetch_from(files, "/js/app.js", {{"if-none-match", "\"other\", W/" + etag}}).status, 304) << "a list, a weak form";
  EXPECT_EQ(fetch_from(files, "/js/app.js", {{"if-none-match", "\"other\""}}).status, 200);
  // A new content (and size): a new ETag, though the cache held the old one.
  write_file(dir_ / "web/js/app.js", "console.log(22)");
  const Response changed = fetch_from(files, "/js/app.js", {{"if-none-match", etag}});
  EXPECT_EQ(changed.status, 200);
  EXPECT_EQ(changed.body, "console.log(22)");
  EXPECT_NE(header(changed, "ETag"), etag);
}

TEST_F(StaticFilesTest, TextGoesGzippedToClientsThatAcceptIt) {
  std::string script;
  for (int i = 0; i < 400; ++i) script += "export const value" + std::to_string(i) + " = " + std::to_string(i) + ";\n";
  write_file(dir_ / "web/big.js", script);
  write_file(dir_ / "web/image.png", std::string(4096, 'x'));
  const StaticFiles files(dir_ / "web");
  const Response zipped = fetch_from(files, "/big.js", {{"accept-encoding", "gzip, deflate, br"}});
  EXPECT_EQ(header(zipped, "Content-Encoding"), "gzip");
  EXPECT_EQ(header(zipped, "Vary"), "Accept-Encoding");
  EXPECT_LT(zipped.body.size(), script.size() / 3);
  EXPECT_EQ(gunzip(zipped.body), script);
  const Response plain = fetch_from(files, "/big.js");
  EXPECT_EQ(plain.body, script);
  EXPECT_EQ(header(plain, "Content-Encoding"), "");
  EXPECT_NE(header(plain, "ETag"), header(zipped, "ETag")) << "one ETag per representation";
  EXPECT_EQ(fetch_from(files, "/big.js", {{"accept-encoding", "gzip;q=0, identity"}}).body, script);
  EXPECT_EQ(header(fetch_from(files, "/image.png", {{"accept-encoding", "gzip"}}), "Content-Encoding"), "") << "not text";
  EXPECT_EQ(header(fetch_from(files, "/index.html", {{"accept-encoding", "gzip"}}), "Content-Encoding"), "") << "too small to pay";
}

TEST_F(StaticFilesTest, LibrariesAreServedAtTheirInstalledVersionAndKeptForAYear) {
  write_file(dir_ / "web/node_modules/three/package.json", R"({"name": "three", "version": "0.187.0"})");
  write_file(dir_ / "web/node_modules/three/build/three.module.js", "export {}");
  const StaticFiles files(dir_ / "web");
  const Response library = fetch_from(files, "/lib/three@0.187.0/build/three.module.js");
  EXPECT_EQ(library.status, 200);
  EXPECT_EQ(library.body, "export {}");
  EXPECT_EQ(header(library, "Cache-Control"), kLibraryCacheControl);
  const Response other = fetch_from(files, "/lib/three@0.150.0/build/three.module.js");
  EXPECT_EQ(other.status, 404);
  EXPECT_NE(other.body.find("installed: 0.187.0"), std::string::npos) << other.body;
  EXPECT_EQ(fetch_from(files, "/lib/uplot@1.0.0/x.js").status, 404) << "not installed";
  EXPECT_EQ(fetch_from(files, "/lib/three/build/three.module.js").status, 404) << "no version";
  EXPECT_EQ(fetch_from(files, "/lib/three@0.187.0/../../secret.txt").status, 400);
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
