// relightd's core with its real Modbus TCP server over loopback: several
// clients at once, each at 100 writes/s; the final rendered state must be
// the last value written to every register. (The 60 s soak of the same is
// bench/modbus_soak; this is its few-seconds version.)
#include <gtest/gtest.h>

#include <modbus/modbus.h>

#include <chrono>
#include <thread>

#include "daemon_test_support.h"
#include "relight/hal/modbus_tcp_server.h"
#include "relight/hal/register_map.h"

namespace relight::daemon {
namespace {

// The engine keeps angles in (-180, 180] degrees.
int32_t WrapQ16(int32_t deg_q16) {
  int64_t v = deg_q16 % (int64_t{360} << 16);
  if (v > (int64_t{180} << 16)) v -= int64_t{360} << 16;
  if (v <= -(int64_t{180} << 16)) v += int64_t{360} << 16;
  return static_cast<int32_t>(v);
}

hal::ModbusTcpServer* TcpServerOf(const Daemon& d) {
  for (hal::InputSource* s : d.sources()) {
    if (auto* tcp = dynamic_cast<hal::ModbusTcpServer*>(s)) return tcp;
  }
  return nullptr;
}

TEST(DaemonModbus, EightClientsAt100HzEndOnTheLastValues) {
  DaemonConfig c = testing::SmallConfig();
  c.fps = 30;
  c.modbus_port = 0;
  Daemon d;
  ASSERT_TRUE(d.Open(c).ok());
  ASSERT_TRUE(d.Start().ok());
  hal::ModbusTcpServer* server = TcpServerOf(d);
  ASSERT_NE(server, nullptr);
  const int port = server->port();
  std::atomic<bool> stop{false}, reload{false};
  std::atomic<int64_t> frames{0};
  d.SetFrameObserver([&](const FrameInfo& f) { frames.store(f.frame + 1); });
  Status run_status;
  std::thread runner([&] { run_status = d.Run(stop, reload); });

  // Client k writes register k of the spot's block (0 dimmer ... 7 flags).
  constexpr int kClients = 8, kWrites = 200;
  const auto value_of = [](int reg, int i) -> uint16_t {
    switch (reg) {
      case hal::kRegRed: case hal::kRegGreen: case hal::kRegBlue: return static_cast<uint16_t>((i * 37 + reg) % 256);
      case hal::kRegProfile: return 0;
      case hal::kRegFlags: return static_cast<uint16_t>(i % 2 == 1 ? 1 : 0);  // ends on: 199 is odd
      default: return static_cast<uint16_t>((i * 331 + reg * 1000) % 65536);
    }
  };
  std::vector<int> ok(kClients, 0);
  std::vector<std::thread> clients;
  for (int k = 0; k < kClients; ++k) {
    clients.emplace_back([&, k] {
      modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
      modbus_set_response_timeout(ctx, 2, 0);
      if (modbus_connect(ctx) != 0) {
        modbus_free(ctx);
        return;
      }
      auto next = std::chrono::steady_clock::now();
      for (int i = 0; i < kWrites; ++i) {
        if (modbus_write_register(ctx, k, value_of(k, i)) == 1) ++ok[static_cast<size_t>(k)];
        next += std::chrono::milliseconds(10);
        std::this_thread::sleep_until(next);
      }
      modbus_close(ctx);
      modbus_free(ctx);
    });
  }
  for (auto& t : clients) t.join();
  // Two more frames so the last writes are surely shown.
  const int64_t seen = frames.load();
  while (frames.load() < seen + 2) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  ASSERT_EQ(modbus_connect(ctx), 0);
  uint16_t status[hal::kStatusRegisterCount] = {};
  ASSERT_EQ(modbus_read_input_registers(ctx, 0, hal::kStatusRegisterCount, status), hal::kStatusRegisterCount);
  modbus_close(ctx);
  modbus_free(ctx);
  stop.store(true);
  runner.join();
  ASSERT_TRUE(run_status.ok()) << run_status.ToString();

  for (int k = 0; k < kClients; ++k) EXPECT_EQ(ok[static_cast<size_t>(k)], kWrites) << "client " << k << " starved";
  const std::vector<uint16_t> regs = server->holding_registers();
  for (int k = 0; k < kClients; ++k) EXPECT_EQ(regs[static_cast<size_t>(k)], value_of(k, kWrites - 1)) << "register " << k;
  const hal::FixturePatch& f = d.patch().fixtures[0];
  const FixtureState s = d.engine().state(0);
  EXPECT_EQ(s.dimmer.raw(), hal::LevelQ15FromRegister16(value_of(hal::kRegDimmer, kWrites - 1)));
  EXPECT_EQ(s.pan_deg.raw(), WrapQ16(hal::AngleQ16FromRegister(value_of(hal::kRegPan, kWrites - 1), f.pan_range_q16)));
  EXPECT_EQ(s.tilt_deg.raw(), WrapQ16(hal::AngleQ16FromRegister(value_of(hal::kRegTilt, kWrites - 1), f.tilt_range_q16)));
  for (int ch = 0; ch < 3; ++ch) {
    EXPECT_EQ(s.rgb[ch].raw(), hal::LevelQ15FromByte(value_of(hal::kRegRed + ch, kWrites - 1)));
  }
  const uint32_t frame_counter = (uint32_t{status[hal::kStatusFrameHigh]} << 16) | status[hal::kStatusFrameLow];
  const uint32_t latency_us = (uint32_t{status[hal::kStatusLatencyHigh]} << 16) | status[hal::kStatusLatencyLow];
  EXPECT_GE(frame_counter, static_cast<uint32_t>(seen));
  EXPECT_GT(latency_us, 0u);
  EXPECT_EQ(status[hal::kStatusIllegalValue], 0);
}

}  // namespace
}  // namespace relight::daemon
