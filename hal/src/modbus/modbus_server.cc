#include "relight/hal/modbus_server.h"

#include "register_bank.h"

namespace relight::hal {

ModbusServer::ModbusServer(const RegisterMap& map, std::vector<uint16_t> initial)
    : bank_(std::make_unique<RegisterBank>(map, std::move(initial))) {}

// The derived server has stopped its thread by now (its destructor runs first).
ModbusServer::~ModbusServer() = default;

ModbusServerCounters ModbusServer::counters() const { return bank_->counters(); }
std::vector<uint16_t> ModbusServer::holding_registers() const { return bank_->input().Snapshot(); }

size_t ModbusServer::DoPoll(int64_t /*now_us*/, ParamChange* out, size_t capacity) {
  return bank_->input().Collect(out, capacity);
}

void ModbusServer::DoOnFrameOut(uint32_t frame, uint32_t latency_us) { bank_->PublishFrame(frame, latency_us); }

}  // namespace relight::hal
