// What the Modbus TCP and RTU servers share as input sources: the register
// bank their server thread answers from and the daemon polls, its counters
// (also served as status input registers, register_map.h kStatus*) and the
// frame status the daemon publishes. A server adds its transport: DoStart,
// DoStop and the thread that feeds requests to the bank.
//
// Thread safety: Poll from the daemon's thread; counters(),
// holding_registers() and OnFrameOut() from any.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "relight/hal/input_source.h"
#include "relight/hal/register_map.h"

namespace relight::hal {

struct ModbusServerCounters {
  uint32_t illegal_address = 0;   // exceptions 0x02 sent
  uint32_t illegal_value = 0;     // exceptions 0x03 sent
  uint32_t illegal_function = 0;  // exceptions 0x01 sent
  uint32_t bad_frames = 0;        // malformed or garbled frames dropped
  uint32_t refused = 0;           // connections refused (allow-list, client limit)
  uint32_t clients = 0;           // TCP clients connected now
};

class RegisterBank;  // src/modbus/register_bank.h

class ModbusServer : public InputSource {
 public:
  ~ModbusServer() override;

  ModbusServerCounters counters() const;
  std::vector<uint16_t> holding_registers() const;

 protected:
  // `initial`: the holding registers' starting values (map.holding_count()),
  // e.g. RegisterMap::Encode of the engine's state; zeros if empty.
  ModbusServer(const RegisterMap& map, std::vector<uint16_t> initial);
  RegisterBank& bank() { return *bank_; }

 private:
  size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) final;
  void DoOnFrameOut(uint32_t frame, uint32_t latency_us) final;

  std::unique_ptr<RegisterBank> bank_;
};

}  // namespace relight::hal
