// Issue 17 faults: the Modbus TCP server under abuse, over real loopback
// sockets. A client that connects and sends nothing, one that trickles a
// request a byte at a time (slowloris: a byte every 100 ms, the test's
// "1 byte a second" scaled to short timeouts), and 500 connections opened at
// once against max_clients = 8. What must survive: a well-behaved libmodbus
// client keeps reading and writing with a bounded latency, the server's file
// descriptors stay bounded, the silent and slow clients are closed after the
// configured timeouts.
#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "hal_test_support.h"
#include "modbus_test_client.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/hal/modbus_tcp_server.h"

namespace relight::hal {
namespace {

using testing::MapOf;
using testing::RawConnect;
using testing::RestRegisters;
using testing::TcpClient;
using testing::TwoFixturePatch;

constexpr int kMaxClients = 8;
constexpr int kIdleMs = 400, kRequestMs = 400;
constexpr int kFlood = 500;

int OpenFds() {
  int n = 0;
  DIR* d = opendir("/proc/self/fd");
  while (readdir(d) != nullptr) ++n;
  closedir(d);
  return n - 3;  // ".", ".." and the DIR's own fd
}

// True when the server has closed `fd` (read gives 0 or an error) within `ms`.
bool ClosedWithin(int fd, int ms) {
  pollfd p{fd, POLLIN, 0};
  if (poll(&p, 1, ms) <= 0) return false;
  char byte;
  return recv(fd, &byte, 1, MSG_DONTWAIT) <= 0;
}

// A connect() that does not wait for the server's accept queue.
int ConnectNonBlocking(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);  // EINPROGRESS or done
  return fd;
}

class ModbusTcpAbuse : public ::testing::Test {
 protected:
  void SetUp() override {
    ModbusTcpConfig config;
    config.enabled = true;
    config.port = 0;
    config.max_clients = kMaxClients;
    config.idle_timeout_ms = kIdleMs;
    config.request_timeout_ms = kRequestMs;
    server_ = std::make_unique<ModbusTcpServer>(config, map_, RestRegisters(map_));
    ASSERT_TRUE(server_->Start().ok());
  }

  // One write and one read-back by the good client; its latency in ms.
  double GoodRoundTrip(TcpClient& good, uint16_t value) {
    const int64_t t0 = MonotonicUs();
    EXPECT_EQ(modbus_write_register(good.ctx(), kRegDimmer, value), 1) << modbus_strerror(errno);
    uint16_t back = 0;
    EXPECT_EQ(modbus_read_registers(good.ctx(), kRegDimmer, 1, &back), 1) << modbus_strerror(errno);
    EXPECT_EQ(back, value);
    return static_cast<double>(MonotonicUs() - t0) / 1000.0;
  }

