// The Modbus client poller against a real peer over loopback (our own TCP
// server standing in for a dimmer rack): values arrive as changes; when the
// peer vanishes the last state stays, one line is logged, and the poller
// reconnects when the peer is back.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <mutex>
#include <thread>

#include "hal_test_support.h"
#include "modbus_test_client.h"
#include "relight/base/log.h"
#include "relight/hal/modbus_poller.h"
#include "relight/hal/modbus_tcp_server.h"

namespace relight::hal {
namespace {

using testing::MapOf;
using testing::RestRegisters;
using testing::TwoFixturePatch;

class LogCapture {
 public:
  LogCapture() {
    SetLogSink([this](LogLevel, const std::string& line) {
      std::lock_guard<std::mutex> lock(mutex_);
      lines_.push_back(line);
    });
  }
  ~LogCapture() { SetLogSink(nullptr); }
  int Count(const std::string& text) {
    std::lock_guard<std::mutex> lock(mutex_);
    int n = 0;
    for (const std::string& l : lines_) n += l.find(text) != std::string::npos ? 1 : 0;
    return n;
  }

 private:
  std::mutex mutex_;
  std::vector<std::string> lines_;
};

// Polls `source` until `pred(changes so far)` or 10 s.
template <typename Pred>
bool PollUntil(InputSource& source, std::vector<ParamChange>* seen, Pred pred) {
  for (int i = 0; i < 1000; ++i) {
    ParamChange out[16];
    const size_t n = source.Poll(0, out, 16);
    seen->insert(seen->end(), out, out + n);
    if (pred(*seen)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

TEST(ModbusPoller, ReadsMappedRegistersKeepsStateWhenThePeerGoesAndReconnects) {
  LogCapture log;
  const Patch patch = TwoFixturePatch();
  const RegisterMap map = MapOf(patch);
  // The peer: a "dimmer rack" with 16 holding registers.
  ModbusTcpConfig peer_config;
  peer_config.port = 0;
  auto peer = std::make_unique<ModbusTcpServer>(peer_config, map, RestRegisters(map));
  ASSERT_TRUE(peer->Start().ok());
  peer_config.port = peer->port();

  ModbusPollerConfig config;
  config.enabled = true;
  config.port = peer_config.port;
  config.rate_hz = 50;
  config.timeout_ms = 200;
  config.backoff_max_ms = 400;
  config.map = {{0, "wash", Channel::kDimmer, 0}, {3, "wash", Channel::kRed, 0}, {9, "spot", Channel::kPan, 0}};
  ModbusPoller poller(config, map, RestRegisters(map));
  ASSERT_TRUE(poller.Start().ok());

  testing::TcpClient console(peer_config.port);
  ASSERT_TRUE(console.Connect());
  ASSERT_EQ(modbus_write_register(console.ctx(), 0, 65535), 1);
  ASSERT_EQ(modbus_write_register(console.ctx(), 3, 128), 1);
  ASSERT_EQ(modbus_write_register(console.ctx(), 9, 32768 + 16384), 1);
  // The poller may read between the console's writes: wait for the final values.
  const auto value_of = [](const std::vector<ParamChange>& s, const char* fixture, Param param) {
    int32_t v = -1;
    for (const ParamChange& c : s) {
      if (c.fixture == testing::FixtureIndexOf(fixture) && c.param == param) v = testing::Raw(c);
    }
    return v;
  };
  std::vector<ParamChange> seen;
  ASSERT_TRUE(PollUntil(poller, &seen, [&](const std::vector<ParamChange>& s) {
    return value_of(s, "spot", Param::kPan) == (135 << 16) && value_of(s, "wash", Param::kDimmer) == 32767 &&
           value_of(s, "wash", Param::kRed) == LevelQ15FromByte(128);
  }));  // 135 degrees: a quarter of the spot's 540
  EXPECT_EQ(value_of(seen, "spot", Param::kDimmer), -1);  // unmapped parameters never change

  // The peer vanishes: no changes (the last state stays), one log line.
  peer.reset();
  seen.clear();
  const auto lost = [&](const std::vector<ParamChange>&) { return !poller.counters().connected; };
  ASSERT_TRUE(PollUntil(poller, &seen, lost));
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));  // several reconnect attempts
  ParamChange out[16];
  EXPECT_EQ(poller.Poll(0, out, 16), 0u);
  EXPECT_EQ(log.Count("modbus-poller: lost") + log.Count("modbus-poller: cannot reach"), 1);

  // Back, holding what it held before except the dimmer, now 0: the poller
  // reconnects, logs once, and delivers only that change.
  std::vector<uint16_t> back = RestRegisters(map);
  back[0] = 0;
  back[3] = 128;
  back[9] = 32768 + 16384;
  peer = std::make_unique<ModbusTcpServer>(peer_config, map, back);
  ASSERT_TRUE(peer->Start().ok());
  ASSERT_TRUE(PollUntil(poller, &seen, [](const std::vector<ParamChange>& s) { return !s.empty(); }));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // a few more reads
  const size_t more = poller.Poll(0, out, 16);
  seen.insert(seen.end(), out, out + more);
  ASSERT_EQ(seen.size(), 1u);
  EXPECT_EQ(seen[0].fixture, testing::FixtureIndexOf("wash"));
  EXPECT_EQ(seen[0].param, Param::kDimmer);
  EXPECT_EQ(testing::Raw(seen[0]), 0);
  EXPECT_EQ(poller.counters().connects, 2u);
  EXPECT_EQ(log.Count("modbus-poller: connected"), 2);
}

TEST(ModbusPoller, StartsWithoutAPeerAndNamesBadMapEntries) {
  const Patch patch = TwoFixturePatch();
  const RegisterMap map = MapOf(patch);
  ModbusPollerConfig config;
  config.port = 1;  // nothing listens on port 1
  config.map = {{0, "ghost", Channel::kDimmer, 0}};
  ModbusPoller bad(config, map, RestRegisters(map));
  const Status st = bad.Start();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("'ghost'"), std::string::npos) << st.message();
  config.map = {{0, "spot", Channel::kDimmer, 0}};
  ModbusPoller absent(config, map, RestRegisters(map));
  EXPECT_TRUE(absent.Start().ok());
  ParamChange out[4];
  EXPECT_EQ(absent.Poll(0, out, 4), 0u);
  absent.Stop();
}

}  // namespace
}  // namespace relight::hal
