#include "register_bank.h"

#include "relight/base/log.h"
#include "request_check.h"

namespace relight::hal {

RegisterBank::RegisterBank(const RegisterMap& map, std::vector<uint16_t> initial)
    : input_(map, initial), initial_(std::move(initial)) {
  initial_.resize(static_cast<size_t>(map.holding_count()), 0);
}

RegisterBank::~RegisterBank() {
  if (mapping_ != nullptr) modbus_mapping_free(mapping_);
}

Status RegisterBank::Init() {
  if (mapping_ != nullptr) return Status::Ok();
  // No coils or discrete inputs: requests for them get exception 0x02.
  mapping_ = modbus_mapping_new_start_address(0, 0, 0, 0, 0, input_.map().holding_count(), 0, kStatusRegisterCount);
  if (mapping_ == nullptr) return Status(StatusCode::kInternal, "modbus: cannot allocate the register mapping");
  const std::vector<uint16_t> now = input_.Snapshot();
  for (size_t i = 0; i < now.size(); ++i) mapping_->tab_registers[i] = now[i];
  RefreshStatus();
  return Status::Ok();
}

void RegisterBank::RefreshStatus() {
  uint16_t* r = mapping_->tab_input_registers;
  const uint32_t frame = frame_.load(std::memory_order_relaxed);
  const uint32_t latency = latency_us_.load(std::memory_order_relaxed);
  r[kStatusFrameHigh] = static_cast<uint16_t>(frame >> 16);
  r[kStatusFrameLow] = static_cast<uint16_t>(frame & 0xFFFF);
  r[kStatusLatencyHigh] = static_cast<uint16_t>(latency >> 16);
  r[kStatusLatencyLow] = static_cast<uint16_t>(latency & 0xFFFF);
  r[kStatusIllegalAddress] = static_cast<uint16_t>(illegal_address_.load());
  r[kStatusIllegalValue] = static_cast<uint16_t>(illegal_value_.load());
  r[kStatusBadFrames] = static_cast<uint16_t>(bad_frames_.load());
  r[kStatusRefused] = static_cast<uint16_t>(refused_.load());
  r[kStatusClients] = static_cast<uint16_t>(clients_.load());
  r[kStatusFixtures] = static_cast<uint16_t>(input_.map().fixture_count());
}

bool RegisterBank::HandleRequest(modbus_t* ctx, const uint8_t* req, int req_len, int checksum_len,
                                 int64_t arrival_us) {
  const int header = modbus_get_header_length(ctx);
  const int pdu_len = req_len - header - checksum_len;
  const PduCheck check = CheckPdu(req + header, pdu_len, input_.map(), mapping_->tab_registers);
  if (check.verdict == PduVerdict::kMalformed) {
    bad_frames_.fetch_add(1);
    return false;
  }
  if (check.verdict == PduVerdict::kException) {
    (check.exception == kExceptionIllegalAddress  ? illegal_address_
     : check.exception == kExceptionIllegalValue ? illegal_value_
                                                  : illegal_function_)
        .fetch_add(1);
    return modbus_reply_exception(ctx, req, check.exception) >= 0;
  }
  RefreshStatus();
  // Hand the write to the daemon before the answer goes out, so a client
  // that has its answer knows the next frame will show it. modbus_reply
  // then writes the same values into its mapping.
  if (check.write_count > 0) input_.Write(check.write_addr, check.write_count, check.write_values, arrival_us);
  return modbus_reply(ctx, req, req_len, mapping_) >= 0;
}

ModbusServerCounters RegisterBank::counters() const {
  ModbusServerCounters c;
  c.illegal_address = illegal_address_.load();
  c.illegal_value = illegal_value_.load();
  c.illegal_function = illegal_function_.load();
  c.bad_frames = bad_frames_.load();
  c.refused = refused_.load();
  c.clients = clients_.load();
  return c;
}

}  // namespace relight::hal