  // Round trips every 50 ms for `ms` (the good client is never idle itself);
  // the worst latency in ms.
  double KeepServedFor(TcpClient& good, int ms) {
    double worst = 0;
    const int64_t end = MonotonicUs() + int64_t{ms} * 1000;
    for (uint16_t v = 1000; MonotonicUs() < end; ++v) {
      worst = std::max(worst, GoodRoundTrip(good, v));
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return worst;
  }

  Patch patch_ = TwoFixturePatch();
  RegisterMap map_ = MapOf(patch_);
  std::unique_ptr<ModbusTcpServer> server_;
};

TEST_F(ModbusTcpAbuse, SilentAndSlowClientsAreClosedAndOthersKeepBeingServed) {
  TcpClient good(server_->port());
  ASSERT_TRUE(good.Connect());
  const int silent = RawConnect(server_->port());
  const int slow = RawConnect(server_->port());
  // A write-single trickled a byte every 100 ms: never idle for kIdleMs,
  // but the request is not whole after kRequestMs.
  const uint8_t request[] = {0, 7, 0, 0, 0, 6, 1, 0x06, 0, 1, 0x12, 0x34};
  const int64_t t0 = MonotonicUs();
  double worst_ms = 0;
  bool slow_closed = false;
  for (size_t i = 0; i < sizeof request && !slow_closed; ++i) {
    if (testing::Send(slow, &request[i], 1) != 1) {
      slow_closed = true;
      break;
    }
    worst_ms = std::max(worst_ms, GoodRoundTrip(good, static_cast<uint16_t>(i * 100)));
    slow_closed = ClosedWithin(slow, 100);
  }
  const double slow_closed_ms = static_cast<double>(MonotonicUs() - t0) / 1000.0;
  EXPECT_TRUE(slow_closed) << "a request trickled over " << sizeof request * 100 << " ms was not cut off";
  EXPECT_NE(server_->holding_registers()[kRegPan], 0x1234) << "the slow request was applied";
  // The silent one goes after the idle timeout (poll rounds are 250 ms).
  worst_ms = std::max(worst_ms, KeepServedFor(good, kIdleMs + 300));
  EXPECT_TRUE(ClosedWithin(silent, 0)) << "a silent client outlived idle_timeout_ms";
  worst_ms = std::max(worst_ms, GoodRoundTrip(good, 4321));
  // The good client writes every 100 ms here, so it is never idle itself.
  std::printf("slowloris closed after %.0f ms (request_timeout_ms %d); good client worst round trip %.1f ms\n",
              slow_closed_ms, kRequestMs, worst_ms);
  EXPECT_LT(worst_ms, 1000.0);
  close(silent);
  close(slow);
}

TEST_F(ModbusTcpAbuse, FiveHundredConnectionsAtOnceLeaveFdsBoundedAndTheGoodClientServed) {
  TcpClient good(server_->port());
  ASSERT_TRUE(good.Connect());
  GoodRoundTrip(good, 1);
  std::atomic<int> refusal_lines{0};
  SetLogSink([&](LogLevel, const std::string& line) {
    if (line.find("refused") != std::string::npos) ++refusal_lines;
  });
  const int fds_before = OpenFds();
  std::vector<int> flood;
  double worst_ms = 0;
  for (int i = 0; i < kFlood; ++i) {
    flood.push_back(ConnectNonBlocking(server_->port()));
    if (i % 50 == 49) worst_ms = std::max(worst_ms, GoodRoundTrip(good, static_cast<uint16_t>(i)));
  }
  // The server refuses what it cannot take at once and closes the ones it
  // kept when they stay silent: wait until it has hung up on every one
  // (a connect whose SYN the kernel dropped comes back after 1 s, 3 s).
  std::vector<bool> done(kFlood, false);
  int closed = 0, peak_server_fds = 0;
  uint32_t peak_clients = 0;
  for (int round = 0; round < 600 && closed < kFlood; ++round) {
    peak_server_fds = std::max(peak_server_fds, OpenFds() - fds_before - kFlood);
    peak_clients = std::max(peak_clients, server_->counters().clients);
    for (int i = 0; i < kFlood; ++i) {
      if (!done[static_cast<size_t>(i)] && ClosedWithin(flood[static_cast<size_t>(i)], 0)) {
        done[static_cast<size_t>(i)] = true;
        ++closed;
      }
    }
    worst_ms = std::max(worst_ms, GoodRoundTrip(good, static_cast<uint16_t>(round)));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const ModbusServerCounters c = server_->counters();
  std::printf("%d connections: %u refused at once, the rest closed when idle; %d of %d hung up on; at most %u clients "
              "(max_clients %d), server fds above baseline at most %d, good client worst round trip %.1f ms\n",
              kFlood, c.refused, closed, kFlood, peak_clients, kMaxClients, peak_server_fds, worst_ms);
  EXPECT_EQ(closed, kFlood) << "flood connections still open on the server's side";
  EXPECT_LE(peak_clients, static_cast<uint32_t>(kMaxClients));
  EXPECT_GE(c.refused, static_cast<uint32_t>(kFlood / 2));
  EXPECT_LE(peak_server_fds, kMaxClients) << "the server holds more sockets than max_clients";
  EXPECT_LT(worst_ms, 1000.0);
  // Refusals are logged, at most about one line a second.
  EXPECT_GE(refusal_lines.load(), 1);
  EXPECT_LE(refusal_lines.load(), 20) << "one log line per refused connection";
  SetLogSink(nullptr);
  // The flood's kept connections send nothing: closed after the idle timeout,
  // and then a newcomer gets a slot again.
  for (int fd : flood) close(fd);
  KeepServedFor(good, kIdleMs + 600);
  GoodRoundTrip(good, 77);
  TcpClient late(server_->port());
  ASSERT_TRUE(late.Connect());
  uint16_t back = 0;
  EXPECT_EQ(modbus_read_registers(late.ctx(), kRegDimmer, 1, &back), 1) << modbus_strerror(errno);
  EXPECT_EQ(back, 77);
  EXPECT_LE(OpenFds(), fds_before + 2) << "sockets left open after the flood";
}

// The process runs out of file descriptors: a newcomer waits in the accept
// queue (the server does not spin on it), the clients it has are served, and
// the newcomer is taken once descriptors are free again.
TEST_F(ModbusTcpAbuse, OutOfFileDescriptorsNewcomersWaitAndTheOthersAreServed) {
  TcpClient good(server_->port());
  ASSERT_TRUE(good.Connect());
  GoodRoundTrip(good, 5);
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_NOFILE, &old), 0);
  rlimit tight = old;
  tight.rlim_cur = static_cast<rlim_t>(OpenFds() + 64);
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &tight), 0);
  std::vector<int> fillers;
  for (int fd; (fd = open("/dev/null", O_RDONLY | O_CLOEXEC)) >= 0;) fillers.push_back(fd);
  close(fillers.back());  // one descriptor left: the newcomer's own socket
  fillers.pop_back();
  TcpClient newcomer(server_->port());
  ASSERT_TRUE(newcomer.Connect());  // the kernel completes it; the server cannot accept it
  const double worst_ms = KeepServedFor(good, 600);
  EXPECT_EQ(server_->counters().clients, 1u) << "accepted without a descriptor?";
  for (int fd : fillers) close(fd);
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &old), 0);
  uint16_t back = 0;
  EXPECT_EQ(modbus_read_registers(newcomer.ctx(), kRegDimmer, 1, &back), 1) << modbus_strerror(errno);
  EXPECT_EQ(server_->counters().clients, 2u);
  std::printf("out of fds: good client worst round trip %.1f ms; the newcomer served once fds were free\n", worst_ms);
  EXPECT_LT(worst_ms, 1000.0);
}

}  // namespace
}  // namespace relight::hal
