#include "http/static_files.hpp"

#include <zlib.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "core/sha256.hpp"

namespace hrisim::http {

std::string_view content_type_for(const std::filesystem::path& file) {
  static const std::map<std::string, std::string_view, std::less<>> kTypes = {
      {".html", "text/html; charset=utf-8"},  {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"}, {".css", "text/css; charset=utf-8"},
      {".json", "application/json"},          {".yaml", "application/yaml"},
      {".txt", "text/plain; charset=utf-8"},  {".svg", "image/svg+xml"},
      {".png", "image/png"},                  {".jpg", "image/jpeg"},
      {".jpeg", "image/jpeg"},                {".ico", "image/x-icon"},
      {".webp", "image/webp"},                {".wasm", "application/wasm"},
      {".woff2", "font/woff2"},               {".map", "application/json"},
      {".mp4", "video/mp4"}};
  const auto found = kTypes.find(file.extension().string());
  return found == kTypes.end() ? "application/octet-stream" : found->second;
}

struct StaticFiles::File {
  std::filesystem::file_time_type time;
  std::uintmax_t size = 0;
  std::string content_type;
  std::string body;
  std::string etag;
  std::optional<std::string> gzipped;  ///< when the type is text and gzip makes it smaller
};

namespace {

bool compressible(std::string_view type) {
  return type.starts_with("text/") || type == "application/json" || type == "application/yaml" || type == "image/svg+xml" ||
         type == "application/wasm";
}

/// gzip (RFC 1952) of `data`, or nothing when zlib fails.
std::optional<std::string> gzip(std::string_view data) {
  z_stream stream{};
  constexpr int kGzipWindow = 15 + 16;  // 2^15 bytes, with a gzip header
  if (deflateInit2(&stream, Z_DEFAULT_COMPRESSION, Z_DEFLATED, kGzipWindow, 8, Z_DEFAULT_STRATEGY) != Z_OK) return std::nullopt;
  std::string out(deflateBound(&stream, static_cast<uLong>(data.size())), '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  stream.avail_in = static_cast<uInt>(data.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  const int result = deflate(&stream, Z_FINISH);
  out.resize(stream.total_out);
  deflateEnd(&stream);
  if (result != Z_STREAM_END) return std::nullopt;
  return out;
}

/// Whether Accept-Encoding lets gzip through (a q of 0 refuses it).
bool accepts_gzip(const Request& request) {
  const auto header = request.headers.find("accept-encoding");
  if (header == request.headers.end()) return false;
  std::istringstream codings(header->second);
  for (std::string coding; std::getline(codings, coding, ',');) {
    coding.erase(std::remove(coding.begin(), coding.end(), ' '), coding.end());
    const std::string name = coding.substr(0, coding.find(';'));
    if (name != "gzip" && name != "*") continue;
    const std::size_t q = coding.find(";q=");
    return q == std::string::npos || std::strtod(coding.c_str() + q + 3, nullptr) > 0.0;
  }
  return false;
}

/// Whether If-None-Match names `etag` (or is "*"); weak and strong forms compare equal.
bool not_modified(const Request& request, const std::string& etag) {
  const auto header = request.headers.find("if-none-match");
  if (header == request.headers.end()) return false;
  std::istringstream tags(header->second);
  for (std::string tag; std::getline(tags, tag, ',');) {
    tag.erase(std::remove(tag.begin(), tag.end(), ' '), tag.end());
    if (tag.starts_with("W/")) tag.erase(0, 2);
    if (tag == "*" || tag == etag) return true;
  }
  return false;
}

std::string read_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  return content.str();
}

}  // namespace

StaticFiles::StaticFiles(std::filesystem::path root) : root_(std::filesystem::weakly_canonical(root)) {}
StaticFiles::~StaticFiles() = default;

std::shared_ptr<const StaticFiles::File> StaticFiles::load(const std::filesystem::path& path) const {
  std::error_code ec;
  const auto time = std::filesystem::last_write_time(path, ec);
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) return nullptr;
  {
    std::lock_guard lock(mutex_);
    const auto found = cache_.find(path);
    if (found != cache_.end() && found->second->time == time && found->second->size == size) return found->second;
  }
  auto file = std::make_shared<File>();
  file->time = time;
  file->size = size;
  file->content_type = std::string(content_type_for(path));
  file->body = read_file(path);
  // Strong ETags, one per representation: 128 bits of the content's SHA-256.
  file->etag = "\"" + core::sha256_hex(file->body).substr(0, 32) + "\"";
  if (compressible(file->content_type) && file->body.size() >= kGzipMinBytes) {
    if (auto packed = gzip(file->body); packed && packed->size() < file->body.size()) file->gzipped = std::move(packed);
  }
  const std::size_t bytes = file->body.size() + (file->gzipped ? file->gzipped->size() : 0);
  std::lock_guard lock(mutex_);
  if (bytes > kStaticCacheBytes / 4) return file;  // too large to keep
  if (cached_bytes_ + bytes > kStaticCacheBytes) {
    cache_.clear();
    cached_bytes_ = 0;
  }
  if (const auto old = cache_.find(path); old != cache_.end()) {
    cached_bytes_ -= old->second->body.size() + (old->second->gzipped ? old->second->gzipped->size() : 0);
  }
  cache_[path] = file;
  cached_bytes_ += bytes;
  return file;
}

Response StaticFiles::serve(const Request& request) const {
  if (request.method != "GET" && request.method != "HEAD") {
    Response response = Response::error(core::Error(core::ErrorCode::method_not_allowed,
                                                    request.method + " is not allowed on " + request.path,
                                                    {{"allowed", "GET, HEAD"}}));
    response.headers.emplace_back("Allow", "GET, HEAD");
    return response;
  }
  const core::Error not_found(core::ErrorCode::not_found, "no file at " + request.path, {{"path", request.path}});
  std::vector<std::string> segments;
  std::size_t start = 1;
  while (start <= request.path.size()) {
    const std::size_t end = std::min(request.path.find('/', start), request.path.size());
    const std::string_view segment = std::string_view(request.path).substr(start, end - start);
    if (segment == "..") {
      return Response::error(core::Error(core::ErrorCode::bad_request, "path must not contain '..' segments",
                                         {{"path", request.path}}));
    }
    if (segment.find('\\') != std::string_view::npos) {
      return Response::error(core::Error(core::ErrorCode::bad_request, "path must not contain backslashes",
                                         {{"path", request.path}}));
    }
    if (!segment.empty() && segment != ".") segments.emplace_back(segment);
    start = end + 1;
  }

  // /lib/<package>@<version>/… is node_modules/<package>/… when that is the version installed.
  std::filesystem::path relative;
  bool library = false;
  if (segments.size() >= 3 && segments[0] == "lib") {
    const std::size_t at = segments[1].rfind('@');
    if (at == std::string::npos || at == 0) return Response::error(not_found);
    const std::string package = segments[1].substr(0, at), version = segments[1].substr(at + 1);
    const auto manifest = load(root_ / "node_modules" / package / "package.json");
    const auto installed = manifest ? nlohmann::json::parse(manifest->body, nullptr, false) : nlohmann::json();
    if (!installed.is_object() || installed.value("version", "") != version) {
      return Response::error(core::Error(core::ErrorCode::not_found,
                                         "no library " + package + " " + version + " (installed: " +
                                             (installed.is_object() ? installed.value("version", "none") : std::string("none")) + ")",
                                         {{"path", request.path}}));
    }
    relative = std::filesystem::path("node_modules") / package;
    segments.erase(segments.begin(), segments.begin() + 2);
    library = true;
  }
  for (const std::string& segment : segments) relative /= segment;

  std::error_code ec;
  std::filesystem::path path = std::filesystem::weakly_canonical(root_ / relative, ec);
  if (ec) return Response::error(not_found);
  if (std::filesystem::is_directory(path, ec)) path /= "index.html";
  // A symlink inside the root may point outside it: compare canonical paths component by component.
  const auto root_end = std::mismatch(root_.begin(), root_.end(), path.begin(), path.end()).first;
  if (root_end != root_.end() || !std::filesystem::is_regular_file(path, ec)) return Response::error(not_found);
  const auto file = load(path);
  if (!file) return Response::error(not_found);

  const bool zipped = file->gzipped && accepts_gzip(request);
  const std::string etag = zipped ? file->etag.substr(0, file->etag.size() - 1) + "-gz\"" : file->etag;
  Response response{200, file->content_type, "", {}, {}};
  response.headers.emplace_back("ETag", etag);
  response.headers.emplace_back("Cache-Control", library ? std::string(kLibraryCacheControl) : "no-cache");
  if (file->gzipped) response.headers.emplace_back("Vary", "Accept-Encoding");
  if (not_modified(request, etag)) {
    response.status = 304;
    return response;
  }
  if (zipped) response.headers.emplace_back("Content-Encoding", "gzip");
  response.body = zipped ? *file->gzipped : file->body;
  return response;
}

}  // namespace hrisim::http
