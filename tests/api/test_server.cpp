#include "test_server.hpp"

#include <algorithm>
#include <cctype>

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <regex>
#include <stdexcept>
#include <thread>

namespace hrisim::testing {
namespace {

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

TestServer::TestServer(std::vector<std::string> extra_args, int max_open_files) : database_(dir_ / "var/hrisim.db") {
  std::vector<std::string> args = {HRISIM_BINARY, "serve", "--port", "0", "--db", database_.string(),
                                   "--scenarios", std::string(HRISIM_SOURCE_DIR) + "/scenarios",
                                   "--web", std::string(HRISIM_SOURCE_DIR) + "/web", "--log-requests", "0"};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  int out[2];
  if (pipe(out) != 0) throw std::runtime_error("pipe failed");
  pid_ = fork();
  if (pid_ == 0) {
    // A test killed by ctest's timeout must not leave its server running.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (max_open_files > 0) {
      const rlimit limit{static_cast<rlim_t>(max_open_files), static_cast<rlim_t>(max_open_files)};
      setrlimit(RLIMIT_NOFILE, &limit);
    }
    dup2(out[1], STDOUT_FILENO);
    close(out[0]);
    close(out[1]);
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(out[1]);
  stdout_fd_ = out[0];
  // The server prints "... listening on http://HOST:PORT ..." once it accepts connections.
  const std::regex listening(R"(listening on http://[^:]+:(\d+))");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  std::smatch match;
  while (!std::regex_search(output_, match, listening)) {
    pollfd poll_fd{stdout_fd_, POLLIN, 0};
    if (std::chrono::steady_clock::now() > deadline || poll(&poll_fd, 1, 200) < 0) {
      throw std::runtime_error("hrisim serve did not start; output: " + output_);
    }
    if (poll_fd.revents & (POLLIN | POLLHUP)) {
      char buffer[512];
      const ssize_t n = read(stdout_fd_, buffer, sizeof buffer);
      if (n <= 0) throw std::runtime_error("hrisim serve exited at start; output: " + output_);
      output_.append(buffer, static_cast<std::size_t>(n));
    }
  }
  port_ = static_cast<std::uint16_t>(std::stoi(match[1]));
}

TestServer::~TestServer() {
  if (pid_ > 0) terminate(std::chrono::seconds(20));
  if (stdout_fd_ >= 0) close(stdout_fd_);
}

int TestServer::terminate(std::chrono::seconds limit) {
  if (pid_ <= 0) return -1;
  kill(pid_, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (waitpid(pid_, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
      pid_ = -1;
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  pid_ = -1;
  output();
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

void TestServer::kill_now() {
  if (pid_ <= 0) return;
  kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
}

std::string TestServer::output() {
  char buffer[512];
  pollfd poll_fd{stdout_fd_, POLLIN, 0};
  while (poll(&poll_fd, 1, 0) > 0 && (poll_fd.revents & POLLIN)) {
    const ssize_t n = read(stdout_fd_, buffer, sizeof buffer);
    if (n <= 0) break;
    output_.append(buffer, static_cast<std::size_t>(n));
  }
  return output_;
}

RawConnection::RawConnection(std::uint16_t port, std::chrono::milliseconds receive_timeout, const std::string& source) {
  fd_ = socket(AF_INET, SOCK_STREAM, 0);
  timeval tv{static_cast<time_t>(receive_timeout.count() / 1000),
             static_cast<suseconds_t>(receive_timeout.count() % 1000 * 1000)};
  setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  if (!source.empty()) {
    sockaddr_in local{};
    local.sin_family = AF_INET;
    if (inet_pton(AF_INET, source.c_str(), &local.sin_addr) != 1 ||
        bind(fd_, reinterpret_cast<sockaddr*>(&local), sizeof local) != 0) {
      throw std::runtime_error("cannot bind a client socket to " + source);
    }
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(port);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    throw std::runtime_error("cannot connect to 127.0.0.1:" + std::to_string(port));
  }
}

RawConnection::~RawConnection() { close(fd_); }

bool RawConnection::send(const std::string& bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return false;
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

std::string RawConnection::receive_some() {
  char buffer[4096];
  const ssize_t n = recv(fd_, buffer, sizeof buffer, 0);
  if (n < 0) throw std::runtime_error("receive failed or timed out");
  return std::string(buffer, static_cast<std::size_t>(n));
}

HttpReply RawConnection::read_reply(bool head) {
  std::size_t header_end;
  while ((header_end = pending_.find("\r\n\r\n")) == std::string::npos) {
    const std::string chunk = receive_some();
    if (chunk.empty()) throw std::runtime_error("connection closed before a reply: " + pending_);
    pending_ += chunk;
  }
  HttpReply reply;
  const std::string head_text = pending_.substr(0, header_end);
  pending_.erase(0, header_end + 4);
  std::size_t line_end = head_text.find("\r\n");
  const std::string status_line = head_text.substr(0, line_end);
  reply.status = std::stoi(status_line.substr(status_line.find(' ') + 1, 3));
  while (line_end != std::string::npos) {
    const std::size_t start = line_end + 2;
    line_end = head_text.find("\r\n", start);
    const std::string line = head_text.substr(start, line_end == std::string::npos ? std::string::npos : line_end - start);
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string value = line.substr(colon + 1);
    value.erase(0, value.find_first_not_of(' '));
    reply.headers[lower(line.substr(0, colon))] = value;
  }
  const std::size_t length = head ? 0 : std::stoul(reply.headers.count("content-length") ? reply.headers["content-length"] : "0");
  while (pending_.size() < length) {
    const std::string chunk = receive_some();
    if (chunk.empty()) throw std::runtime_error("connection closed inside a body");
    pending_ += chunk;
  }
  reply.body = pending_.substr(0, length);
  pending_.erase(0, length);
  return reply;
}

bool RawConnection::closed_by_peer() {
  char byte;
  const ssize_t n = recv(fd_, &byte, 1, 0);
  if (n == 0) return true;
  return n < 0 && errno == ECONNRESET;
}

CommandResult run_command(const std::string& command, bool with_stderr) {
  CommandResult result;
  FILE* pipe = popen((command + (with_stderr ? " 2>&1" : " 2>/dev/null")).c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + command);
  char buffer[256];
  while (fgets(buffer, sizeof buffer, pipe)) result.output += buffer;
  const int status = pclose(pipe);
  result.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

HttpReply http(std::uint16_t port, const std::string& method, const std::string& target, const std::string& body,
               const std::string& extra_headers) {
  RawConnection connection(port);
  std::string request = method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n" + extra_headers;
  if (!body.empty() || method == "POST" || method == "PUT") {
    std::string lower = extra_headers;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    if (lower.find("content-type:") == std::string::npos) request += "Content-Type: application/json\r\n";
    request += "Content-Length: " + std::to_string(body.size()) + "\r\n";
  }
  request += "\r\n" + body;
  connection.send(request);
  return connection.read_reply(method == "HEAD");
}

nlohmann::json wait_for_run(std::uint16_t port, const std::string& id, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  for (;;) {
    nlohmann::json run = nlohmann::json::parse(http(port, "GET", "/api/v1/runs/" + id).body);
    if (run["status"] != "queued" && run["status"] != "running") return run;
    if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("run " + id + " did not end: " + run.dump());
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

std::string base64(const std::string& bytes) {
  static const char* const kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t group = 0;
    for (std::size_t k = 0; k < 3; ++k) group = group << 8 | (k < n ? static_cast<std::uint8_t>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) text.push_back(k <= n ? kAlphabet[group >> (18 - 6 * k) & 63] : '=');
  }
  return text;
}

}  // namespace hrisim::testing
