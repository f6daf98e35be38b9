// Modbus TCP server backend: a console, a wall panel or a PLC writes the
// holding registers of register_map.h; the daemon polls the changes.
//
// One thread with its own libmodbus context serves every client through
// poll() (libmodbus contexts are not thread-safe; no thread per client).
// Frames are cut from each client's bounded buffer by their MBAP length, so
// a client that sends half a request or nothing at all never holds up the
// others; malformed frames close that client only. Listens on 127.0.0.1
// unless configured otherwise; an allow-list refuses other peers.
//
// Thread safety: Start/Poll/Stop from one thread; counters(), port(),
// holding_registers() and OnFrameOut() from any.
#pragma once

#include <memory>
#include <vector>

#include "relight/hal/modbus_server.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {

class ModbusTcpServer final : public ModbusServer {
 public:
  // `initial` as for ModbusServer.
  ModbusTcpServer(ModbusTcpConfig config, const RegisterMap& map, std::vector<uint16_t> initial);
  ~ModbusTcpServer() override;

  int port() const;  // the port listened on, after Start() (config port 0 = any free one)

 private:
  // Start: kIoError naming the address if it cannot listen.
  Status DoStart() override;
  const char* DoName() const override { return "modbus-tcp"; }
  void DoStop() override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::hal
