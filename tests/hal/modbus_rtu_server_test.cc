// The Modbus RTU server over a pseudo-terminal pair made by socat: libmodbus
// (RTU) and mbpoll as clients on the other end, garbage on the line.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "hal_test_support.h"
#include "modbus_test_client.h"
#include "relight/hal/modbus_rtu_server.h"

extern char** environ;

namespace relight::hal {
namespace {

using testing::MapOf;
using testing::RestRegisters;
using testing::TwoFixturePatch;

// socat -d -d pty,raw,echo=0,link=A pty,raw,echo=0,link=B, for one test.
class PtyPair {
 public:
  PtyPair() {
    const std::string dir = ::testing::TempDir() + "/rtu_" + std::to_string(getpid()) + "_" +
                            ::testing::UnitTest::GetInstance()->current_test_info()->name();
    mkdir(dir.c_str(), 0700);
    a_ = dir + "/ttyA";
    b_ = dir + "/ttyB";
    unlink(a_.c_str());
    unlink(b_.c_str());
    std::string a_arg = "pty,raw,echo=0,link=" + a_, b_arg = "pty,raw,echo=0,link=" + b_;
    std::string prog = "socat";
    std::vector<char*> argv = {prog.data(), a_arg.data(), b_arg.data(), nullptr};
    if (posix_spawnp(&pid_, "socat", nullptr, nullptr, argv.data(), environ) != 0) pid_ = -1;
    for (int i = 0; i < 500 && pid_ > 0; ++i) {
      struct stat st {};
      if (stat(a_.c_str(), &st) == 0 && stat(b_.c_str(), &st) == 0) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "socat made no pty pair";
  }
  ~PtyPair() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      waitpid(pid_, nullptr, 0);
    }
  }
  const std::string& server_end() const { return a_; }
  const std::string& client_end() const { return b_; }

 private:
  pid_t pid_ = -1;
  std::string a_, b_;
};

// Modbus RTU CRC-16 (polynomial 0xA001 reflected, initial 0xFFFF).
uint16_t Crc16(const uint8_t* data, size_t n) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < n; ++i) {
    crc ^= data[i];
    for (int b = 0; b < 8; ++b) crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : static_cast<uint16_t>(crc >> 1);
  }
  return crc;
}

class ModbusRtu : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!testing::HaveTool("socat")) GTEST_SKIP() << "socat not installed (Debian package socat)";
    pty_ = std::make_unique<PtyPair>();
    ModbusRtuConfig config;
    config.enabled = true;
    config.device = pty_->server_end();
    config.baud = 19200;
    config.unit_id = 5;
    server_ = std::make_unique<ModbusRtuServer>(config, map_, RestRegisters(map_));
    const Status st = server_->Start();
    ASSERT_TRUE(st.ok()) << st.ToString();
    client_ = modbus_new_rtu(pty_->client_end().c_str(), 19200, 'N', 8, 1);
    ASSERT_NE(client_, nullptr);
    modbus_set_slave(client_, 5);
    modbus_set_response_timeout(client_, 2, 0);
    ASSERT_EQ(modbus_connect(client_), 0) << modbus_strerror(errno);
  }
  void TearDown() override {
    if (client_ != nullptr) {
      modbus_close(client_);
      modbus_free(client_);
    }
    server_.reset();
    pty_.reset();
  }

  Patch patch_ = TwoFixturePatch();
  RegisterMap map_ = MapOf(patch_);
  std::unique_ptr<PtyPair> pty_;
  std::unique_ptr<ModbusRtuServer> server_;
  modbus_t* client_ = nullptr;
};

