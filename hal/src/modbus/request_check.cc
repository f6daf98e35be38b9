#include "request_check.h"

namespace relight::hal {
namespace {

int Word(const uint8_t* p) { return (p[0] << 8) | p[1]; }

PduCheck Exception(uint8_t code) {
  PduCheck c;
  c.verdict = PduVerdict::kException;
  c.exception = code;
  return c;
}

PduCheck Malformed() {
  PduCheck c;
  c.verdict = PduVerdict::kMalformed;
  return c;
}

// A read of `count` registers from `addr` in a table of `size`.
PduCheck CheckRead(int addr, int count, int size, int max_count) {
  if (count < 1 || count > max_count) return Exception(kExceptionIllegalValue);
  if (addr + count > size) return Exception(kExceptionIllegalAddress);
  return PduCheck();
}

// Values (big-endian words at `data`) written from `addr`.
PduCheck CheckWrites(int addr, int count, const uint8_t* data, const RegisterMap& map) {
  if (addr + count > map.holding_count()) return Exception(kExceptionIllegalAddress);
  // Address errors before value errors, as a device checks the range first.
  for (int i = 0; i < count; ++i) {
    int offset = 0;
    if (map.FixtureAt(addr + i, &offset) < 0) return Exception(kExceptionIllegalAddress);
  }
  for (int i = 0; i < count; ++i) {
    if (const uint8_t e = map.CheckWrite(addr + i, static_cast<uint16_t>(Word(data + 2 * i))); e != 0) {
      return Exception(e);
    }
  }
  PduCheck c;
  c.write_addr = addr;
  c.write_count = count;
  for (int i = 0; i < count; ++i) c.write_values[i] = static_cast<uint16_t>(Word(data + 2 * i));
  return c;
}

}  // namespace

PduCheck CheckPdu(const uint8_t* pdu, int pdu_len, const RegisterMap& map, const uint16_t* holding) {
  if (pdu_len < 1) return Malformed();
  const uint8_t function = pdu[0];
  switch (function) {
    case 0x01:  // read coils
    case 0x02:  // read discrete inputs
    case 0x05:  // write single coil
      if (pdu_len != 5) return Malformed();
      return Exception(kExceptionIllegalAddress);  // no coils or discrete inputs in this map
    case 0x0F:  // write multiple coils
      if (pdu_len < 6 || pdu_len != 6 + pdu[5]) return Malformed();
      return Exception(kExceptionIllegalAddress);
    case 0x03:  // read holding registers
      if (pdu_len != 5) return Malformed();
      return CheckRead(Word(pdu + 1), Word(pdu + 3), map.holding_count(), 125);
    case 0x04:  // read input registers (status)
      if (pdu_len != 5) return Malformed();
      return CheckRead(Word(pdu + 1), Word(pdu + 3), kStatusRegisterCount, 125);
    case 0x06:  // write single register
      if (pdu_len != 5) return Malformed();
      return CheckWrites(Word(pdu + 1), 1, pdu + 3, map);
    case 0x10: {  // write multiple registers
      if (pdu_len < 6 || pdu_len != 6 + pdu[5]) return Malformed();
      const int count = Word(pdu + 3);
      if (count < 1 || count > 123 || pdu[5] != 2 * count) return Exception(kExceptionIllegalValue);
      return CheckWrites(Word(pdu + 1), count, pdu + 6, map);
    }
    case 0x16: {  // mask write register: result = (current AND and) OR (or AND NOT and)
      if (pdu_len != 7) return Malformed();
      const int addr = Word(pdu + 1);
      int offset = 0;
      if (map.FixtureAt(addr, &offset) < 0) return Exception(kExceptionIllegalAddress);
      const int and_mask = Word(pdu + 3), or_mask = Word(pdu + 5);
      const int result = (holding[addr] & and_mask) | (or_mask & ~and_mask & 0xFFFF);
      const uint8_t word[2] = {static_cast<uint8_t>(result >> 8), static_cast<uint8_t>(result & 0xFF)};
      return CheckWrites(addr, 1, word, map);
    }
    case 0x17: {  // read/write multiple registers: the write happens first
      if (pdu_len < 10 || pdu_len != 10 + pdu[9]) return Malformed();
      const int write_count = Word(pdu + 7);
      if (write_count < 1 || write_count > 121 || pdu[9] != 2 * write_count) return Exception(kExceptionIllegalValue);
      const PduCheck read = CheckRead(Word(pdu + 1), Word(pdu + 3), map.holding_count(), 125);
      if (read.verdict != PduVerdict::kReply) return read;
      return CheckWrites(Word(pdu + 5), write_count, pdu + 10, map);
    }
    case 0x11:  // report server ID
      if (pdu_len != 1) return Malformed();
      return PduCheck();
    default:
      return Exception(kExceptionIllegalFunction);
  }
}

}  // namespace relight::hal
