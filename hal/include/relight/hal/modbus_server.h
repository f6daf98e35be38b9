// Counters the Modbus servers keep (also served as status input registers,
// register_map.h kStatus*).
#pragma once

#include <cstdint>

namespace relight::hal {

struct ModbusServerCounters {
  uint32_t illegal_address = 0;   // exceptions 0x02 sent
  uint32_t illegal_value = 0;     // exceptions 0x03 sent
  uint32_t illegal_function = 0;  // exceptions 0x01 sent
  uint32_t bad_frames = 0;        // malformed or garbled frames dropped
  uint32_t refused = 0;           // connections refused (allow-list, client limit)
  uint32_t clients = 0;           // TCP clients connected now
};

}  // namespace relight::hal
