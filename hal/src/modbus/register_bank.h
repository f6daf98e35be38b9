// What the Modbus TCP and RTU servers share: the libmodbus mapping they
// answer from, the checks before each answer, the status registers and
// counters, and the RegisterInput the daemon polls.
//
// Thread safety: HandleRequest() and the mapping belong to the server's
// thread; Collect(), Snapshot(), counters and PublishFrame() may be called
// from any thread.
#pragma once

#include <modbus/modbus.h>

#include <atomic>
#include <cstdint>
#include <vector>

#include "../register_input.h"
#include "relight/hal/modbus_server.h"
#include "relight/hal/register_map.h"
#include "relight/base/status.h"

namespace relight::hal {

class RegisterBank {
 public:
  RegisterBank(const RegisterMap& map, std::vector<uint16_t> initial);
  ~RegisterBank();
  RegisterBank(const RegisterBank&) = delete;
  RegisterBank& operator=(const RegisterBank&) = delete;

  Status Init();  // allocates the libmodbus mapping (kInternal if it cannot)

  // Answers one request. `req` holds the whole ADU (header + PDU [+ CRC])
  // and must have at least MODBUS_MAX_ADU_LENGTH readable bytes (padded by the
  // caller); `checksum_len` is 2 for RTU, 0 for TCP. Returns false when the
  // request is malformed or the answer could not be sent (TCP: close it).
  bool HandleRequest(modbus_t* ctx, const uint8_t* req, int req_len, int checksum_len, int64_t arrival_us);

  RegisterInput& input() { return input_; }
  ModbusServerCounters counters() const;
  std::atomic<uint32_t>& bad_frames() { return bad_frames_; }
  std::atomic<uint32_t>& refused() { return refused_; }
  std::atomic<uint32_t>& clients() { return clients_; }
  void PublishFrame(uint32_t frame, uint32_t latency_us) {
    frame_.store(frame, std::memory_order_relaxed);
    latency_us_.store(latency_us, std::memory_order_relaxed);
  }

 private:
  void RefreshStatus();

  RegisterInput input_;
  modbus_mapping_t* mapping_ = nullptr;
  std::vector<uint16_t> initial_;
  std::atomic<uint32_t> frame_{0}, latency_us_{0};
  std::atomic<uint32_t> illegal_address_{0}, illegal_value_{0}, illegal_function_{0}, bad_frames_{0},
      refused_{0}, clients_{0};
};

}  // namespace relight::hal
