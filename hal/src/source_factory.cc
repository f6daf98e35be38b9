#include "relight/hal/source_factory.h"

#include "relight/hal/gpiod_source.h"
#include "relight/hal/modbus_poller.h"
#include "relight/hal/modbus_rtu_server.h"
#include "relight/hal/modbus_tcp_server.h"
#include "relight/hal/replay_source.h"

namespace relight::hal {

Status MakeInputSources(const Patch& patch, const RegisterMap& map, const std::vector<uint16_t>& initial,
                        const std::string& replay_script, std::vector<std::unique_ptr<InputSource>>* out) {
  std::vector<std::unique_ptr<InputSource>> sources;
  if (patch.modbus_tcp.enabled) sources.push_back(std::make_unique<ModbusTcpServer>(patch.modbus_tcp, map, initial));
  if (patch.modbus_rtu.enabled) sources.push_back(std::make_unique<ModbusRtuServer>(patch.modbus_rtu, map, initial));
  if (patch.modbus_poller.enabled) {
    sources.push_back(std::make_unique<ModbusPoller>(patch.modbus_poller, map, initial));
  }
  if (!patch.buttons.empty() || !patch.encoders.empty()) sources.push_back(std::make_unique<GpiodSource>(patch));
  const std::string script = replay_script.empty() ? patch.replay_script : replay_script;
  if (!script.empty()) {
    // Its changes index the patch's fixtures, as every other source here.
    std::vector<std::string> names;
    for (const FixturePatch& f : patch.fixtures) names.push_back(f.name);
    sources.push_back(std::make_unique<ReplaySource>(script, std::move(names)));
  }
  *out = std::move(sources);
  return Status::Ok();
}

}  // namespace relight::hal
