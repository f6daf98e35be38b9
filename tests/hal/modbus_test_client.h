// Test-side Modbus helpers: a libmodbus TCP client, raw loopback sockets for
// malformed traffic, and running mbpoll (an independent client).
#pragma once

#include <arpa/inet.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

namespace relight::hal::testing {

class TcpClient {
 public:
  explicit TcpClient(int port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    modbus_set_response_timeout(ctx_, 2, 0);
  }
  ~TcpClient() {
    modbus_close(ctx_);
    modbus_free(ctx_);
  }
  bool Connect() { return modbus_connect(ctx_) == 0; }
  modbus_t* ctx() { return ctx_; }

 private:
  modbus_t* ctx_;
};

// A plain TCP connection to 127.0.0.1:port from `from` (a loopback address).
inline int RawConnect(int port, const char* from = "127.0.0.1") {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  inet_pton(AF_INET, from, &local.sin_addr);
  EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local), 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  timeval tv{2, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  return fd;
}

// send() without SIGPIPE: the server may have hung up on a misbehaving socket.
inline ssize_t Send(int fd, const void* data, size_t size) { return send(fd, data, size, MSG_NOSIGNAL); }

// Runs a shell command; returns its exit status and fills *out with stdout+stderr.
inline int Run(const std::string& command, std::string* out) {
  out->clear();
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (p == nullptr) return -1;
  std::array<char, 512> buf{};
  while (fgets(buf.data(), static_cast<int>(buf.size()), p) != nullptr) *out += buf.data();
  const int status = pclose(p);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline bool HaveTool(const char* name) {
  std::string out;
  return Run(std::string("command -v ") + name, &out) == 0;
}

}  // namespace relight::hal::testing
