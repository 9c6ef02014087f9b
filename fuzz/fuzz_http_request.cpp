// Fuzz target: the HTTP request path of `hrisim serve` — the guard (Host, Origin, tokens, content type),
// percent-decoding, the router and every handler — against a scratch database, with deferred answers
// computed at once. The input is a request as it would arrive: "METHOD TARGET", header lines, an empty
// line, the body (a missing part is empty).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_server.hpp"
#include "http/router.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  hrisim::fuzz::Server& server = hrisim::fuzz::server();
  hrisim::http::Request request = hrisim::fuzz::parse_request(input);
  hrisim::fuzz::check_reply(server.answer(std::move(request)));
  return 0;
}
