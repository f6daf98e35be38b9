// The Modbus TCP server over real loopback sockets: libmodbus as a client,
// mbpoll as an independent one, raw sockets for garbage and half requests.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "hal_test_support.h"
#include "modbus_test_client.h"
#include "relight/hal/modbus_tcp_server.h"

namespace relight::hal {
namespace {

using testing::LayoutPatch;
using testing::MapOf;
using testing::RawConnect;
using testing::RestRegisters;
using testing::TcpClient;
using testing::TwoFixturePatch;

class ModbusTcp : public ::testing::Test {
 protected:
  void SetUp() override { StartServer({}); }

  void StartServer(std::vector<std::string> allow) {
    server_.reset();
    ModbusTcpConfig config;
    config.enabled = true;
    config.port = 0;  // any free port: tests run in parallel
    config.allow = std::move(allow);
    config.idle_timeout_ms = 60000;
    server_ = std::make_unique<ModbusTcpServer>(config, map_, RestRegisters(map_));
    const Status st = server_->Start();
    ASSERT_TRUE(st.ok()) << st.ToString();
    ASSERT_GT(server_->port(), 0);
  }

  std::vector<ParamChange> Drain() {
    std::vector<ParamChange> all(64);
    all.resize(server_->Poll(0, all.data(), all.size()));
    return all;
  }

  // A client that must still be served: reads the status frame counter.
  void ExpectServed(TcpClient& c) {
    uint16_t regs[2] = {};
    EXPECT_EQ(modbus_read_input_registers(c.ctx(), kStatusFrameHigh, 2, regs), 2) << modbus_strerror(errno);
  }

