#include "http/api.hpp"

#include <boost/version.hpp>

#include "core/build_info.hpp"
#include "http/static_files.hpp"
#include "render/image_codec.hpp"
#include "render/offscreen_context.hpp"
#include "storage/store.hpp"

namespace hrisim::http {
namespace embedded {
extern const std::pair<std::string_view, std::string_view> kEmbedded[];
extern const int kEmbeddedCount;
}  // namespace embedded

namespace {

std::string_view embedded_file(std::string_view name) {
  for (int i = 0; i < embedded::kEmbeddedCount; ++i) {
    if (embedded::kEmbedded[i].first == name) return embedded::kEmbedded[i].second;
  }
  throw core::Error(core::ErrorCode::internal, "embedded file " + std::string(name) + " is missing");
}

std::string boost_version() {
  return std::to_string(BOOST_VERSION / 100000) + "." + std::to_string(BOOST_VERSION / 100 % 1000) + "." +
         std::to_string(BOOST_VERSION % 100);
}

}  // namespace

nlohmann::json version_info() {
  return {{"name", "hrisim"},
          {"version", core::version()},
          {"git_commit", core::git_commit()},
          {"build_type", core::build_type()},
          {"compiler", core::compiler()},
          {"libraries",
           {{"boost", boost_version()},
            {"eigen", core::eigen_version()},
            {"nlohmann_json", core::json_version()},
            {"opencv", render::opencv_version()},
            {"sqlite", storage::Store::sqlite_version()}}},
          {"opengl",
           {{"version", render::probe_gl().version},
            {"renderer", render::probe_gl().renderer},
            {"vendor", render::probe_gl().vendor}}}};
}

std::shared_ptr<const Router> make_api_router(const ApiContext& context) {
  auto router = std::make_shared<Router>();
  storage::Store* store = context.store;

  router->add("GET", "/healthz", [store](const Request&) {
    try {
      store->ping();
      return Response::json(200, {{"status", "ok"}, {"database", "ok"}});
    } catch (const core::Error& e) {
      return Response::json(503, {{"status", "unavailable"}, {"database", e.what()}});
    }
  });

  const nlohmann::json version = version_info();
  router->add("GET", "/api/v1/version", [version](const Request&) { return Response::json(200, version); });

  router->add("GET", "/api/v1/openapi.yaml", [](const Request&) {
    return Response{200, "application/yaml", std::string(embedded_file("openapi.yaml")), {}};
  });

  auto files = std::make_shared<StaticFiles>(context.web_root);
  router->set_fallback([files](const Request& request) {
    if (request.path == "/api" || request.path.starts_with("/api/")) {
      return Response::error(core::Error(core::ErrorCode::not_found, "no API endpoint at " + request.path,
                                         {{"path", request.path}}));
    }
    return files->serve(request);
  });
  return router;
}

}  // namespace hrisim::http
