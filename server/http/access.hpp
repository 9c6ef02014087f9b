#pragma once
// Who may use the API and from where: bearer tokens with owners and roles, the Host a request names
// (against DNS rebinding), the Origin of browser requests, and the content type of state-changing
// requests on a server without tokens (a foreign page can POST text/plain without asking first).
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "http/router.hpp"
#include "http/ws_tickets.hpp"

namespace hrisim::http {

/// What a token may do: `user` creates and sees its own sessions, runs and uploads; `read` sees its
/// owner's, changes nothing; `admin` sees and changes everyone's.
enum class Role { user, read, admin };

struct Token {
  std::string name;    ///< the owner: tokens with the same name share a namespace; empty for a lone admin token
  std::string secret;  ///< at least kMinimumTokenLength characters
  Role role = Role::user;
};

/// Shortest token secret accepted: guessing 16 random characters is out of reach.
inline constexpr std::size_t kMinimumTokenLength = 16;

/// `SECRET` (one admin token without a name, as before owners) or `NAME:SECRET[:ROLE]`, ROLE being
/// user (default), read or admin. Throws core::Error(bad_request) saying what is wrong.
Token parse_token(const std::string& text);
/// A token file: one `NAME:SECRET[:ROLE]` per line; blank lines and lines starting with '#' skipped.
/// Errors name the line (never the secret).
std::vector<Token> read_token_file(const std::filesystem::path& file);

struct AccessPolicy {
  std::vector<Token> tokens;                 ///< none: the API is open (a server on loopback)
  std::vector<std::string> allowed_origins;  ///< browser origins besides the server's own, scheme://host[:port]
  std::vector<std::string> allowed_hosts;    ///< Host names besides IP addresses and localhost ("*": any)
};

/// The guard every request passes: Host, then Origin (state-changing requests and WebSocket upgrades),
/// then the token (or a WebSocket ticket on an upgrade, or the content type without tokens); fills in
/// the request's caller. /healthz, /api/v1/version and the UI need no token.
std::function<std::optional<Response>(Request&)> make_guard(AccessPolicy policy, std::shared_ptr<TicketBook> tickets);

}  // namespace hrisim::http
