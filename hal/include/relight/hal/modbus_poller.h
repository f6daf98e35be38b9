// Modbus client poller backend: reads a dimmer rack's or PLC's holding
// registers at a set rate (patch [modbus_poller]) and turns the mapped ones
// into parameter changes. When the peer vanishes it keeps the last state,
// logs once, and reconnects with a doubling backoff; it logs once more when
// the peer is back.
//
// Thread safety: Start/Poll/Stop from one thread; the rest from any.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "relight/hal/input_source.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {

struct ModbusPollerCounters {
  uint32_t reads_ok = 0;
  uint32_t reads_failed = 0;
  uint32_t connects = 0;     // successful connections, the first included
  bool connected = false;
};

class ModbusPoller final : public InputSource {
 public:
  // `map` is our own register map: each polled register lands on its
  // fixture parameter's register there; `initial` as for the servers.
  ModbusPoller(ModbusPollerConfig config, const RegisterMap& map, std::vector<uint16_t> initial);
  ~ModbusPoller() override;

  ModbusPollerCounters counters() const;

 private:
  // Start never fails for an absent peer (it may come later): only for a
  // map entry naming an unknown fixture (kNotFound).
  Status DoStart() override;
  size_t DoPoll(int64_t now_us, ParamChange* out, size_t capacity) override;
  const char* DoName() const override { return "modbus-poller"; }
  void DoStop() override;

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relight::hal
