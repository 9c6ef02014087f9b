#include "http/static_files.hpp"

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

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

StaticFiles::StaticFiles(std::filesystem::path root) : root_(std::filesystem::weakly_canonical(root)) {}

Response StaticFiles::serve(const Request& request) const {
  if (request.method != "GET" && request.method != "HEAD") {
    Response response = Response::error(core::Error(core::ErrorCode::method_not_allowed,
                                                    request.method + " is not allowed on " + request.path,
                                                    {{"allowed", "GET, HEAD"}}));
    response.headers.emplace_back("Allow", "GET, HEAD");
    return response;
  }
  const core::Error not_found(core::ErrorCode::not_found, "no file at " + request.path, {{"path", request.path}});
  std::filesystem::path relative;
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
    if (!segment.empty() && segment != ".") relative /= segment;
    start = end + 1;
  }

  std::error_code ec;
  std::filesystem::path file = std::filesystem::weakly_canonical(root_ / relative, ec);
  if (ec) return Response::error(not_found);
  if (std::filesystem::is_directory(file, ec)) file /= "index.html";
  // A symlink inside the root may point outside it: compare canonical paths component by component.
  const auto root_end = std::mismatch(root_.begin(), root_.end(), file.begin(), file.end()).first;
  if (root_end != root_.end() || !std::filesystem::is_regular_file(file, ec)) return Response::error(not_found);

  std::ifstream in(file, std::ios::binary);
  if (!in) return Response::error(not_found);
  std::ostringstream content;
  content << in.rdbuf();
  Response response{200, std::string(content_type_for(file)), content.str(), {}, {}};
  response.headers.emplace_back("Cache-Control", "no-cache");
  return response;
}

}  // namespace hrisim::http
