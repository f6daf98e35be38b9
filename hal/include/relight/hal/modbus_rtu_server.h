// Modbus RTU server backend: the same register map (register_map.h) over a
// serial line (RS-232/RS-485 adapter, or a pseudo-terminal in tests).
// Its own thread and libmodbus context; garbage or CRC errors on the line
// are counted and flushed, and the next good request is answered.
//
// Thread safety: Start/Poll/Stop from one thread; counters() and
// OnFrameOut() from any.
#pragma once

#include <memory>
#include <vector>

#include "relight/hal/modbus_server.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {

class ModbusRtuServer final : public ModbusServer {
 public:
  // `initial` as for ModbusServer.
  ModbusRtuServer(ModbusRtuConfig config, const RegisterMap& map, std::vector<uint16_t> initial);
  ~ModbusRtuServer() override;

 private:
  // Start: kNotFound / kIoError naming the device if it cannot be opened.
  Status DoStart() override;
  const char* DoName() const override { return "modbus-rtu"; }
  void DoStop() override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::hal