TEST_F(ModbusRtu, WritesReadsAndExceptionsOverTheSerialLine) {
  ASSERT_EQ(modbus_write_register(client_, 8 + kRegTilt, 0), 1) << modbus_strerror(errno);
  const uint16_t rgb[3] = {10, 20, 30};
  ASSERT_EQ(modbus_write_registers(client_, kRegRed, 3, rgb), 3);
  uint16_t back[16] = {};
  ASSERT_EQ(modbus_read_registers(client_, 0, 16, back), 16);
  EXPECT_EQ(back[kRegBlue], 30);
  EXPECT_EQ(back[8 + kRegTilt], 0);
  EXPECT_EQ(modbus_write_register(client_, kRegGreen, 300), -1);
  EXPECT_EQ(errno, EMBXILVAL);
  EXPECT_EQ(modbus_read_registers(client_, 16, 1, back), -1);
  EXPECT_EQ(errno, EMBXILADD);
  server_->OnFrameOut(77, 0);
  uint16_t status[2] = {};
  ASSERT_EQ(modbus_read_input_registers(client_, kStatusFrameHigh, 2, status), 2);
  EXPECT_EQ(status[1], 77);
  ParamChange out[16];
  const size_t n = server_->Poll(0, out, 16);
  ASSERT_EQ(n, 4u);
  EXPECT_EQ(out[0].param, Param::kRed);
  EXPECT_EQ(out[3].param, Param::kTilt);
  EXPECT_EQ(out[3].fixture, testing::FixtureIndexOf("wash"));
  EXPECT_EQ(testing::Raw(out[3]), -(90 << 16));
  EXPECT_EQ(server_->counters().illegal_value, 1u);
  EXPECT_EQ(server_->counters().illegal_address, 1u);
}

TEST_F(ModbusRtu, GarbageOnTheLineIsDroppedAndTheNextRequestAnswered) {
  const int fd = modbus_get_socket(client_);
  const uint8_t garbage[] = {0x05, 0x03, 0xFF, 0x00, 0x12, 0x99, 0x42, 0x00, 0x13, 0x37, 0xAA, 0x55};
  ASSERT_EQ(write(fd, garbage, sizeof garbage), static_cast<ssize_t>(sizeof garbage));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // longer than the server's byte timeout
  tcflush(fd, TCIFLUSH);  // whatever the garbage provoked
  ASSERT_EQ(modbus_write_register(client_, kRegDimmer, 4242), 1) << modbus_strerror(errno);
  EXPECT_EQ(server_->holding_registers()[kRegDimmer], 4242);
  EXPECT_GE(server_->counters().bad_frames, 1u);
  // A request for another unit on the bus is not answered; that unit's answer
  // (played here by the test) is skipped, and the next request for us is served.
  modbus_set_slave(client_, 9);
  modbus_set_response_timeout(client_, 0, 200000);
  uint16_t v = 0;
  EXPECT_EQ(modbus_read_registers(client_, 0, 1, &v), -1);
  uint8_t other_answer[7] = {9, 0x03, 2, 0x12, 0x34, 0, 0};
  const uint16_t crc = Crc16(other_answer, 5);
  other_answer[5] = static_cast<uint8_t>(crc & 0xFF);  // CRC goes low byte first
  other_answer[6] = static_cast<uint8_t>(crc >> 8);
  ASSERT_EQ(write(fd, other_answer, sizeof other_answer), static_cast<ssize_t>(sizeof other_answer));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  modbus_flush(client_);
  modbus_set_slave(client_, 5);
  modbus_set_response_timeout(client_, 2, 0);
  ASSERT_EQ(modbus_read_registers(client_, 0, 1, &v), 1) << modbus_strerror(errno);
  EXPECT_EQ(v, 4242);
}

TEST_F(ModbusRtu, MbpollOverRtu) {
  if (!testing::HaveTool("mbpoll")) GTEST_SKIP() << "mbpoll not installed (Debian package mbpoll)";
  // Hand the line to mbpoll: close our client end first.
  modbus_close(client_);
  modbus_free(client_);
  client_ = nullptr;
  std::string out;
  const std::string line = " -m rtu -a 5 -b 19200 -P none -0 -t 4 -1 " + pty_->client_end();
  ASSERT_EQ(testing::Run("mbpoll" + line + " -r 9 -- 50000", &out), 0) << out;  // "-r 9" after -0: PDU 9
  EXPECT_EQ(server_->holding_registers()[9], 50000);
  ASSERT_EQ(testing::Run("mbpoll" + line + " -r 8 -c 3", &out), 0) << out;
  EXPECT_NE(out.find("[9]: \t50000"), std::string::npos) << out;
}

}  // namespace
}  // namespace relight::hal
