// Modbus TCP server: one thread, poll() over a wake pipe, the listening
// socket and every client; requests cut from per-client buffers by their
// MBAP length and answered by libmodbus (modbus_reply) on that client's
// socket.
//
// Abuse (issue 17, docs/modbus.md "Limits"): at most max_clients at once,
// the rest refused and closed at once with a log line; a client silent for
// idle_timeout_ms is closed; a request begun must be whole within
// request_timeout_ms, so a sender trickling a byte at a time (slowloris)
// cannot hold a slot; pending connections are accepted (and refused) in
// batches so a flood does not starve the clients being served.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <thread>

#include "register_bank.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/hal/modbus_tcp_server.h"

namespace relight::hal {
namespace {

constexpr int kMbapLength = 7;  // transaction(2) protocol(2) length(2) unit(1)
constexpr size_t kClientBuffer = 2 * MODBUS_TCP_MAX_ADU_LENGTH;
constexpr int kAcceptBatch = 64;  // connections taken per poll round: a flood cannot starve the clients

struct Client {
  int fd = -1;
  std::string peer;
  uint8_t buf[kClientBuffer];
  size_t len = 0;
  int64_t last_us = 0;
  int64_t partial_since_us = 0;  // when the unfinished request in buf began (0: none)
};

std::string PeerName(const sockaddr_in& addr) {
  char ip[INET_ADDRSTRLEN] = "?";
  inet_ntop(AF_INET, &addr.sin_addr, ip, sizeof ip);
  return std::string(ip) + ":" + std::to_string(ntohs(addr.sin_port));
}

}  // namespace

struct ModbusTcpServer::Impl {
  ModbusTcpConfig config;
  RegisterBank& bank;
  modbus_t* ctx = nullptr;
  int listen_fd = -1;
  int wake[2] = {-1, -1};
  int port = 0;
  std::thread thread;
  std::vector<std::unique_ptr<Client>> clients;
  std::vector<in_addr_t> allow;
  int64_t last_refusal_log_us = INT64_MIN / 2;
  int refusals_not_logged = 0;
  bool accept_paused = false;  // out of fds at the last accept: the listener skips one poll round

  Impl(ModbusTcpConfig c, RegisterBank& b) : config(std::move(c)), bank(b) {}

  void Close(size_t i, const char* why) {
    Log(LogLevel::kInfo, "modbus-tcp: client %s %s", clients[i]->peer.c_str(), why);
    close(clients[i]->fd);
    clients.erase(clients.begin() + static_cast<long>(i));
    bank.clients().store(static_cast<uint32_t>(clients.size()));
  }

  // Takes up to kAcceptBatch pending connections; false when none is left.
  bool AcceptBatch() {
    for (int i = 0; i < kAcceptBatch; ++i) {
      if (!Accept()) return false;
    }
    return true;
  }

  // One pending connection: kept, or refused and closed. False: none pending
  // (or no fd left: EMFILE; the next round tries again).
  bool Accept() {
    sockaddr_in addr{};
    socklen_t len = sizeof addr;
    const int fd = accept4(listen_fd, reinterpret_cast<sockaddr*>(&addr), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno == EMFILE || errno == ENFILE || errno == ENOBUFS || errno == ENOMEM) {
        // Out of descriptors: the pending connection stays queued. Stop
        // polling the listener for a round, or poll() would spin on it.
        if (!accept_paused) {
          Log(LogLevel::kWarning, "modbus-tcp: cannot accept: %s; new connections wait", std::strerror(errno));
        }
        accept_paused = true;
      }
      return false;
    }
    if (accept_paused) Log(LogLevel::kInfo, "modbus-tcp: accepting connections again");
    accept_paused = false;
    const std::string peer = PeerName(addr);
    const bool allowed = allow.empty() || std::find(allow.begin(), allow.end(), addr.sin_addr.s_addr) != allow.end();
    if (!allowed || static_cast<int>(clients.size()) >= config.max_clients) {
      bank.refused().fetch_add(1);
      close(fd);
      // One line a second at most: a flood must not flood the log too.
      const int64_t now_us = MonotonicUs();
      if (now_us - last_refusal_log_us < 1000000) {
        ++refusals_not_logged;
        return true;
      }
      const std::string more =
          refusals_not_logged > 0 ? "; " + std::to_string(refusals_not_logged) + " more refused since the last such line"
                                  : "";
      Log(LogLevel::kWarning, "modbus-tcp: refused %s (%s)%s", peer.c_str(),
          allowed ? "too many clients: max_clients reached" : "not in the allow-list", more.c_str());
      last_refusal_log_us = now_us;
      refusals_not_logged = 0;
      return true;
    }
    const int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    auto client = std::make_unique<Client>();
    client->fd = fd;
    client->peer = peer;
    client->last_us = MonotonicUs();
    clients.push_back(std::move(client));
    bank.clients().store(static_cast<uint32_t>(clients.size()));
    Log(LogLevel::kInfo, "modbus-tcp: client %s connected", peer.c_str());
    return true;
  }