  Patch patch_ = TwoFixturePatch();
  RegisterMap map_ = MapOf(patch_);
  std::unique_ptr<ModbusTcpServer> server_;
};

TEST_F(ModbusTcp, WritesBecomeChangesAndReadBack) {
  TcpClient c(server_->port());
  ASSERT_TRUE(c.Connect());
  ASSERT_EQ(modbus_write_register(c.ctx(), 8 + kRegPan, 32768 + 8192), 1);  // wash pan: 1/8 of 360 = 45 deg
  const uint16_t rgb[3] = {255, 128, 0};
  ASSERT_EQ(modbus_write_registers(c.ctx(), kRegRed, 3, rgb), 3);
  // The answer comes after the write is handed over: the changes are there now.
  const std::vector<ParamChange> got = Drain();
  ASSERT_EQ(got.size(), 3u);  // spot r, g (b stays 0) and wash pan
  EXPECT_EQ(got[0].fixture, testing::FixtureIndexOf("spot"));
  EXPECT_EQ(got[0].param, Param::kRed);
  EXPECT_EQ(testing::Raw(got[0]), 32767);
  EXPECT_EQ(got[1].param, Param::kGreen);
  EXPECT_EQ(testing::Raw(got[1]), LevelQ15FromByte(128));
  EXPECT_EQ(got[2].fixture, testing::FixtureIndexOf("wash"));
  EXPECT_EQ(testing::Raw(got[2]), 45 << 16);
  EXPECT_GT(got[2].time_us, 0);
  uint16_t back[16] = {};
  ASSERT_EQ(modbus_read_registers(c.ctx(), 0, 16, back), 16);
  EXPECT_EQ(back[kRegRed], 255);
  EXPECT_EQ(back[kRegGreen], 128);
  EXPECT_EQ(back[8 + kRegPan], 32768 + 8192);
  EXPECT_EQ(back[kRegFlags], kFlagOn);
  // Read/write and mask write go through the same checks.
  uint16_t rw_back[2] = {};
  const uint16_t tilt = 0;
  ASSERT_EQ(modbus_write_and_read_registers(c.ctx(), kRegTilt, 1, &tilt, kRegPan, 2, rw_back), 2);
  EXPECT_EQ(rw_back[1], 0);
  ASSERT_EQ(modbus_mask_write_register(c.ctx(), kRegBlue, 0x0000, 0x0040), 1);
  const std::vector<ParamChange> more = Drain();
  ASSERT_EQ(more.size(), 2u);
  EXPECT_EQ(more[0].param, Param::kTilt);
  EXPECT_EQ(testing::Raw(more[0]), -(135 << 16));
  EXPECT_EQ(more[1].param, Param::kBlue);
  EXPECT_EQ(testing::Raw(more[1]), LevelQ15FromByte(0x40));
}

TEST_F(ModbusTcp, IllegalAddressesAndValuesGetExceptionsAndChangeNothing) {
  TcpClient c(server_->port());
  ASSERT_TRUE(c.Connect());
  EXPECT_EQ(modbus_write_register(c.ctx(), 16, 1), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_write_register(c.ctx(), kRegRed, 256), -1);
  EXPECT_EQ(errno, EMBXILVAL);
  EXPECT_EQ(modbus_write_register(c.ctx(), kRegFlags, 0x8001), -1);
  EXPECT_EQ(errno, EMBXILVAL);
  // A block write with one bad value is refused whole: no silently clipped state.
  const uint16_t values[4] = {65535, 100, 100, 999};  // dimmer, pan, tilt, red = 999
  EXPECT_EQ(modbus_write_registers(c.ctx(), 0, 4, values), -1);
  EXPECT_EQ(errno, EMBXILVAL);
  uint16_t regs[16];
  EXPECT_EQ(modbus_read_registers(c.ctx(), 10, 7, regs), -1);
  EXPECT_EQ(errno, EMBXILADD);
  uint8_t coils[4];
  EXPECT_EQ(modbus_read_bits(c.ctx(), 0, 4, coils), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_TRUE(Drain().empty());
  ASSERT_EQ(modbus_read_registers(c.ctx(), 0, 16, regs), 16);
  EXPECT_EQ(regs[kRegDimmer], 0);
  EXPECT_EQ(regs[kRegRed], 0);
  const ModbusServerCounters counters = server_->counters();
  EXPECT_EQ(counters.illegal_address, 3u);
  EXPECT_EQ(counters.illegal_value, 3u);
  EXPECT_EQ(counters.clients, 1u);
}

TEST_F(ModbusTcp, StatusRegistersShowFramesLatencyAndCounters) {
  TcpClient c(server_->port());
  ASSERT_TRUE(c.Connect());
  EXPECT_EQ(modbus_write_register(c.ctx(), 99, 1), -1);
  server_->OnFrameOut(0x12345, 0x00010203);
  uint16_t status[kStatusRegisterCount] = {};
  ASSERT_EQ(modbus_read_input_registers(c.ctx(), 0, kStatusRegisterCount, status), kStatusRegisterCount);
  EXPECT_EQ(status[kStatusFrameHigh], 0x1);
  EXPECT_EQ(status[kStatusFrameLow], 0x2345);
  EXPECT_EQ(status[kStatusLatencyHigh], 0x1);
  EXPECT_EQ(status[kStatusLatencyLow], 0x0203);
  EXPECT_EQ(status[kStatusIllegalAddress], 1);
  EXPECT_EQ(status[kStatusClients], 1);
  EXPECT_EQ(status[kStatusFixtures], 2);
}

TEST_F(ModbusTcp, GarbageClosesOnlyThatClient) {
  TcpClient good(server_->port());
  ASSERT_TRUE(good.Connect());
  const int bad = RawConnect(server_->port());
  const uint8_t garbage[] = {0xDE, 0xAD, 0xBE, 0xEF, 0xFF, 0xFF, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06};
  ASSERT_EQ(testing::Send(bad, garbage, sizeof garbage), static_cast<ssize_t>(sizeof garbage));
  char byte;
  EXPECT_EQ(read(bad, &byte, 1), 0);  // the server hangs up on it
  close(bad);
  ExpectServed(good);
  // A well-framed request whose PDU length lies about its byte count.
  const int liar = RawConnect(server_->port());
  const uint8_t lie[] = {0, 1, 0, 0, 0, 8, 1, 0x10, 0, 0, 0, 1, 200, 0};
  ASSERT_EQ(testing::Send(liar, lie, sizeof lie), static_cast<ssize_t>(sizeof lie));
  EXPECT_EQ(read(liar, &byte, 1), 0);
  close(liar);
  ExpectServed(good);
  EXPECT_EQ(server_->counters().bad_frames, 2u);
}

TEST_F(ModbusTcp, HalfRequestsAndSilentClientsDoNotHoldUpOthers) {
  const int silent = RawConnect(server_->port());
  const int half = RawConnect(server_->port());
  const uint8_t head[] = {0, 7, 0, 0, 0, 6, 1, 0x06};  // a write-single cut short
  ASSERT_EQ(testing::Send(half, head, sizeof head), static_cast<ssize_t>(sizeof head));
  TcpClient good(server_->port());
  ASSERT_TRUE(good.Connect());
  for (int i = 0; i < 20; ++i) {
    ASSERT_EQ(modbus_write_register(good.ctx(), kRegDimmer, static_cast<uint16_t>(i * 1000)), 1);
  }
  ExpectServed(good);
  // The half request completed later is answered like any other.
  const uint8_t rest[] = {0, 1, 0x12, 0x34};  // register 1 (pan) = 0x1234
  ASSERT_EQ(testing::Send(half, rest, sizeof rest), static_cast<ssize_t>(sizeof rest));
  uint8_t answer[12] = {};
  ASSERT_EQ(read(half, answer, sizeof answer), 12);
  EXPECT_EQ(answer[7], 0x06);  // echo of a write-single: success
  EXPECT_EQ(server_->holding_registers()[kRegPan], 0x1234);
  // A client that vanishes halfway through a request.
  const int quitter = RawConnect(server_->port());
  ASSERT_EQ(testing::Send(quitter, head, 5), 5);
  close(quitter);
  ExpectServed(good);
  close(silent);
  close(half);
  ExpectServed(good);
}

TEST_F(ModbusTcp, EightClientsAtOnceEndOnTheirLastWrites) {
  constexpr int kClients = 8, kWrites = 150;
  std::atomic<int> failures{0};
  std::atomic<bool> done{false};
  // The daemon side: a consumer applying every change to a shadow state.
  std::vector<int32_t> shadow_red(2, -1), shadow_pan(2, -1);
  std::thread consumer([&] {
    std::vector<ParamChange> out(64);
    for (;;) {
      const bool last = done.load();
      const size_t n = server_->Poll(0, out.data(), out.size());
      for (size_t i = 0; i < n; ++i) {
        const int f = out[i].fixture == testing::FixtureIndexOf("spot") ? 0 : 1;
        if (out[i].param == Param::kRed) shadow_red[f] = testing::Raw(out[i]);
        if (out[i].param == Param::kPan) shadow_pan[f] = testing::Raw(out[i]);
      }
      if (last && n == 0) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  });
  std::vector<std::thread> clients;
  std::vector<int> served(kClients, 0);
  for (int k = 0; k < kClients; ++k) {
    clients.emplace_back([&, k] {
      TcpClient c(server_->port());
      if (!c.Connect()) {
        failures.fetch_add(1);
        return;
      }
      // Client k owns fixture k % 2's red (k < 2) or writes pan of fixture k % 2.
      for (int i = 0; i < kWrites; ++i) {
        const int base = (k % 2) * 8;
        const uint16_t red = static_cast<uint16_t>((i * 7 + k) % 256);
        const uint16_t pan = static_cast<uint16_t>(i * 400 + k);
        const int rc = k < 2 ? modbus_write_register(c.ctx(), base + kRegRed, red)
                             : modbus_write_register(c.ctx(), base + kRegPan, pan);
        if (rc != 1) failures.fetch_add(1); else ++served[k];
      }
    });
  }
  for (auto& t : clients) t.join();
  // Every client finishes with the same final value on the shared pan registers.
  TcpClient last(server_->port());
  ASSERT_TRUE(last.Connect());
  const uint16_t final_pan[2] = {40000, 20000};
  ASSERT_EQ(modbus_write_register(last.ctx(), kRegPan, final_pan[0]), 1);
  ASSERT_EQ(modbus_write_register(last.ctx(), 8 + kRegPan, final_pan[1]), 1);
  done.store(true);
  consumer.join();
  EXPECT_EQ(failures.load(), 0);
  for (int k = 0; k < kClients; ++k) EXPECT_EQ(served[k], kWrites) << "client " << k << " starved";
  const std::vector<uint16_t> regs = server_->holding_registers();
  for (int f = 0; f < 2; ++f) {
    const uint16_t last_red = static_cast<uint16_t>(((kWrites - 1) * 7 + f) % 256);
    EXPECT_EQ(regs[static_cast<size_t>(f * 8 + kRegRed)], last_red);
    EXPECT_EQ(shadow_red[f], LevelQ15FromByte(last_red));
    EXPECT_EQ(regs[static_cast<size_t>(f * 8 + kRegPan)], final_pan[f]);
    EXPECT_EQ(shadow_pan[f], AngleQ16FromRegister(final_pan[f], map_.fixture(f).pan_range_q16));
  }
}

TEST_F(ModbusTcp, AllowListRefusesOtherPeers) {
  StartServer({"127.0.0.2"});
  const int stranger = RawConnect(server_->port(), "127.0.0.1");
  const uint8_t read_req[] = {0, 1, 0, 0, 0, 6, 1, 0x03, 0, 0, 0, 1};
  (void)!testing::Send(stranger, read_req, sizeof read_req);
  uint8_t answer[16];
  EXPECT_LE(read(stranger, answer, sizeof answer), 0);  // closed, no answer
  close(stranger);
  const int friend_fd = RawConnect(server_->port(), "127.0.0.2");
  ASSERT_EQ(testing::Send(friend_fd, read_req, sizeof read_req), static_cast<ssize_t>(sizeof read_req));
  EXPECT_EQ(read(friend_fd, answer, sizeof answer), 11);  // MBAP 7 + fc, count, 2 bytes
  EXPECT_EQ(answer[7], 0x03);
  close(friend_fd);
  EXPECT_EQ(server_->counters().refused, 1u);
}

TEST_F(ModbusTcp, StopsAndStartsAgainAndReportsABusyPort) {
  const int port = server_->port();
  ModbusTcpConfig config;
  config.port = port;
  ModbusTcpServer second(config, map_, RestRegisters(map_));
  const Status st = second.Start();
  EXPECT_EQ(st.code(), StatusCode::kIoError);
  EXPECT_NE(st.message().find("127.0.0.1:" + std::to_string(port)), std::string::npos) << st.message();
  server_->Stop();
  ASSERT_TRUE(second.Start().ok());
  TcpClient c(port);
  ASSERT_TRUE(c.Connect());
  EXPECT_EQ(modbus_write_register(c.ctx(), kRegDimmer, 5), 1);
}

// A patch layout with coarse/fine pan and tilt and a roll register, over the
// wire: one request carries a fixture's channels; the changes are the
// 16-bit values over the luminaire's ranges (pan 630, tilt 265, roll 360).
TEST(ModbusTcpLayout, CoarseFineBytesAndRollBecomeAngles) {
  const Patch patch = LayoutPatch();
  const RegisterMap map = MapOf(patch);
  std::vector<uint16_t> initial(static_cast<size_t>(map.holding_count()), 0);
  FixtureState rest{};
  for (int f = 0; f < map.fixture_count(); ++f) {
    map.Encode(rest, f, &initial[static_cast<size_t>(map.fixture(f).modbus_base)]);
  }
  ModbusTcpConfig config;
  config.port = 0;
  ModbusTcpServer server(config, map, initial);
  ASSERT_TRUE(server.Start().ok());
  TcpClient c(server.port());
  ASSERT_TRUE(c.Connect());
  uint16_t back[10] = {};
  ASSERT_EQ(modbus_read_registers(c.ctx(), 0, 10, back), 10);
  EXPECT_EQ(back[1], 0x80);  // pan 0 degrees = 32768: coarse 0x80, fine 0
  EXPECT_EQ(back[2], 0);
  EXPECT_EQ(back[5], 32768);  // roll 0

  const uint16_t channels[5] = {0xC4, 0x27, 0x3F, 0xFF, 32768 - 4096};  // pan 0xC427, tilt 0x3FFF, roll -22.5
  ASSERT_EQ(modbus_write_registers(c.ctx(), 1, 5, channels), 5);
  std::vector<ParamChange> got(16);
  got.resize(server.Poll(0, got.data(), got.size()));
  ASSERT_EQ(got.size(), 3u);  // one change per angle, not one per byte
  EXPECT_EQ(got[0].param, Param::kPan);
  EXPECT_EQ(testing::Raw(got[0]), AngleQ16FromRegister(0xC427, 630 << 16));
  EXPECT_LE(std::fabs(testing::Raw(got[0]) / 65536.0 - (0xC427 - 32768.0) / 65536.0 * 630), 0.5 / 65536);
  EXPECT_EQ(got[1].param, Param::kTilt);
  EXPECT_LE(std::fabs(testing::Raw(got[1]) / 65536.0 - (0x3FFF - 32768.0) / 65536.0 * 265), 0.5 / 65536);
  EXPECT_EQ(got[2].param, Param::kRoll);
  EXPECT_EQ(testing::Raw(got[2]), -(22 << 16) - 32768);
  // A fine byte above 255 is refused whole; the fine byte alone moves the pan by one step.
  const uint16_t bad[2] = {0xC4, 0x100};
  EXPECT_EQ(modbus_write_registers(c.ctx(), 1, 2, bad), -1);
  EXPECT_EQ(errno, EMBXILVAL);
  const uint16_t fine = 0x28;
  ASSERT_EQ(modbus_write_register(c.ctx(), 2, fine), 1);
  got.assign(16, ParamChange());
  got.resize(server.Poll(0, got.data(), got.size()));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(testing::Raw(got[0]), AngleQ16FromRegister(0xC428, 630 << 16));
  EXPECT_EQ(server.counters().illegal_value, 1u);
}

TEST_F(ModbusTcp, MbpollAsAnIndependentClient) {
  if (!testing::HaveTool("mbpoll")) GTEST_SKIP() << "mbpoll not installed (Debian package mbpoll)";
  const std::string port = std::to_string(server_->port());
  std::string out;
  // -0: PDU (0-based) addresses; write holding register 9 (wash pan).
  ASSERT_EQ(testing::Run("mbpoll -m tcp -p " + port + " -0 -t 4 -r 9 -1 127.0.0.1 12345", &out), 0) << out;
  EXPECT_EQ(server_->holding_registers()[9], 12345);
  // mbpoll's default 1-based references: 4 = PDU 3 (red).
  ASSERT_EQ(testing::Run("mbpoll -m tcp -p " + port + " -t 4 -r 4 -1 127.0.0.1 200", &out), 0) << out;
  EXPECT_EQ(server_->holding_registers()[3], 200);
  ASSERT_EQ(testing::Run("mbpoll -m tcp -p " + port + " -0 -t 4 -r 8 -c 8 -1 127.0.0.1", &out), 0) << out;
  EXPECT_NE(out.find("[9]: \t12345"), std::string::npos) << out;
  // An illegal value: mbpoll reports the exception, the state is untouched.
  EXPECT_NE(testing::Run("mbpoll -m tcp -p " + port + " -0 -t 4 -r 3 -1 127.0.0.1 300", &out), 0);
  EXPECT_NE(out.find("Illegal data value"), std::string::npos) << out;
  EXPECT_EQ(server_->holding_registers()[3], 200);
  const std::vector<ParamChange> got = Drain();
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].param, Param::kRed);
  EXPECT_EQ(got[1].param, Param::kPan);
}

}  // namespace
}  // namespace relight::hal
