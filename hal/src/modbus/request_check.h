// Checks a Modbus request PDU against the register map before libmodbus
// answers it: the PDU length must match what its function code implies
// (libmodbus's modbus_reply trusts the caller on that), every written value
// must be legal for its register (RegisterMap::CheckWrite), every address
// must be mapped. Pure function: no I/O, no libmodbus.
#pragma once

#include <cstdint>

#include "relight/hal/register_map.h"

namespace relight::hal {

enum class PduVerdict : uint8_t {
  kReply,      // well-formed and legal: let modbus_reply answer it
  kException,  // answer with exception `exception`
  kMalformed,  // length does not match the function: drop (TCP: close the connection)
};

struct PduCheck {
  PduVerdict verdict = PduVerdict::kReply;
  uint8_t exception = 0;
  // For kReply on a write: the holding registers it changes, and to what.
  int write_addr = 0, write_count = 0;
  uint16_t write_values[123] = {};
};

// pdu: function code first; pdu_len bytes (no MBAP header, no CRC).
// holding: the current holding registers (for mask-write's result).
PduCheck CheckPdu(const uint8_t* pdu, int pdu_len, const RegisterMap& map, const uint16_t* holding);

}  // namespace relight::hal