  // Reads what is there and answers every complete request. False: close it.
  bool Serve(Client& c, const char** why) {
    const ssize_t n = read(c.fd, c.buf + c.len, kClientBuffer - c.len);
    if (n == 0) {
      *why = "disconnected";
      return false;
    }
    if (n < 0) {
      if (errno == EAGAIN || errno == EINTR) return true;
      *why = "lost (read error)";
      return false;
    }
    const int64_t arrival_us = MonotonicUs();
    c.last_us = arrival_us;
    c.len += static_cast<size_t>(n);
    size_t start = 0;
    while (c.len - start >= kMbapLength) {
      const uint8_t* f = c.buf + start;
      const int protocol = (f[2] << 8) | f[3];
      const int length = (f[4] << 8) | f[5];  // unit id + PDU
      if (protocol != 0 || length < 2 || length > MODBUS_TCP_MAX_ADU_LENGTH - 6) {
        bank.bad_frames().fetch_add(1);
        *why = "sent a malformed frame (bad MBAP header); closed";
        return false;  // a TCP stream cannot be resynchronised
      }
      const size_t frame_len = 6 + static_cast<size_t>(length);
      if (c.len - start < frame_len) break;
      uint8_t req[MODBUS_TCP_MAX_ADU_LENGTH + 8] = {};  // padded: libmodbus may read a little past a short PDU
      std::memcpy(req, f, frame_len);
      modbus_set_socket(ctx, c.fd);
      if (!bank.HandleRequest(ctx, req, static_cast<int>(frame_len), 0, arrival_us)) {
        *why = "sent a malformed request or stopped reading answers; closed";
        return false;
      }
      start += frame_len;
    }
    std::memmove(c.buf, c.buf + start, c.len - start);
    c.len -= start;
    // The clock of an unfinished request starts with its first byte.
    if (c.len == 0) {
      c.partial_since_us = 0;
    } else if (start > 0 || c.partial_since_us == 0) {
      c.partial_since_us = arrival_us;
    }
    return true;
  }

  void Run() {
    std::vector<pollfd> fds;
    for (;;) {
      fds.clear();
      fds.push_back({wake[0], POLLIN, 0});
      fds.push_back({listen_fd, static_cast<short>(accept_paused ? 0 : POLLIN), 0});
      for (const auto& c : clients) fds.push_back({c->fd, POLLIN, 0});
      const int rc = poll(fds.data(), fds.size(), 250);
      if (rc < 0 && errno != EINTR) {
        Log(LogLevel::kError, "modbus-tcp: poll: %s; server thread stops", std::strerror(errno));
        return;
      }
      if (fds[0].revents != 0) return;  // Stop()
      const int64_t now_us = MonotonicUs();
      // Clients first (fds[2..] match clients[0..] until one is closed), then accept.
      const size_t served = clients.size();
      for (size_t i = served; i-- > 0;) {
        const short ev = fds[2 + i].revents;
        const char* why = "idle too long; closed";
        bool keep = true;
        Client& c = *clients[i];
        if (ev & (POLLIN | POLLHUP | POLLERR)) keep = Serve(c, &why);
        if (keep && now_us - c.last_us > int64_t{config.idle_timeout_ms} * 1000) {
          keep = false;
        } else if (keep && c.partial_since_us != 0 &&
                   now_us - c.partial_since_us > int64_t{config.request_timeout_ms} * 1000) {
          why = "too slow: a request not whole within request_timeout_ms; closed";
          keep = false;
        }
        if (!keep) Close(i, why);
      }
      if (fds[1].revents & POLLIN) {
        AcceptBatch();
      } else if (accept_paused) {
        Accept();  // one try a round (poll's 250 ms timeout, or a client's traffic)
      }
    }
  }

