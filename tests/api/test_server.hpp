#pragma once
// Starts the real `hrisim serve` binary on a free loopback port with a temporary database, and talks
// raw HTTP to it, so tests can send exactly the bytes a misbehaving client would.
#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/temp_dir.hpp"

namespace hrisim::testing {

struct HttpReply {
  int status = 0;
  std::map<std::string, std::string> headers;  ///< names in lower case
  std::string body;
};

class TestServer {
 public:
  /// Starts `hrisim serve --port 0` with a database in a temporary folder plus `extra_args`, and waits
  /// until it prints the port it listens on; `max_open_files` > 0 lowers its descriptor limit.
  explicit TestServer(std::vector<std::string> extra_args = {}, int max_open_files = 0);
  /// Sends SIGTERM and waits for the process.
  ~TestServer();
  TestServer(const TestServer&) = delete;
  TestServer& operator=(const TestServer&) = delete;

  std::uint16_t port() const { return port_; }
  pid_t pid() const { return pid_; }
  const std::filesystem::path& database() const { return database_; }
  const TempDir& dir() const { return dir_; }

  /// Sends SIGTERM and waits up to `limit` for the exit; returns the exit status, or -1 on time-out.
  int terminate(std::chrono::seconds limit);
  /// Kills the process with SIGKILL (no clean-up of any kind) and waits for it.
  void kill_now();
  /// Everything the server printed on stdout so far (after terminate(): all of it).
  std::string output();

 private:
  TempDir dir_;
  std::filesystem::path database_;
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::string output_;
  std::uint16_t port_ = 0;
};

/// A blocking loopback client connection with a receive time-out.
class RawConnection {
 public:
  /// Connects to 127.0.0.1:port from `source` (another loopback address stands for another client).
  explicit RawConnection(std::uint16_t port, std::chrono::milliseconds receive_timeout = std::chrono::seconds(10),
                         const std::string& source = "");
  ~RawConnection();
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  /// Sends all bytes; false when the peer has closed the connection.
  bool send(const std::string& bytes);
  /// Reads one HTTP response (headers and Content-Length body); throws on time-out or early close.
  HttpReply read_reply(bool head = false);
  /// True when the server has closed the connection (reads EOF or reset within the time-out).
  bool closed_by_peer();

 private:
  std::string receive_some();
  int fd_ = -1;
  std::string pending_;
};

struct CommandResult {
  int exit_status = -1;
  std::string output;  ///< stdout and stderr together
};

/// Runs a shell command to completion; its stderr joins the output unless `with_stderr` is false.
CommandResult run_command(const std::string& command, bool with_stderr = true);

/// One request on a fresh connection with "Connection: close".
HttpReply http(std::uint16_t port, const std::string& method, const std::string& target, const std::string& body = "",
               const std::string& extra_headers = "");

/// Standard base64 of bytes (RFC 4648, padded): a bundle's binary files.
std::string base64(const std::string& bytes);

/// Polls a run until it is no longer queued or running; its last reply. Throws after `limit`.
nlohmann::json wait_for_run(std::uint16_t port, const std::string& id, std::chrono::seconds limit = std::chrono::seconds(120));

}  // namespace hrisim::testing