  void Shutdown() {
    if (thread.joinable()) {
      const char byte = 1;
      if (write(wake[1], &byte, 1) < 0) {
        // The pipe cannot be full (one byte per Stop); nothing else to do.
      }
      thread.join();
    }
    while (!clients.empty()) {
      close(clients.back()->fd);
      clients.pop_back();
    }
    bank.clients().store(0);
    if (listen_fd >= 0) close(listen_fd);
    listen_fd = -1;
    for (int& fd : wake) {
      if (fd >= 0) close(fd);
      fd = -1;
    }
    if (ctx != nullptr) {
      modbus_set_socket(ctx, -1);
      modbus_free(ctx);
    }
    ctx = nullptr;
  }
};

ModbusTcpServer::ModbusTcpServer(ModbusTcpConfig config, const RegisterMap& map, std::vector<uint16_t> initial)
    : ModbusServer(map, std::move(initial)), impl_(std::make_unique<Impl>(std::move(config), bank())) {}

ModbusTcpServer::~ModbusTcpServer() { impl_->Shutdown(); }

int ModbusTcpServer::port() const { return impl_->port; }

Status ModbusTcpServer::DoStart() {
  Impl& m = *impl_;
  m.Shutdown();
  const std::string where = "modbus-tcp: " + m.config.listen + ":" + std::to_string(m.config.port);
  m.allow.clear();
  for (const std::string& a : m.config.allow) {
    in_addr addr{};
    if (inet_pton(AF_INET, a.c_str(), &addr) != 1) {
      return Status(StatusCode::kInvalidArgument, where + ": allow-list entry '" + a + "' is not an IPv4 address");
    }
    m.allow.push_back(addr.s_addr);
  }
  RELIGHT_RETURN_IF_ERROR(m.bank.Init());
  // libmodbus treats an address starting with '0' as "every interface".
  m.ctx = modbus_new_tcp(m.config.listen.c_str(), m.config.port);
  if (m.ctx == nullptr) return Status(StatusCode::kInternal, where + ": modbus_new_tcp failed");
  // A deep accept queue: a burst of connections waits there to be refused
  // at once instead of having its SYNs dropped and retried for seconds.
  m.listen_fd = modbus_tcp_listen(m.ctx, 128);
  if (m.listen_fd < 0) {
    const std::string why = std::strerror(errno);
    m.Shutdown();
    return Status(StatusCode::kIoError, where + ": cannot listen: " + why);
  }
  fcntl(m.listen_fd, F_SETFL, fcntl(m.listen_fd, F_GETFL) | O_NONBLOCK);
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  getsockname(m.listen_fd, reinterpret_cast<sockaddr*>(&bound), &len);
  m.port = ntohs(bound.sin_port);
  if (pipe2(m.wake, O_CLOEXEC | O_NONBLOCK) != 0) {
    m.Shutdown();
    return Status(StatusCode::kIoError, where + ": pipe: " + std::strerror(errno));
  }
  m.thread = std::thread([&m] { m.Run(); });
  Log(LogLevel::kInfo, "modbus-tcp: listening on %s:%d (%d fixtures, holding registers 0..%d)", m.config.listen.c_str(),
      m.port, m.bank.input().map().fixture_count(), m.bank.input().map().holding_count() - 1);
  return Status::Ok();
}

void ModbusTcpServer::DoStop() { impl_->Shutdown(); }

}  // namespace relight::hal
